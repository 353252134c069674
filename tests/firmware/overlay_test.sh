#!/usr/bin/env bash
# Compiles the LED overlay with dtc and checks what the daemon relies on: line 17 is named
# SLICECAP_LED, the overlay targets the gpio bank by label (resolved when the firmware loads it),
# and config.txt drives the same pin low from boot.
set -euo pipefail
firmware=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dtc -@ -q -I dts -O dtb -o "$work/slicecap-led.dtbo" "$firmware/slicecap-led-overlay.dts"
mapfile -t names < <(fdtget -t s "$work/slicecap-led.dtbo" /fragment@0/__overlay__ gpio-line-names | tr ' ' '\n')
fail() { echo "FAIL: $*" >&2; exit 1; }
[[ ${#names[@]} -eq 28 ]] || fail "expected 28 header line names, got ${#names[@]}"
[[ ${names[17]} == SLICECAP_LED ]] || fail "line 17 is named '${names[17]}', not SLICECAP_LED"
for i in "${!names[@]}"; do
  [[ $i -eq 17 || ${names[$i]} == GPIO$i || $i -lt 2 ]] || fail "line $i renamed to '${names[$i]}'"
done
[[ $(fdtget "$work/slicecap-led.dtbo" /__fixups__ gpio) == /fragment@0:target:0 ]] ||
  fail "the overlay does not target the &gpio label"
grep -qx 'gpio=17=op,dl,pd' "$firmware/config.txt" || fail "config.txt does not drive GPIO17 low at boot"
grep -qx 'dtoverlay=slicecap-led' "$firmware/config.txt" || fail "config.txt does not load the overlay"
echo "overlay and config.txt agree: GPIO17 = SLICECAP_LED, low from boot"
