#!/usr/bin/env bash
# slicecapd end to end on the file camera: the daemon plays a simulated eight-slice session, a
# person's whole session is driven through the `slicecap` CLI, the daemon is killed with SIGKILL in
# mid-sweep and restarted (no acknowledged sample may be lost; ExecStopPost's `--led-off` switches
# the LED off), and the exported EXR's error against the material must lie between the offline
# pipeline's on the same recordings (`slicecap capture-offline`: its default two-sided room-light
# term, which the live loop takes too, one LED block late, and an unlimited marker search) and the
# old live loop's (`--ambient previous`: the LED-off frame before alone, the live search budget),
# each with 10 % to spare. Texture
# capture is on: its store survives the kill, the export carries it, and `slicecap btf` turns the
# exported texture into a BTF with every texel reconstructed.
# Usage: slicecapd_e2e_test.sh SLICECAP SLICECAPD [MATERIAL]
set -euo pipefail
slicecap=$1
slicecapd=$2
material=${3:-satin-blue-45}
work=$(mktemp -d /tmp/slicecapd-e2e-XXXXXX)
# shellcheck source=../../scripts/slicecapd-session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/slicecapd-session.sh"
trap 'session_cleanup; rm -rf "$work"' EXIT

"$slicecap" simulate --material "$material" --session "$work/session" --frames 32 --seed 7 >/dev/null
# The session's recordings at 4 x their recorded pace: the same frames, their LED states and
# timestamps (a recorded frame says whether the LED was on), without 72 of the 96 s a person's
# eight 12 s sweeps would wait on the clock. Slow enough that the kill below lands mid-sweep.
write_config "$work/session" "texture_resolution = 16" "camera_recording_speed = 4"

start_daemon
led_is_off || fail "the LED is not off after the start"
"$slicecap" session new "$material" --id e2e >/dev/null
acknowledged=0
for slice in "${session_slices[@]}"; do
  if [[ $slice == "axial 30 30" ]]; then
    # The four diagonal sweeps are in: the daemon's isotropy test (the shipped prior) has spoken.
    status=$("$slicecap" status --json | tr -d '\n ')
    grep -q '"isotropy":{' <<<"$status" || fail "no isotropy verdict after the diagonal sweeps"
    grep -q '"isotropy":{[^}]*"error"' <<<"$status" && fail "the isotropy test failed: $status"
    # The default satin's grain: the axial sweeps are needed.
    if [[ $material == satin-blue-45 ]] && ! grep -q '"axial_sweeps_needed":true' <<<"$status"; then
      fail "$material called isotropic after the diagonal sweeps: $status"
    fi
    echo "after the diagonal sweeps: $("$slicecap" status | grep '^isotropy:')"
    # An operator who stops here still gets a table: the prior (on the window cells, the
    # default) reads the diagonal slices alone.
    "$slicecap" export e2e -o "$work/diagonal-only" >/dev/null || fail "export after the diagonal sweeps failed"
    [[ -f $work/diagonal-only/e2e-abrdf-prior-cells.exr ]] || fail "the diagonal sweeps' export has no prior-cells EXR"
  fi
  if [[ $slice != "axial 75 30" ]]; then
    sweep "$slice"
    continue
  fi
  # shellcheck disable=SC2086
  "$slicecap" sweep start $slice >/dev/null
  # Mid-sweep: read what has been acknowledged, then kill the daemon without warning.
  for _ in $(seq 1 400); do
    acknowledged=$(sweep_samples || echo 0)
    [[ ${acknowledged:-0} -ge 3 ]] && break
    sleep 0.02
  done
  kill -9 "$daemon_pid"; wait "$daemon_pid" 2>/dev/null || true; daemon_pid=
  texture_frames() { find "$work/storage/e2e/texture/axial-75-30" -name '*.tex' 2>/dev/null | wc -l; }
  stored_before=$(texture_frames)
  "$slicecapd" --config "$work/slicecapd.conf" --led-off || fail "--led-off failed"
  led_is_off || fail "the LED is not off after --led-off"
  start_daemon
  status=$("$slicecap" status --json | tr -d '\n ')
  grep -q '"state":"paused"' <<<"$status" || fail "the interrupted sweep did not come back paused"
  after=$(sweep_samples)
  [[ $after -ge $acknowledged ]] || fail "samples lost in the kill: $acknowledged acknowledged, $after kept"
  echo "kill -9 in mid-sweep: $acknowledged samples acknowledged before, $after kept after the restart"
  [[ $(texture_frames) -ge $stored_before ]] ||
    fail "texture frames lost in the kill: $stored_before stored, $(texture_frames) after the restart"
  echo "  and $stored_before texture frames stored before the kill, $(texture_frames) after"
  sweep "$slice"   # `sweep start` continues the paused sweep
done
"$slicecap" export e2e -o "$work/desk" >/dev/null
daemon_exr=$work/desk/e2e-abrdf-b.exr
[[ -f $daemon_exr ]] || fail "no EXR exported"
[[ -f $work/desk/e2e-slices.csv && -f $work/desk/e2e-summary.json ]] || fail "export incomplete"
texture=$work/desk/e2e-texture
[[ -f $texture/texture.json && -f $texture/slices.csv ]] || fail "the export has no texture"
frames=$(find "$texture" -name '*.tex' | wc -l)
[[ $frames -ge 40 ]] || fail "the texture kept only $frames frames"
"$slicecap" btf "$texture" -o "$work/btf" --threads 2 >/dev/null 2>"$work/btf.log" ||
  fail "slicecap btf on the exported texture failed: $(tail -3 "$work/btf.log")"
