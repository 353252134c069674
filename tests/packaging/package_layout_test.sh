#!/usr/bin/env bash
# The package picks up what the daemon's issue adds (slicecapd, systemd units, sysusers, tmpfiles, udev
# rules, firmware with its overlay compiled, data) with no change to the packaging: a scratch project
# with stand-ins for those files is packaged by cmake/SlicecapPackaging.cmake and scripts/package, and
# the .deb must hold each in its place, with /etc/slicecap/slicecapd.conf generated from `slicecapd
# --print-config` and marked as a conffile.
# Usage: package_layout_test.sh REPO_DIR
set -euo pipefail
repo=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

mkdir -p "$work/src/app" "$work/src/systemd" "$work/src/firmware"
cd "$work/src"
ln -s "$repo/cmake" cmake
ln -s "$repo/scripts" scripts
cp "$repo/README.md" README.md
cat >CMakeLists.txt <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(slicecap VERSION 0.1.0 LANGUAGES CXX DESCRIPTION "packaging layout test")
list(APPEND CMAKE_MODULE_PATH "${CMAKE_SOURCE_DIR}/cmake")
include(SlicecapPackaging)
add_executable(slicecap app/stand_in.cpp)
add_executable(slicecapd app/stand_in.cpp)
slicecap_install_data(FILES firmware/led.dtbo SUBDIR priors)
slicecap_package()
EOF
cat >app/stand_in.cpp <<'EOF'
#include <cstring>
#include <iostream>
int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--print-config") == 0) {
    std::cout << "# stand-in configuration\nstorage = /var/lib/slicecap\n";
  } else {
    std::cout << "stand-in 0.1.0: a stand-in program\n\nusage: stand-in COMMAND\n\ncommands:\n"
                 "  sweep   one sweep\n\nend\n";
  }
  return 0;
}
EOF
printf '[Unit]\nDescription=slicecap daemon\n\n[Service]\nExecStart=/usr/bin/slicecapd\n\n[Install]\nWantedBy=multi-user.target\n' \
  >systemd/slicecapd.service
printf 'g slicecap -\nu slicecap -:slicecap "slicecap daemon" /var/lib/slicecap\n' >systemd/slicecap.sysusers
printf 'd /var/lib/slicecap 0750 slicecap slicecap -\n' >systemd/slicecap.tmpfiles
printf 'not a unit\n' >systemd/README.md
printf 'overlay\n' >firmware/led.dtbo
printf 'SUBSYSTEM=="gpio", KERNEL=="gpiochip*", GROUP="gpio", MODE="0660"\n' >systemd/60-slicecap-gpio.rules
printf '/dts-v1/;\n/plugin/;\n/ { compatible = "brcm,bcm2711"; };\n' >firmware/slicecap-led-overlay.dts

cmake -S . -B build -G Ninja -DCMAKE_INSTALL_PREFIX=/usr >build.log 2>&1 || { cat build.log; fail "configure"; }
deb=$(scripts/package build / 2>>build.log | tail -n1) || { cat build.log; fail "scripts/package"; }
[[ -f $deb ]] || fail "no .deb"

contents=$(dpkg-deb -c "$deb" | awk '{print $NF}' | sed 's|^\./|/|')
for path in /usr/bin/slicecap /usr/bin/slicecapd /usr/share/man/man1/slicecap.1.gz \
  /usr/share/man/man1/slicecapd.1.gz /lib/systemd/system/slicecapd.service \
  /usr/lib/sysusers.d/slicecap.conf /usr/lib/tmpfiles.d/slicecap.conf /etc/slicecap/slicecapd.conf \
  /usr/share/slicecap/firmware/led.dtbo /usr/share/slicecap/priors/led.dtbo \
  /lib/udev/rules.d/60-slicecap-gpio.rules /usr/share/slicecap/firmware/slicecap-led-overlay.dts \
  /usr/share/slicecap/firmware/slicecap-led.dtbo \
  /usr/share/doc/slicecap/copyright /usr/share/doc/slicecap/changelog.gz; do
  grep -qx "$path" <<<"$contents" || fail "$path is not in the package"
done
! grep -q 'systemd/system/README' <<<"$contents" || fail "systemd/README.md was installed as a unit"

mkdir control
dpkg-deb -e "$deb" control
[[ $(cat control/conffiles) == /etc/slicecap/slicecapd.conf ]] || fail "conffiles: $(cat control/conffiles)"
for script in postinst prerm postrm; do
  [[ -x control/$script ]] || fail "no executable $script"
done
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./etc/slicecap/slicecapd.conf | grep -qx 'storage = /var/lib/slicecap' \
  || fail "slicecapd.conf is not what --print-config writes"
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/man/man1/slicecapd.1.gz | gzip -d | grep -q '^\.SH "SLICECAPD SWEEP"' \
  || fail "the man page lacks the section of the command its --help lists"
grep -q '^libc6' <<<"$(dpkg-deb -f "$deb" Depends)" || fail "Depends lacks libc6: $(dpkg-deb -f "$deb" Depends)"
echo "PASS: $(wc -l <<<"$contents") entries, conffiles and maintainer scripts in place"
