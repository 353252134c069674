#!/usr/bin/env bash
# slicecapd on an HDR recording (the file camera plays `slicecap simulate --hdr 2`: LED pairs
# alternating a long and a short exposure, frames[].exposure_level): the daemon processes each
# level in its own pipeline and the bins merge the levels per cell, so its session holds what
# `slicecap process --ambient previous` (the live loop's one-sided room light) makes of the same
# recording, bin for bin, and a sharp highlight that clips the long exposure is kept.
# Usage: slicecapd_hdr_test.sh SLICECAP SLICECAPD
set -euo pipefail
slicecap=$1
slicecapd=$2
work=$(mktemp -d /tmp/slicecapd-hdr-XXXXXX)
# shellcheck source=../../scripts/slicecapd-session.sh
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/slicecapd-session.sh"
trap 'session_cleanup; rm -rf "$work"' EXIT

# A sharp Ward lobe (alpha 0.04 across): metered on the paper its peak would clip by ~100 x.
material="ward:diffuse=0.02,specular=0.9,ax=0.04,ay=0.3,tangent=0"
"$slicecap" simulate --material "$material" --slice diagonal --theta-i 75 --theta-v 75 --hdr 2 \
  --steady --seed 3 -o "$work/rec" >/dev/null 2>&1 || fail "simulate --hdr 2 failed"
write_config "$work/rec"
start_daemon
"$slicecap" session new "hdr" --id hdr >/dev/null
sweep "diagonal 75 75"
"$slicecap" export hdr -o "$work/desk" >/dev/null || fail "export failed"
stop_daemon
"$slicecap" process "$work/rec" -o "$work/offline.csv" --ambient previous >/dev/null 2>&1 ||
  fail "slicecap process --ambient previous failed"

python3 - "$work/desk/hdr-slices.csv" "$work/offline.csv" "$work/rec/truth.json" <<'PY' || fail "the daemon's HDR bins differ from the offline pipeline's"
import csv, json, sys

def bins(path):
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith("#")][1:]
    return {round(float(r[4]) / 15.0) % 24: [float(x) for x in r[5:8]] for r in rows}

daemon, offline = bins(sys.argv[1]), bins(sys.argv[2])
truth_peak = max(max(f["brdf"]) for f in json.load(open(sys.argv[3]))["frames"] if f.get("led_on", True))
# The live loop has no LED-off frame before each level's first LED-on one: at most those two bins.
assert len(daemon) >= 22, f"the daemon filled {len(daemon)} of 24 bins"
for k, value in daemon.items():
    assert k in offline, f"bin {k}: in the daemon's session, not offline"
    for a, b in zip(value, offline[k]):
        assert abs(a - b) <= 1e-6 * max(abs(b), 1e-3), f"bin {k}: daemon {value}, offline {offline[k]}"
peak = max(max(v) for v in daemon.values())
assert peak >= 0.8 * truth_peak, f"the peak bin reads {peak:.3f} where the truth peaks at {truth_peak:.3f}"
print(f"HDR: {len(daemon)} bins equal to process --ambient previous; peak {peak:.2f} (truth {truth_peak:.2f})")
PY
echo "slicecapd on an HDR recording: ok"
