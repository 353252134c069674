# Install rules and the Debian package (cpack -G DEB; scripts/package drives it). What the package holds
# is whatever the tree has when it is configured:
#   /usr/bin/slicecap, /usr/bin/slicecapd        the programs, where those targets exist
#   /usr/share/man/man1/<program>.1.gz           from each program's --help (and each subcommand's)
#   /lib/systemd/system/                         systemd/*.service|socket|timer|path  (these four
#   /usr/lib/sysusers.d/slicecap.conf            systemd/*.sysusers: user and group    only once
#   /usr/lib/tmpfiles.d/slicecap.conf            systemd/*.tmpfiles                    slicecapd exists;
#   /lib/udev/rules.d/                           systemd/*.rules                       postinst applies them)
#   /etc/slicecap/slicecapd.conf                 `slicecapd --print-config`, when slicecapd exists
#   /etc/slicecap/                               files given to slicecap_install_config() (conffiles)
#   /usr/share/slicecap/                         files given to slicecap_install_data() (e.g. a prior)
#   /usr/share/slicecap/firmware/                firmware/* (config.txt fragment, overlay, wiring),
#                                                and each firmware/NAME-overlay.dts compiled to NAME.dtbo
#   /usr/share/doc/slicecap/                     README.md, copyright
# Runtime dependencies are not guessed here: scripts/deb-depends reads the shared libraries the installed
# programs link and names the Debian packages that ship them (in the sysroot for a cross build).

include(GNUInstallDirs)

set(SLICECAP_INSTALL_PROGRAMS slicecap slicecapd CACHE STRING "Program targets installed to bin, if they exist")
# Where data files (firmware, a learned prior) are installed and read from on the box; a package is
# configured with CMAKE_INSTALL_PREFIX=/usr (scripts/package sees to it), so this is /usr/share/slicecap.
set(SLICECAP_DATA_DIR "${CMAKE_INSTALL_FULL_DATADIR}/slicecap")
set(SLICECAP_CONFIG_DIR "/etc/slicecap" CACHE PATH "Where the default configuration is installed")

# slicecap_install_config(FILES ...): default configuration under /etc/slicecap, marked as conffiles so
# that an upgrade keeps the owner's edits.
function(slicecap_install_config)
  cmake_parse_arguments(ARG "" "" "FILES" ${ARGN})
  install(FILES ${ARG_FILES} DESTINATION "${SLICECAP_CONFIG_DIR}")
  foreach(f IN LISTS ARG_FILES)
    get_filename_component(name "${f}" NAME)
    set_property(GLOBAL APPEND PROPERTY SLICECAP_CONFFILES "${SLICECAP_CONFIG_DIR}/${name}")
  endforeach()
endfunction()

# slicecap_install_data(FILES ... [SUBDIR dir]): read-only data under /usr/share/slicecap[/dir].
function(slicecap_install_data)
  cmake_parse_arguments(ARG "" "SUBDIR" "FILES" ${ARGN})
  install(FILES ${ARG_FILES} DESTINATION "${CMAKE_INSTALL_DATADIR}/slicecap/${ARG_SUBDIR}")
endfunction()

