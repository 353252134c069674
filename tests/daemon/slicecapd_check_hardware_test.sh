#!/usr/bin/env bash
# `slicecapd --check-hardware` as a program: on the camera model it measures the model's readout
# (28 800 us) within 10 % and writes it with --write-config, never replacing a file without
# --overwrite; a missing camera is a verdict naming the device, exit status 1. In a build without
# a camera backend (V4L2_BUILT or LIBCAMERA_BUILT 0) the verdict and --check-config name the CMake
# option that builds it.
# Usage: slicecapd_check_hardware_test.sh SLICECAPD [V4L2_BUILT [LIBCAMERA_BUILT]]   (1 or 0, default 1)
set -euo pipefail
slicecapd=$1
v4l2_built=${2:-1}
libcamera_built=${3:-1}
work=$(mktemp -d /tmp/slicecapd-hw-XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cat >"$work/model.conf" <<CONF
camera = model
model_rig = ideal
storage = $work/storage
socket = $work/s.sock
socket_group =
CONF
"$slicecapd" --config "$work/model.conf" --check-hardware --seconds 0.5 \
  --write-config "$work/measured.conf" >"$work/report.txt" 2>"$work/err.txt" ||
  { cat "$work/report.txt" "$work/err.txt"; fail "the check failed on the model"; }
readout=$(sed -n 's/^readout_us = //p' "$work/measured.conf")
[[ -n $readout ]] || fail "no readout_us in $(cat "$work/measured.conf")"
((readout >= 25920 && readout <= 31680)) || fail "readout_us = $readout, the model's is 28800"
grep -q '^led_guard_us = ' "$work/measured.conf" || fail "no led_guard_us"
grep -q '^\[ok\] LED timing and readout' "$work/report.txt" || fail "LED timing not ok: $(cat "$work/report.txt")"

# An existing file is kept unless --overwrite.
echo "# mine" >"$work/mine.conf"
if "$slicecapd" --config "$work/model.conf" --check-hardware --seconds 0.5 \
  --write-config "$work/mine.conf" >/dev/null 2>"$work/err.txt"; then
  fail "replaced an existing file without --overwrite"
fi
grep -q "mine.conf exists" "$work/err.txt" || fail "no message naming the file: $(cat "$work/err.txt")"
[[ $(cat "$work/mine.conf") == "# mine" ]] || fail "the existing file changed"

# No camera: a verdict naming the device.
sed 's/^camera = model/camera = v4l2\ncamera_device = \/dev\/video-missing/' "$work/model.conf" >"$work/v4l2.conf"
if "$slicecapd" --config "$work/v4l2.conf" --check-hardware >"$work/report.txt" 2>&1; then
  fail "a missing camera passed"
fi
if [[ $v4l2_built == 1 ]]; then
  grep -q '^\[fail\] camera: no camera: /dev/video-missing' "$work/report.txt" ||
    fail "no verdict naming the device: $(cat "$work/report.txt")"
else
  grep -q '^\[fail\] camera: v4l2: not in this build .*-DSLICECAP_WITH_V4L2=ON' "$work/report.txt" ||
    fail "no verdict naming SLICECAP_WITH_V4L2: $(cat "$work/report.txt")"
fi

# camera = libcamera in a build without it: --check-config refuses, naming the option.
if [[ $libcamera_built == 0 ]]; then
  sed 's/^camera = model/camera = libcamera/' "$work/model.conf" >"$work/libcamera.conf"
  if "$slicecapd" --config "$work/libcamera.conf" --check-config >"$work/report.txt" 2>&1; then
    fail "--check-config passed camera = libcamera in a build without it"
  fi
  grep -q 'camera = libcamera: libcamera: not in this build .*-DSLICECAP_WITH_LIBCAMERA=ON' \
    "$work/report.txt" || fail "--check-config did not name SLICECAP_WITH_LIBCAMERA: $(cat "$work/report.txt")"
fi
echo "ok"
