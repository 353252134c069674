#!/usr/bin/env bash
# slicecapd as a process, on the file camera: `--check-config` refuses what a start would refuse
# (a missing socket group, a socket path too long for sun_path, a missing recording); every
# terminating signal a person or the system may send stops the daemon cleanly, in mid-sweep, with
# the LED off and its socket file removed; SIGPIPE does not stop it; a start under umask 000 leaves
# the socket 0660; and slicecap fails when its standard output cannot be written.
# Usage: slicecapd_process_test.sh SLICECAP SLICECAPD
set -euo pipefail
slicecap=$1
slicecapd=$2
work=$(mktemp -d /tmp/slicecapd-proc-XXXXXX)
# shellcheck source=../../scripts/slicecapd-session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/slicecapd-session.sh"
trap 'session_cleanup; rm -rf "$work"' EXIT

# One short recording of one slice: the sweep runs while the signals arrive, or has paused.
"$slicecap" simulate --material lambert:albedo=0.5,0.5,0.5 -o "$work/session" --slice diagonal \
  --frames 16 --ideal --seed 7 >/dev/null 2>&1
write_config "$work/session"
"$slicecapd" --config "$work/slicecapd.conf" --check-config >/dev/null ||
  fail "--check-config refused a good configuration"

# check_refuses WHAT EXPECTED_TEXT LINE...: a configuration with LINE(s) changed fails the check.
check_refuses() {
  local what=$1 expected=$2
  shift 2
  grep -v -e '^socket_group' -e '^socket =' -e '^camera_recording' "$work/slicecapd.conf" >"$work/bad.conf"
  printf '%s\n' "$@" >>"$work/bad.conf"
  grep -q '^socket_group' "$work/bad.conf" || echo "socket_group =" >>"$work/bad.conf"
  grep -q '^socket =' "$work/bad.conf" || echo "socket = $work/s.sock" >>"$work/bad.conf"
  grep -q '^camera_recording' "$work/bad.conf" || echo "camera_recording = $work/session" >>"$work/bad.conf"
  if "$slicecapd" --config "$work/bad.conf" --check-config >"$work/check.out" 2>&1; then
    fail "--check-config said ok with $what: $(cat "$work/check.out")"
  fi
  grep -q -- "$expected" "$work/check.out" || fail "--check-config with $what did not say '$expected': $(cat "$work/check.out")"
}
check_refuses "a missing socket group" "group no-such-group-here does not exist" "socket_group = no-such-group-here"
check_refuses "a socket path too long" "longer than 107 bytes" "socket = /tmp/$(printf 'x%.0s' {1..120}).sock"
check_refuses "a missing recording" "$work/nowhere" "camera_recording = $work/nowhere"
printf '{"version": 2.0, "target": "pisp",' >"$work/broken-tuning.json"
check_refuses "a tuning file that is not JSON" "tuning_file $work/broken-tuning.json: is not valid JSON" \
  "tuning_file = $work/broken-tuning.json"
check_refuses "a tuning file that cannot be read" "tuning_file $work/no-tuning.json: cannot be read" \
  "tuning_file = $work/no-tuning.json"
echo "--check-config refuses a missing group, a long socket path, a missing recording and a bad tuning file"

# A standard output that cannot take what slicecap prints (a full disk) is a failure, not exit 0.
if "$slicecap" --version >/dev/full 2>"$work/full.err"; then
  fail "slicecap --version >/dev/full exited 0"
fi
grep -q "standard output: write failed" "$work/full.err" ||
  fail "slicecap >/dev/full did not say why: $(cat "$work/full.err")"
echo "a standard output that cannot be written is a failure"

# A start under umask 000: the socket is the group's, not everybody's.
saved_umask=$(umask)
umask 000
start_daemon
umask "$saved_umask"
mode=$(stat -c %a "$work/s.sock")
[[ $mode == 660 ]] || fail "the socket is $mode after a start under umask 000"
kill -PIPE "$daemon_pid"
"$slicecap" status >/dev/null || fail "slicecapd stopped answering after SIGPIPE"
stop_daemon
[[ ! -e $work/s.sock ]] || fail "the socket file was left behind after SIGTERM"
echo "umask 000: socket 0660; SIGPIPE ignored; the socket file removed on exit"

for signal in HUP QUIT USR1 USR2 INT TERM; do
  start_daemon
  if [[ $signal == HUP ]]; then "$slicecap" session new "grey card" --id signals >/dev/null; fi
  # The first start begins the sweep; the later ones continue it (it comes back paused).
  "$slicecap" sweep start diagonal 30 30 >/dev/null 2>&1 || true
  kill -"$signal" "$daemon_pid"
  status=0
  wait "$daemon_pid" || status=$?
  daemon_pid=
  [[ $status -eq 0 ]] || fail "slicecapd exited with status $status on SIG$signal"
  led_is_off || fail "the LED is on after SIG$signal"
  [[ ! -e $work/s.sock ]] || fail "the socket file was left behind after SIG$signal"
done
echo "SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGINT and SIGTERM stop it cleanly with the LED off"
echo "slicecapd as a process: ok"
