#!/usr/bin/env bash
# Several devices (issue #14): throughput of one device against two, for PT alone (split by sample
# index) and for the combination (RB on one device, PT on the other, at the same time). Each row is
# one render of --spp N; throughput is PT samples per second (pixels x spp / render seconds) and,
# for the combination, rounds per second. Writes OUT/devices.md.
#
# Usage: bench/devices.sh [--out DIR] [--spp N] [--size N] [--one SPEC] [--two SPEC] [--scene NAME]
# Defaults: --spp 64, --size 128, --one 0, --two 0,1, --scene cornell-box. On PoCL, two CPU devices
# come from POCL_DEVICES (set to "pthread pthread" when unset); they share this machine's cores, so
# on a CPU-only machine two devices cannot be faster than one -- the figure that matters is on a GPU
# plus the CPU, or two GPUs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

out=""; spp=64; size=128; one=0; two=0,1; scene=cornell-box
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    --spp) spp=$2; shift ;;
    --size) size=$2; shift ;;
    --one) one=$2; shift ;;
    --two) two=$2; shift ;;
    --scene) scene=$2; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "devices.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
out=${out:-$bench_root/bench/results/devices}
mkdir -p "$out"
export POCL_DEVICES=${POCL_DEVICES:-pthread pthread}

"$BUNDLEPATH" devices > "$out/devices.txt"
table="$out/devices.md"
{
  echo "| mode | devices | spp | render s | PT Msamples/s | rounds/s | per device (pt_samples, rb_iterations, busy s) |"
  echo "|---|---|---|---|---|---|---|"
} > "$table"
# Untimed first: the kernel builds (and PoCL's work-group code) go to the caches, not to the first row.
for devices in "$one" "$two"; do
  "$BUNDLEPATH" render "$bench_root/scenes/$scene.gltf" --mode combined --ratio 1 --spp 1 --width 16 --height 16 \
    --device "$devices" --out "$out/warm" 2> "$out/log.txt"
done
for mode in "--mode pt" "--mode combined --ratio 1"; do
  for devices in "$one" "$two"; do
    stats="$out/stats-${mode// /_}-${devices//,/_}.json"
    # shellcheck disable=SC2086  # mode is a list of flags
    "$BUNDLEPATH" render "$bench_root/scenes/$scene.gltf" $mode --spp "$spp" --width "$size" --height "$size" \
      --device "$devices" --out "$out/img" --stats "$stats" 2> "$out/log.txt"
    python3 - "$stats" "$mode" "$devices" >> "$table" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
secs = s["render_seconds"]
pt = s["spp"] * s["width"] * s["height"] / secs / 1e6 if secs > 0 else 0.0
rounds = s.get("rounds", s["spp"]) / secs if secs > 0 else 0.0
per = "; ".join(f'[{d["index"]}] {d["pt_samples"]}, {d["rb_iterations"]}, {d["busy_seconds"]:.2f}' for d in s["devices"])
print(f'| {sys.argv[2]} | {sys.argv[3]} | {s["spp"]} | {secs:.2f} | {pt:.3f} | {rounds:.1f} | {per} |')
PY
  done
done
cat "$table"
