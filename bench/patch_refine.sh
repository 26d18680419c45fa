#!/usr/bin/env bash
# --patch-refine against a small shadow: the Blender room (scenes/blender-room.glb), whose sphere
# stands on the floor under a point light, at 320x180 and fixed work (--ratio 1/4, 512 spp + 2048
# iterations, where the ray bundles carry much of the image), with --patch-refine off and on, at
# two seeds, against a 4096-spp path-traced reference: the errors over 4-, 8- and 16-pixel boxes and
# at the sphere's contact shadow (bench/box_errors.py). Prints a markdown table.
#
#   bash bench/patch_refine.sh [--seeds "1 2"] [--at X,Y]
#
# Not part of CI. Needs numpy and OpenEXR (PYTHON, default the peers' venv: bench/peers/setup.sh).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
seeds="1 2" at=216,140
while [ $# -gt 0 ]; do
  case $1 in
    --seeds) seeds=$2; shift 2 ;;
    --at) at=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "patch_refine.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
PYTHON=${PYTHON:-$bench_root/bench-out/peers-venv/bin/python}
cd "$bench_root"
ref=$(bench_reference scenes/blender-room.glb 4096 320x180)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
images=()
for refine in off on; do
  for seed in $seeds; do
    start=$(date +%s.%N)
    bench_render scenes/blender-room.glb --width 320 --height 180 --ratio 1/4 --iterations 2048 --seed "$seed" \
      --patch-refine "$refine" --out "$tmp/refine-$refine-seed$seed" --stats "$tmp/s.json" 2>/dev/null
    python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(f'refine $refine, seed $seed: {s[\"patches\"]} patches, {s[\"bins\"]} bins, {s[\"render_seconds\"]:.1f} s')" "$tmp/s.json"
    images+=("$tmp/refine-$refine-seed$seed.exr")
  done
done
echo
"$PYTHON" bench/box_errors.py "$ref" "${images[@]}" --at "$at"
echo
echo "(reference: $(basename "$ref"); $("$BUNDLEPATH" devices 2>/dev/null | head -1); $(date -u +%Y-%m-%d))"
