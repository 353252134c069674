# Cross-compiles slicecap for aarch64 (Raspberry Pi 4/5, Debian 12 / Raspberry Pi OS bookworm) with
# Debian's g++-aarch64-linux-gnu against an arm64 sysroot (scripts/arm64-sysroot makes one), and runs
# the built programs (tests, gtest discovery, try_run) under qemu-aarch64-static, which needs no binfmt
# registration. scripts/arm64-check uses it; by hand:
#   cmake -S . -B build-arm64 -G Ninja -DSLICECAP_SYSROOT=DIR \
#         -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake
# SLICECAP_SYSROOT may also come from the environment. SLICECAP_QEMU_CPU (default cortex-a72, the Pi 4's
# core) is the CPU qemu emulates, so that code and library paths needing a newer core fail here too.

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

if(NOT SLICECAP_SYSROOT AND DEFINED ENV{SLICECAP_SYSROOT})
  set(SLICECAP_SYSROOT "$ENV{SLICECAP_SYSROOT}")
endif()
if(NOT SLICECAP_SYSROOT OR NOT EXISTS "${SLICECAP_SYSROOT}/usr/lib/aarch64-linux-gnu")
  message(FATAL_ERROR "aarch64 toolchain: SLICECAP_SYSROOT='${SLICECAP_SYSROOT}' is not an arm64 sysroot "
                      "(make one with scripts/arm64-sysroot and pass -DSLICECAP_SYSROOT=DIR)")
endif()
if(NOT SLICECAP_QEMU_CPU)
  set(SLICECAP_QEMU_CPU cortex-a72)
endif()
# try_compile projects read this file again: hand them the same values.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES SLICECAP_SYSROOT SLICECAP_QEMU_CPU)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_SYSROOT "${SLICECAP_SYSROOT}")

# Headers, libraries and CMake packages from the sysroot only; programs (pkg-config, protoc) from the host.
set(CMAKE_FIND_ROOT_PATH "${SLICECAP_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${SLICECAP_SYSROOT}")
set(ENV{PKG_CONFIG_LIBDIR} "${SLICECAP_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${SLICECAP_SYSROOT}/usr/share/pkgconfig")

# The linker resolves the libraries' own dependencies (glog, BLAS, ...) inside the sysroot too.
set(_slicecap_rpath_link
    "-Wl,-rpath-link,${SLICECAP_SYSROOT}/usr/lib/aarch64-linux-gnu -Wl,-rpath-link,${SLICECAP_SYSROOT}/lib/aarch64-linux-gnu")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${_slicecap_rpath_link}")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "${_slicecap_rpath_link}")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "${_slicecap_rpath_link}")

find_program(SLICECAP_QEMU qemu-aarch64-static)
if(NOT SLICECAP_QEMU)
  message(FATAL_ERROR "aarch64 toolchain: qemu-aarch64-static not found (Debian package qemu-user-static)")
endif()
set(CMAKE_CROSSCOMPILING_EMULATOR "${SLICECAP_QEMU};-cpu;${SLICECAP_QEMU_CPU};-L;${SLICECAP_SYSROOT}")
