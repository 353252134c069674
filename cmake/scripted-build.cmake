# Initial cache of the project's scripted builds (scripts/build, scripts/arm64-check,
# scripts/response-curve: `cmake -C cmake/scripted-build.cmake`). The code is compiled at -O2, as
# RelWithDebInfo, so figures and benchmark timings do not change, but without debug information:
# -g made the compile of tests/btf/btf_texture_test.cpp 10.2 s instead of 7.3 s (one core, 2026-12-02)
# and its object 7.7 MB instead of 0.46 MB, which every test program's link then reads. The test command
# and CI build the whole tree twice (x86-64 and aarch64) on two cores. To debug, configure with
# -DCMAKE_BUILD_TYPE=RelWithDebInfo after this file (scripts/build passes its arguments on to cmake).
set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
set(CMAKE_CXX_FLAGS_RELEASE "-O2 -DNDEBUG" CACHE STRING "Release: -O2 as RelWithDebInfo, without -g" FORCE)
# Compiled through ccache when it is installed (scripts/deps/host.txt): scripts/offline-build-check
# builds a second configuration of the same tree right after, and its unchanged translation units
# (every one but the few that know the SLICECAP_WITH_* options) are then cache hits.
# CCACHE_BASEDIR is the source tree: ccache hashes the paths under it relative to the build folder,
# so build/ and build-offline/ (whose generated-header folders differ) share their entries.
# CCACHE_DEPEND: a miss takes its includes from the compiler's -MD file instead of running the
# preprocessor first, so an empty cache (a fresh CI machine) costs no more than no ccache: 36 s vs
# 41 s without ccache for core and recon on 2 loaded cores, 44 s vs 35 s without depend mode
# (docs/results/2026-12-02-offline-build.md).
find_program(SLICECAP_CCACHE ccache)
if(SLICECAP_CCACHE)
  get_filename_component(slicecap_tree "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
  set(CMAKE_CXX_COMPILER_LAUNCHER "/usr/bin/env;CCACHE_BASEDIR=${slicecap_tree};CCACHE_DEPEND=1;${SLICECAP_CCACHE}"
      CACHE STRING "Compiler launcher (ccache)")
endif()
