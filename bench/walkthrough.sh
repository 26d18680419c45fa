#!/usr/bin/env bash
# Walkthroughs (issue #15, docs/design.md §8): the cost per frame of F views rendered in one run (one
# ray-bundle chain shared by all views, each view its own eye gather and PT samples) against F
# separate renders of the same views, at equal iterations -- for --mode rb and --mode combined.
# The views are F keys of a --camera-path: on the Cornell boxes (cornell-box, cornell-glossy) walking
# into the box (from z = -0.8 to -0.2, swaying in x, looking at the back wall); on any other scene
# (rooms-N, rooms-lambert-N: the house of bench/make_rooms, or a file) walking 1 m from its default
# camera along its view, level, swaying 0.2 m sideways, looking the same way. With the same seed
# a walk's frame k is the separate render of view k bit for bit (tests/e2e/test_walkthrough.cpp), so
# the error per frame is equal and the cost is the whole comparison; the script checks the equality
# (relMSE of frame k against render k: 0) on the first and the last frame of each walk.
# Writes OUT/walkthrough.md: per mode and F, render seconds of the walk and of the F renders, seconds
# per frame of each, their ratio, and the per-kernel device seconds summed likewise.
#
# Usage: bench/walkthrough.sh [--out DIR] [--frames "6 24"] [--iterations N] [--size N] [--ratio C]
#                             [--scene NAME]
# Defaults: --frames "6 24", --iterations 256, --size 128, --ratio 1 (combined: PT samples per pixel
# per RB iteration), --scene cornell-box. A tiny check: --frames "2 3" --iterations 4 --size 16.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

out=""; frames="6 24"; iterations=256; size=128; ratio=1; scene=cornell-box
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    --frames) frames=$2; shift ;;
    --iterations) iterations=$2; shift ;;
    --size) size=$2; shift ;;
    --ratio) ratio=$2; shift ;;
    --scene) scene=$2; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "walkthrough.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
out=${out:-$bench_root/bench/results/walkthrough}
mkdir -p "$out"
: > "$out/log.txt"
scene_file=$(bench_scene "$scene")

# The default camera (position, forward) of a scene that is not a box, from a one-frame walk's stats.
camera_json=""
case $scene in
  cornell-*) ;;
  *) camera_json="$out/camera.json"
     "$BUNDLEPATH" render "$scene_file" --cameras all --mode pt --spp 1 --width 8 --height 8 --out "$out/camera" \
       --stats "$camera_json" 2>> "$out/log.txt" ;;
esac

# F keys: in a box from (0.278, 0.273, -0.8) to (0.278, 0.273, -0.2), swaying in x, each looking at
# the back wall; elsewhere from the default camera 1 m along its level view, swaying 0.2 m sideways.
write_path() {
  python3 - "$1" "$2" "$camera_json" <<'PY'
import json, math, sys
f = int(sys.argv[2])
keys = []
if sys.argv[3]:
    cam = json.load(open(sys.argv[3]))["frames"][0]
    p, d = cam["position"], cam["forward"]
    h = math.hypot(d[0], d[2])
    fx, fz = d[0] / h, d[2] / h  # the view, level
for k in range(f):
    s = k / max(1, f - 1)
    sway = (2 * s - 1) * (1 - s)
    if sys.argv[3]:
        pos = [p[0] + fx * s - fz * 0.2 * sway, p[1], p[2] + fz * s + fx * 0.2 * sway]
        keys.append({"position": pos, "target": [pos[i] + 5 * d[i] for i in range(3)], "up": [0, 1, 0],
                     "yfov": cam["yfov"]})
    else:
        x = 0.278 + 0.1 * sway
        keys.append({"position": [x, 0.273, -0.8 + 0.6 * s], "target": [0.278, 0.273, 0.56], "up": [0, 1, 0]})
json.dump(keys, open(sys.argv[1], "w"))
PY
}

# Seconds and summed kernel device seconds of the renders whose stats are given.
sum_stats() {
  python3 - "$@" <<'PY'
import json, sys
secs = dev = 0.0
for path in sys.argv[1:]:
    s = json.load(open(path))
    secs += s["render_seconds"]
    dev += sum(l["device_seconds"] for l in s.get("launches", {}).values())
print(f"{secs:.4f} {dev:.4f}")
PY
}

table="$out/walkthrough.md"
{
  echo "| mode | F | walk s | F renders s | walk s/frame | render s/frame | renders / walk | walk device s | renders device s |"
  echo "|---|---|---|---|---|---|---|---|---|"
} > "$table"
size_args=(--width "$size" --height "$size")
# Untimed first, each mode (its kernels are built with its own features): the kernel builds go to
# the caches, not to the first row.
for mode in rb combined; do
  "$BUNDLEPATH" render "$scene_file" --mode "$mode" --ratio "$ratio" --iterations 1 --width 16 --height 16 \
    --out "$out/warm" 2>> "$out/log.txt"
done
for mode in rb combined; do
  mode_args=(--mode "$mode")
  [ "$mode" = combined ] && mode_args+=(--ratio "$ratio")
  for f in $frames; do
    dir="$out/$mode-$f"
    rm -rf "$dir"
    mkdir -p "$dir"
    write_path "$dir/path.json" "$f"
    "$BUNDLEPATH" render "$scene_file" "${mode_args[@]}" --iterations "$iterations" "${size_args[@]}" \
      --camera-path "$dir/path.json" --out "$dir/walk" --stats "$dir/walk.json" 2>> "$out/log.txt"
    singles=()
    for k in $(seq 0 $((f - 1))); do
      # View k alone: a one-key path file holding key k.
      python3 -c "import json,sys; k=json.load(open(sys.argv[1])); json.dump([k[int(sys.argv[2])]], open(sys.argv[3], 'w'))" \
        "$dir/path.json" "$k" "$dir/key$k.json"
      "$BUNDLEPATH" render "$scene_file" "${mode_args[@]}" --iterations "$iterations" "${size_args[@]}" \
        --camera-path "$dir/key$k.json" --out "$dir/one$k" --stats "$dir/one$k.json" 2>> "$out/log.txt"
      singles+=("$dir/one$k.json")
    done
    for k in 0 $((f - 1)); do
      frame=$(printf "%s/walk_%04d.exr" "$dir" "$k")
      same=$("$BUNDLEPATH" compare "$frame" "$(printf "%s/one%d_0000.exr" "$dir" "$k")" --json |
             python3 -c "import json,sys; print(json.load(sys.stdin)['rel_mse'])")
      [ "$same" = "0.0" ] || { echo "walkthrough.sh: $mode F=$f frame $k differs from its render (relMSE $same)" >&2; exit 1; }
    done
    read -r walk_s walk_dev <<< "$(sum_stats "$dir/walk.json")"
    read -r one_s one_dev <<< "$(sum_stats "${singles[@]}")"
    python3 - "$mode" "$f" "$walk_s" "$one_s" "$walk_dev" "$one_dev" >> "$table" <<'PY'
import sys
mode, f, walk, one, walk_dev, one_dev = sys.argv[1], int(sys.argv[2]), *map(float, sys.argv[3:])
ratio = one / walk if walk > 0 else float("nan")
print(f"| {mode} | {f} | {walk:.3f} | {one:.3f} | {walk / f:.4f} | {one / f:.4f} | {ratio:.2f} | {walk_dev:.3f} | {one_dev:.3f} |")
PY
  done
done
cat "$table"