grep -q '"failed_texels": 0' "$work/btf/btf.json" || fail "texels failed: $(grep failed "$work/btf/btf.json")"
[[ -f $work/btf/average.exr && -f $work/btf/tv000_pv000/tl000_pl000_tv000_pv000.exr ]] ||
  fail "the BTF directory is incomplete"
echo "texture: $frames frames kept by the daemon, a 16 x 16 BTF reconstructed from the export"

"$slicecap" capture-offline "$work/session" -o "$work/offline.exr" >/dev/null 2>&1
"$slicecap" capture-offline "$work/session" -o "$work/one-sided.exr" --ambient previous >/dev/null 2>&1
"$slicecap" generate "$material" -o "$work/truth.exr" >/dev/null
daemon_de=$(delta_e "$work/truth.exr" "$daemon_exr")
offline_de=$(delta_e "$work/truth.exr" "$work/offline.exr")
one_sided_de=$(delta_e "$work/truth.exr" "$work/one-sided.exr")
echo "dE against $material: daemon session $daemon_de, offline pipeline $offline_de," \
  "offline one-sided (the old live loop) $one_sided_de"
# The prior's table of the first export is made afresh from all eight sweeps, not carried stale.
[[ -f $work/desk/e2e-abrdf-prior-cells.exr ]] || fail "the final export did not remake the prior-cells table"
cmp -s "$work/desk/e2e-abrdf-prior-cells.exr" "$work/diagonal-only/e2e-abrdf-prior-cells.exr" &&
  fail "the prior-cells table was exported stale (the same as after the diagonal sweeps)"
echo "prior-cells: dE $(delta_e "$work/truth.exr" "$work/diagonal-only/e2e-abrdf-prior-cells.exr")" \
  "from the diagonal sweeps, $(delta_e "$work/truth.exr" "$work/desk/e2e-abrdf-prior-cells.exr") from all eight"
awk -v d="$daemon_de" -v o="$offline_de" -v p="$one_sided_de" \
  'BEGIN { exit !(d <= 1.10 * p + 1e-9 && d >= 0.90 * o - 1e-9) }' ||
  fail "the daemon's EXR (dE $daemon_de) is not between the offline pipeline's (dE $offline_de) and" \
    "the one-sided one's (dE $one_sided_de), 10 % either side"

stop_daemon
led_is_off || fail "the LED is not off after SIGTERM"

# One sweep on the camera model (camera = model): a camera that queues frames, exposes its rows one
# after another and delivers late, the LED strobed in step with the rows, the frames kept.
write_model_config "model_material = $material" "model_sweep_seconds = 5" "record_frames = true"
start_daemon
"$slicecap" session new "$material" --id model >/dev/null
"$slicecap" sweep start diagonal 30 30 >/dev/null
wait_paused "diagonal 30 30 (camera model)"
led_is_off || fail "the LED is not off after the camera model's sweep ended"
status=$("$slicecap" status --json | tr -d '\n ')
grep -q '"camera_frames":{' <<<"$status" || fail "the status has no camera_frames: $status"
delivered=$(grep -o '"delivered":[0-9]*' <<<"$status" | grep -o '[0-9]*$')
samples=$(sweep_samples)
[[ $delivered -ge 20 && $samples -ge 1 ]] ||
  fail "the camera model's sweep delivered $delivered frames and $samples samples"
switches=$(grep -c . "$work/led.log")
[[ $switches -ge 10 ]] || fail "the LED switched only $switches times in the camera model's sweep"
"$slicecap" sweep stop >/dev/null
recording=$work/storage-model/model/recordings/diagonal-30-30
grep -q '"led_exposure"' "$recording/recording.json" ||
  fail "the camera model's recording keeps no LED exposure"
# The sweep's decoding (docs/linear-light.md): said by the status and the session; with a measured
# curve, the recording decodes through it and the bracket frames are kept beside it.
grep -q '"decoding":{"decoding":"' <<<"$status" || fail "the status does not say the sweep's decoding: $status"
decoding_file=$work/storage-model/model/decoding/diagonal-30-30.json
[[ -f $decoding_file ]] || fail "the session does not record the sweep's decoding ($decoding_file)"
if grep -q '"decoding": *"measured-curve"' "$decoding_file"; then
  grep -q '"decoding": *"measured-curve"' "$recording/recording.json" ||
    fail "the sweep decoded through a measured curve but its recording does not say so"
  bracket=$work/storage-model/model/brackets/diagonal-30-30/run-1/recording.json
  for _ in $(seq 1 100); do [[ -f $bracket ]] && grep -q '"frame-00007.png"' "$bracket" && break; sleep 0.1; done
  grep -q '"frame-00007.png"' "$bracket" 2>/dev/null || fail "the bracket's 8 frames are not kept in $bracket"
else
  grep -q '"warning"' "$decoding_file" || fail "the sweep fell back to sRGB without a warning: $(cat "$decoding_file")"
fi
"$slicecap" process "$recording" -o "$work/model-slices.csv" >"$work/model-process.log" 2>&1 ||
  fail "slicecap process on the camera model's recording failed: $(tail -3 "$work/model-process.log")"
stop_daemon
led_is_off || fail "the LED is not off after SIGTERM"
echo "camera model: $delivered frames, $samples samples, $switches LED switches, the recording re-processed"
echo "slicecapd end to end: ok"
