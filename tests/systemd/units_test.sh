#!/usr/bin/env bash
# `systemd-analyze verify` on the units; any warning (an unknown key, a bad value) fails the test,
# and so does an exposure score (`systemd-analyze security`) above 2.0.
# Usage: units_test.sh SYSTEMD_DIR [SLICECAPD_BINARY]. verify also checks that ExecStart's program
# exists and is executable: the built slicecapd takes /usr/bin/slicecapd's place (without one, a
# stand-in script does, and the test checks the units' text only).
set -euo pipefail
units=$1
daemon=${2:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [[ -z $daemon ]]; then
  daemon=$work/slicecapd
  printf '#!/bin/sh\nexit 0\n' >"$daemon"
  chmod +x "$daemon"
fi
for unit in slicecapd.service slicecapd.socket; do
  sed "s#/usr/bin/slicecapd#$daemon#g" "$units/$unit" >"$work/$unit"
done
if ! systemd-analyze verify --man=no "$work/slicecapd.socket" "$work/slicecapd.service" 2>"$work/log"; then
  cat "$work/log" >&2
  echo "FAIL: systemd-analyze verify rejected the units" >&2
  exit 1
fi
# Containers without a booted systemd print notes about PID 1 that say nothing of our units.
if grep -v -e 'PID 1' -e 'container' "$work/log" | grep -q .; then
  cat "$work/log" >&2
  echo "FAIL: systemd-analyze verify warned about the units" >&2
  exit 1
fi
grep -q '^Type=notify$' "$units/slicecapd.service" || { echo "FAIL: not Type=notify" >&2; exit 1; }
grep -q '^ExecStopPost=.*--led-off' "$units/slicecapd.service" ||
  { echo "FAIL: no ExecStopPost turning the LED off" >&2; exit 1; }
# The service's exposure score (`systemd-analyze security`, 0.0 safest .. 10.0): 0.4 with systemd
# 252, 2.7 before its sandbox was tightened; a change that brings it above 2.0 fails. --threshold
# counts in tenths. A systemd without --offline (before 250) gets the key directives checked.
if systemd-analyze security --help 2>/dev/null | grep -q -- '--offline'; then
  if ! systemd-analyze security --offline=true --threshold=20 "$work/slicecapd.service" \
      >"$work/security" 2>&1; then
    grep -e '✗' -e 'Overall' -e 'Failed' "$work/security" >&2
    echo "FAIL: the service's exposure score is above 2.0" >&2
    exit 1
  fi
  echo "exposure: $(grep -o 'Overall exposure level.*' "$work/security")"
else
  for directive in '^SystemCallFilter=@system-service' '^PrivateDevices=yes' '^ProtectProc=invisible' \
      '^ProcSubset=pid' '^UMask=0027' '^RemoveIPC=yes' '^PrivateMounts=yes' '^IPAddressDeny=any'; do
    grep -q "$directive" "$units/slicecapd.service" ||
      { echo "FAIL: slicecapd.service lacks $directive" >&2; exit 1; }
  done
fi
echo "units verified"
