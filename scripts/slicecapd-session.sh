# Shared by scripts/demo and tests/daemon/slicecapd_e2e_test.sh (sourced, not run): slicecapd on
# the file camera in a temporary folder, driven through the `slicecap` CLI as a person would.
# Before sourcing set: slicecap, slicecapd (the programs), work (a fresh temporary folder).
# The caller's `trap session_cleanup EXIT` stops the daemon on any exit.

daemon_pid=
# An interrupted run exits through the caller's EXIT trap, which stops the daemon.
trap 'exit 130' INT
trap 'exit 143' TERM
# The daemon's recommended order (`slicecap status`, next): the diagonal sweeps first, after which
# the isotropy test says whether the axial ones are needed.
session_slices=("diagonal 30 30" "diagonal 75 75" "diagonal 30 75" "diagonal 75 30"
                "axial 30 30" "axial 30 75" "axial 75 30" "axial 75 75")

session_cleanup() {
  if [[ -n $daemon_pid ]]; then
    kill "$daemon_pid" 2>/dev/null && wait "$daemon_pid" 2>/dev/null
    daemon_pid=
  fi
  return 0
}
fail() { echo "FAIL: $*" >&2; [[ -f $work/daemon.log ]] && tail -20 "$work/daemon.log" >&2; exit 1; }

# write_daemon_config LINE...: a configuration of the given lines, with the socket and the LED log
# in $work.
write_daemon_config() {
  {
    printf '%s\n' "$@"
    echo "socket = $work/s.sock"
    echo "socket_group ="
    echo "led_log = $work/led.log"
  } >"$work/slicecapd.conf"
  export SLICECAP_SOCKET=$work/s.sock
}
# write_config RECORDINGS [EXTRA_LINE...]: a file-camera configuration with everything in $work.
write_config() {
  local recordings=$1
  shift
  write_daemon_config "camera = file" "camera_recording = $recordings" "storage = $work/storage" "$@"
}
# write_model_config [EXTRA_LINE...]: a camera-model configuration (the virtual rig in front of a
# model of a Pi camera) with everything in $work; storage in $work/storage-model.
write_model_config() {
  write_daemon_config "camera = model" "storage = $work/storage-model" "$@"
}

start_daemon() {
  "$slicecapd" --config "$work/slicecapd.conf" >>"$work/daemon.log" 2>&1 &
  daemon_pid=$!
  for _ in $(seq 1 200); do
    "$slicecap" status >/dev/null 2>&1 && return 0
    kill -0 "$daemon_pid" 2>/dev/null || fail "slicecapd exited at start"
    sleep 0.05
  done
  fail "slicecapd did not answer on its socket"
}
# Stops the daemon as systemd does (SIGTERM) and fails unless it exits cleanly.
stop_daemon() {
  kill -TERM "$daemon_pid"
  wait "$daemon_pid" || { daemon_pid=; fail "slicecapd did not exit cleanly on SIGTERM"; }
  daemon_pid=
}
json_number() { grep -o "\"$1\": *[0-9]*" | head -1 | grep -o '[0-9]*$'; }
sweep_samples() { "$slicecap" status --json | tr -d '\n' | grep -o '"sweep": *{.*' | json_number samples; }
# wait_paused SLICE: until the file camera's recording of the running sweep has been played.
wait_paused() {
  for _ in $(seq 1 1200); do
    "$slicecap" status --json | tr -d '\n ' | grep -q '"state":"paused"' && return 0
    sleep 0.1
  done
  fail "the sweep of $1 never finished its recording"
}
led_is_off() { [[ $(tail -1 "$work/led.log" | awk '{print $2}') == off ]]; }
# sweep SLICE: start a sweep, wait until its recording has played, check the LED, stop it.
sweep() {
  # shellcheck disable=SC2086
  "$slicecap" sweep start $1 >/dev/null
  wait_paused "$1"
  led_is_off || fail "the LED is not off after the recording of $1 ended"
  "$slicecap" sweep stop >/dev/null
}
# delta_e TRUTH TABLE: the mean dE of TABLE against TRUTH (slicecap compare).
delta_e() { "$slicecap" compare "$1" "$2" --json | grep -o '"delta_e": *[0-9.e+-]*' | grep -o '[0-9.e+-]*$'; }
