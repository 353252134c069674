#!/usr/bin/env bash
# slicecapd end to end on the file camera: the daemon plays a simulated eight-slice session, a
# person's whole session is driven through the `slicecap` CLI, the daemon is killed with SIGKILL in
# mid-sweep and restarted (no acknowledged sample may be lost; ExecStopPost's `--led-off` switches
# the LED off), and the exported EXR's error against the material must be within 10 % of the
# offline pipeline's (`slicecap capture-offline --ambient previous`: the live loop's one-sided
# room-light term; the default two-sided one is better than live) on the same recordings.
# Usage: slicecapd_e2e_test.sh SLICECAP SLICECAPD [MATERIAL]
set -euo pipefail
slicecap=$1
slicecapd=$2
material=${3:-satin-blue-45}
work=$(mktemp -d /tmp/slicecapd-e2e-XXXXXX)
daemon_pid=
cleanup() {
  [[ -n $daemon_pid ]] && kill "$daemon_pid" 2>/dev/null && wait "$daemon_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; [[ -f $work/daemon.log ]] && tail -20 "$work/daemon.log" >&2; exit 1; }

"$slicecap" simulate --material "$material" --session "$work/session" --frames 32 --seed 7 >/dev/null
cat >"$work/slicecapd.conf" <<CONF
camera = file
camera_recording = $work/session
storage = $work/storage
socket = $work/s.sock
socket_group =
led_log = $work/led.log
CONF
export SLICECAP_SOCKET=$work/s.sock

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
json_number() { grep -o "\"$1\": *[0-9]*" | head -1 | grep -o '[0-9]*$'; }
sweep_samples() { "$slicecap" status --json | tr -d '\n' | grep -o '"sweep": *{.*' | json_number samples; }
wait_paused() {
  for _ in $(seq 1 1200); do
    "$slicecap" status --json | tr -d '\n ' | grep -q '"state":"paused"' && return 0
    sleep 0.1
  done
  fail "the sweep of $1 never finished its recording"
}
led_is_off() { [[ $(tail -1 "$work/led.log" | awk '{print $2}') == off ]]; }

start_daemon
led_is_off || fail "the LED is not off after the start"
"$slicecap" session new "$material" --id e2e >/dev/null
acknowledged=0
for slice in "axial 30 30" "axial 30 75" "axial 75 30" "axial 75 75" \
             "diagonal 30 30" "diagonal 30 75" "diagonal 75 30" "diagonal 75 75"; do
  # shellcheck disable=SC2086
  "$slicecap" sweep start $slice >/dev/null
  if [[ $slice == "axial 75 30" ]]; then
    # Mid-sweep: read what has been acknowledged, then kill the daemon without warning.
    for _ in $(seq 1 400); do
      acknowledged=$(sweep_samples || echo 0)
      [[ ${acknowledged:-0} -ge 3 ]] && break
      sleep 0.02
    done
    kill -9 "$daemon_pid"; wait "$daemon_pid" 2>/dev/null || true; daemon_pid=
    "$slicecapd" --config "$work/slicecapd.conf" --led-off || fail "--led-off failed"
    led_is_off || fail "the LED is not off after --led-off"
    start_daemon
    status=$("$slicecap" status --json | tr -d '\n ')
    grep -q '"state":"paused"' <<<"$status" || fail "the interrupted sweep did not come back paused"
    after=$(sweep_samples)
    [[ $after -ge $acknowledged ]] || fail "samples lost in the kill: $acknowledged acknowledged, $after kept"
    echo "kill -9 in mid-sweep: $acknowledged samples acknowledged before, $after kept after the restart"
    # shellcheck disable=SC2086
    "$slicecap" sweep start $slice >/dev/null   # continues the paused sweep
  fi
  wait_paused "$slice"
  led_is_off || fail "the LED is not off after the recording of $slice ended"
  "$slicecap" sweep stop >/dev/null
done
"$slicecap" export e2e -o "$work/desk" >/dev/null
daemon_exr=$work/desk/e2e-abrdf-b.exr
[[ -f $daemon_exr ]] || fail "no EXR exported"
[[ -f $work/desk/e2e-slices.csv && -f $work/desk/e2e-summary.json ]] || fail "export incomplete"

"$slicecap" capture-offline "$work/session" -o "$work/offline.exr" --ambient previous >/dev/null 2>&1
"$slicecap" generate "$material" -o "$work/truth.exr" >/dev/null
de() { "$slicecap" compare "$work/truth.exr" "$1" --json | grep -o '"delta_e": *[0-9.e+-]*' | grep -o '[0-9.e+-]*$'; }
daemon_de=$(de "$daemon_exr")
offline_de=$(de "$work/offline.exr")
echo "dE against $material: daemon session $daemon_de, offline pipeline $offline_de"
awk -v d="$daemon_de" -v o="$offline_de" 'BEGIN { exit !(d <= 1.10 * o + 1e-9 && d >= 0.90 * o - 1e-9) }' ||
  fail "the daemon's EXR (dE $daemon_de) is not within 10 % of the offline pipeline's (dE $offline_de)"

kill -TERM "$daemon_pid"; wait "$daemon_pid" || fail "slicecapd did not exit cleanly on SIGTERM"; daemon_pid=
led_is_off || fail "the LED is not off after SIGTERM"
echo "slicecapd end to end: ok"