# Called once at the end of the top-level CMakeLists.txt, after every target and install() exists.
function(slicecap_package)
  foreach(program IN LISTS SLICECAP_INSTALL_PROGRAMS)
    if(TARGET ${program})
      install(TARGETS ${program} RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
      slicecap_man_page(${program})
    endif()
  endforeach()
  if(TARGET slicecapd)
    _slicecap_default_config(slicecapd)
  endif()

  # The daemon's system files ship with the daemon: units naming a missing /usr/bin/slicecapd would be
  # enabled and started on install, and fail.
  if(TARGET slicecapd)
    file(GLOB units CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/systemd/*.service"
         "${PROJECT_SOURCE_DIR}/systemd/*.socket" "${PROJECT_SOURCE_DIR}/systemd/*.timer"
         "${PROJECT_SOURCE_DIR}/systemd/*.path")
    if(units)
      # Debian 12 keeps packaged units under /lib (lintian: systemd-service-file-outside-lib).
      install(FILES ${units} DESTINATION /lib/systemd/system)
    endif()
    foreach(kind sysusers tmpfiles)
      file(GLOB files CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/systemd/*.${kind}")
      foreach(f IN LISTS files)
        get_filename_component(stem "${f}" NAME_WE)
        install(FILES "${f}" DESTINATION "lib/${kind}.d" RENAME "${stem}.conf")
      endforeach()
    endforeach()
    file(GLOB rules CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/systemd/*.rules")
    if(rules)
      install(FILES ${rules} DESTINATION /lib/udev/rules.d)
    endif()
  endif()

  file(GLOB firmware CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/firmware/*")
  install(FILES ${firmware} DESTINATION "${CMAKE_INSTALL_DATADIR}/slicecap/firmware")
  _slicecap_overlays()
  install(FILES "${PROJECT_SOURCE_DIR}/README.md" "${PROJECT_SOURCE_DIR}/cmake/packaging/copyright"
          DESTINATION "${CMAKE_INSTALL_DOCDIR}")
  # A native package's changelog.gz (Debian policy 12.7); its date honours SOURCE_DATE_EPOCH.
  string(TIMESTAMP SLICECAP_CHANGELOG_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
  configure_file("${PROJECT_SOURCE_DIR}/cmake/packaging/changelog.in" "${CMAKE_BINARY_DIR}/packaging/changelog" @ONLY)
  add_custom_command(
    OUTPUT "${CMAKE_BINARY_DIR}/packaging/changelog.gz"
    COMMAND gzip -9nkf "${CMAKE_BINARY_DIR}/packaging/changelog"
    DEPENDS "${CMAKE_BINARY_DIR}/packaging/changelog"
    VERBATIM)
  add_custom_target(slicecap_changelog ALL DEPENDS "${CMAKE_BINARY_DIR}/packaging/changelog.gz")
  install(FILES "${CMAKE_BINARY_DIR}/packaging/changelog.gz" DESTINATION "${CMAKE_INSTALL_DOCDIR}")

  _slicecap_cpack_deb()
endfunction()

# slicecap_man_page(program): a man page made from `program --help` and `program COMMAND --help` for
# each command listed under "commands:" (run under the emulator when cross-compiling).
function(slicecap_man_page program)
  set(page "${CMAKE_BINARY_DIR}/man/${program}.1.gz")
  # Ninja makes an output's folder; the Makefile generator does not.
  file(MAKE_DIRECTORY "${CMAKE_BINARY_DIR}/man")
  add_custom_command(
    OUTPUT "${page}"
    COMMAND "${PROJECT_SOURCE_DIR}/cmake/packaging/help-to-man" "${page}" "${PROJECT_VERSION}"
            ${CMAKE_CROSSCOMPILING_EMULATOR} "$<TARGET_FILE:${program}>"
    DEPENDS ${program} "${PROJECT_SOURCE_DIR}/cmake/packaging/help-to-man"
    COMMENT "Man page of ${program} from its --help"
    VERBATIM)
  add_custom_target(${program}_man ALL DEPENDS "${page}")
  install(FILES "${page}" DESTINATION "${CMAKE_INSTALL_MANDIR}/man1")
endfunction()

# The daemon's documented default configuration, /etc/slicecap/PROGRAM.conf, is what `PROGRAM
# --print-config` writes (daemon/config.hpp): generated at build time so that it cannot drift from the code.
function(_slicecap_default_config program)
  set(conf "${CMAKE_BINARY_DIR}/packaging/${program}.conf")
  add_custom_command(
    OUTPUT "${conf}"
    COMMAND ${CMAKE_CROSSCOMPILING_EMULATOR} "$<TARGET_FILE:${program}>" --print-config > "${conf}.tmp"
    COMMAND "${CMAKE_COMMAND}" -E rename "${conf}.tmp" "${conf}"
    DEPENDS ${program}
    COMMENT "Default configuration of ${program} from its --print-config")
  add_custom_target(${program}_conf ALL DEPENDS "${conf}")
  slicecap_install_config(FILES "${conf}")
endfunction()

# Each firmware/NAME-overlay.dts is also shipped compiled, as firmware/NAME.dtbo (the name
# /boot/firmware/overlays/ and config.txt use; firmware/README.md), so the box needs no dtc.
function(_slicecap_overlays)
  file(GLOB sources CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/firmware/*.dts")
  if(NOT sources)
    return()
  endif()
  find_program(SLICECAP_DTC dtc REQUIRED)
  file(MAKE_DIRECTORY "${CMAKE_BINARY_DIR}/firmware")  # as for the man pages
  set(blobs)
  foreach(dts IN LISTS sources)
    get_filename_component(stem "${dts}" NAME_WE)
    string(REGEX REPLACE "-overlay$" "" stem "${stem}")
    set(dtbo "${CMAKE_BINARY_DIR}/firmware/${stem}.dtbo")
    add_custom_command(
      OUTPUT "${dtbo}"
      COMMAND "${SLICECAP_DTC}" -@ -I dts -O dtb -o "${dtbo}" "${dts}"
      DEPENDS "${dts}"
      COMMENT "Device-tree overlay ${stem}.dtbo"
      VERBATIM)
    list(APPEND blobs "${dtbo}")
  endforeach()
  add_custom_target(slicecap_overlays ALL DEPENDS ${blobs})
  install(FILES ${blobs} DESTINATION "${CMAKE_INSTALL_DATADIR}/slicecap/firmware")
endfunction()

function(_slicecap_cpack_deb)
  set(CPACK_GENERATOR DEB)
  set(CPACK_PACKAGE_NAME slicecap)
  set(CPACK_PACKAGE_VENDOR "slicecap")
  set(CPACK_PACKAGE_CONTACT "slicecap developers <dev@slicecap.invalid>")
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
  set(CPACK_PACKAGE_DESCRIPTION
      "Captures how a real, flat material reflects light, anisotropic included, with a\n"
      "Raspberry-Pi-class box, a camera, one LED and a printed target, and\n"
      "reconstructs its full 81 x 81 apparent BRDF (Method B of Filip and Vavra 2013).")
  string(JOIN "" CPACK_PACKAGE_DESCRIPTION ${CPACK_PACKAGE_DESCRIPTION})
  set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
  set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
  set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
  set(CPACK_DEBIAN_PACKAGE_SECTION science)
  set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
  set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://slicecap.invalid/")
  # The architecture of what was built, not of the build machine (cpack's default).
  if(CMAKE_CROSSCOMPILING)
    execute_process(COMMAND dpkg-architecture -qDEB_HOST_ARCH -t "${CMAKE_LIBRARY_ARCHITECTURE}"
                    OUTPUT_VARIABLE arch OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  else()
    execute_process(COMMAND dpkg --print-architecture OUTPUT_VARIABLE arch OUTPUT_STRIP_TRAILING_WHITESPACE)
  endif()
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE "${arch}")
  # Filled by scripts/package from scripts/deb-depends (cpack -D CPACK_DEBIAN_PACKAGE_DEPENDS=...).
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
  set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
  set(CPACK_STRIP_FILES ON)

  set(control_dir "${CMAKE_BINARY_DIR}/packaging/deb")
  file(MAKE_DIRECTORY "${control_dir}")
  set(extra)
  foreach(script postinst prerm postrm)
    configure_file("${PROJECT_SOURCE_DIR}/cmake/packaging/${script}" "${control_dir}/${script}" COPYONLY)
    list(APPEND extra "${control_dir}/${script}")
  endforeach()
  get_property(conffiles GLOBAL PROPERTY SLICECAP_CONFFILES)
  if(conffiles)
    list(JOIN conffiles "\n" text)
    file(WRITE "${control_dir}/conffiles" "${text}\n")
    list(APPEND extra "${control_dir}/conffiles")
  else()
    file(REMOVE "${control_dir}/conffiles")
  endif()
  set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA "${extra}")
  include(CPack)
endfunction()
