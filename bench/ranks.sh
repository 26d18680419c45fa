#!/usr/bin/env bash
# MPI ranks (issue #14): throughput of one process against N ranks (mpirun -np N) at equal work, for
# PT (--spp), RB (--iterations) and the combination (--ratio 1, --spp). Each row is one render;
# throughput is PT samples per second (pixels x spp / rank 0's render seconds) and RB iterations
# per second, and the speed-up is against the one-process row of the same mode. Writes OUT/ranks.md.
#
# Usage: bench/ranks.sh [--out DIR] [--spp N] [--iterations N] [--size N] [--ranks N] [--scene NAME]
# Defaults: --spp 256, --iterations 512, --size 128, --ranks 2, --scene cornell-box. MPIRUN overrides
# the launcher (default: mpirun with the flags the tests use, --allow-run-as-root added as root).
# What a machine shows: the ranks of one machine share its cores, which PoCL already fills with one
# process, so on this 2-core machine two ranks cannot be faster than one; the rows then measure what
# ranks cost (the reduction of the image after every batch, MPI's busy waits, RB's second warm-up)
# rather than what they gain. The gain needs ranks with compute of their own (several machines, or a
# GPU each).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

out=""; spp=256; iterations=512; size=128; ranks=2; scene=cornell-box
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    --spp) spp=$2; shift ;;
    --iterations) iterations=$2; shift ;;
    --size) size=$2; shift ;;
    --ranks) ranks=$2; shift ;;
    --scene) scene=$2; shift ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) echo "ranks.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
out=${out:-$bench_root/bench/results/ranks}
mkdir -p "$out"
root_flag=""
if [ "$(id -u)" -eq 0 ]; then root_flag="--allow-run-as-root"; fi
MPIRUN=${MPIRUN:-mpirun --oversubscribe $root_flag --mca pml ob1 --mca btl self,vader --mca btl_vader_single_copy_mechanism none}
if ! command -v "${MPIRUN%% *}" > /dev/null; then
  echo "ranks.sh: ${MPIRUN%% *} not found (bash scripts/setup.sh installs openmpi-bin)" >&2
  exit 2
fi

scene_file="$bench_root/scenes/$scene.gltf"
table="$out/ranks.md"
{
  echo "| mode | ranks | spp | iterations | render s | PT Msamples/s | RB iterations/s | speed-up | rank 0's part |"
  echo "|---|---|---|---|---|---|---|---|---|"
} > "$table"
# Untimed first: the kernel builds (and PoCL's work-group code) go to the caches, not to the first row.
"$BUNDLEPATH" render "$scene_file" --mode combined --ratio 1 --spp 1 --width 16 --height 16 --out "$out/warm" \
  2> "$out/log.txt"
for mode in "--mode pt --spp $spp" "--mode rb --iterations $iterations" "--mode combined --ratio 1 --spp $spp"; do
  for n in 1 "$ranks"; do
    stats="$out/stats-$(echo "$mode" | cut -d' ' -f2)-$n.json"
    launcher=""
    if [ "$n" -gt 1 ]; then launcher="$MPIRUN -np $n"; fi
    # shellcheck disable=SC2086  # the launcher and the mode are lists of words
    $launcher "$BUNDLEPATH" render "$scene_file" $mode --width "$size" --height "$size" \
      --out "$out/img" --stats "$stats" 2> "$out/log.txt"
    python3 - "$stats" "$(echo "$mode" | cut -d' ' -f2)" "$out/base-$(echo "$mode" | cut -d' ' -f2)" >> "$table" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
mode, base_file = sys.argv[2], sys.argv[3]
secs = s["render_seconds"]
iterations = s.get("iterations", 0)
pt = s["spp"] * s["width"] * s["height"] / secs / 1e6 if secs > 0 else 0.0
rb = iterations / secs if secs > 0 else 0.0
if s["ranks"] == 1:
    open(base_file, "w").write(str(secs))
speed_up = float(open(base_file).read()) / secs if secs > 0 else 0.0
d = s["devices"][0]
part = d["pt_samples"] / s["spp"] if s["spp"] else d["rb_iterations"] / max(iterations, 1)
print(f'| {mode} | {s["ranks"]} | {s["spp"]} | {iterations} | {secs:.2f} | {pt:.3f} | {rb:.1f} | '
      f'{speed_up:.2f} | {part:.2f} |')
PY
  done
done
rm -f "$out"/base-*
cat "$table"
