#!/usr/bin/env bash
# The conventions check of issue 29: on the Cornell box, each peer's long-ish render must agree with
# bundlepath's own path-traced reference in image mean within 1 %, so that a difference in the
# peers' table is never one of scene conventions (camera, units, emitters' sides, materials).
# Renders Cycles (light tree, with and without guiding), LuxCore (DLS cache, no PhotonGI: its cache
# is biased by design) and, as a control, bundlepath --mode pt, each for BUDGET seconds at SIZE, and
# writes bench/peers/results/conventions-<scene>-<date>.md. Exit 1 when a mean is off by more than 1 %.
#
#   bash bench/peers/check_conventions.sh [--size 128x128] [--budget 30] [--ref-spp 4096]
#                                         [--scene cornell-box] [--threads 1] [--results FILE.md]
#
# --scene takes what run.sh takes, and cornell-two-sided: the Cornell box with its light double-sided
# and lowered 0.15 m (bench/peers/cornell_two_sided.py), for the emitters' back faces. The sun, a
# point light and a texture: --scene scenes/blender-room.glb --size 128x96.
#
# At 128x128 and 30 s each, the means of the renders are within about 0.1 % of the reference
# (Cycles about 450 spp, LuxCore about 300), far inside the 1 % bar. Needs bench/peers/setup.sh.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
size=128x128
budget=30
ref_spp=4096
scene=cornell-box
threads=1
results=
while [ $# -gt 0 ]; do
  case $1 in
    --size) size=$2; shift 2 ;;
    --budget) budget=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --results) results=$2; shift 2 ;;
    -h|--help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "check_conventions.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ "$scene" = cornell-two-sided ]; then  # the Cornell box with a double-sided light, lowered
  mkdir -p "$here/../../bench-out/peers/scenes"
  scene=$(cd "$here/../.." && pwd)/bench-out/peers/scenes/cornell-two-sided.gltf
  python3 "$here/cornell_two_sided.py" "$scene"
fi
tag=$(basename "${scene%.*}")
results=${results:-$here/results/conventions-$tag-$(date -u +%Y-%m-%d).md}
exec bash "$here/run.sh" --scene "$scene" --sizes "$size" --budgets "$budget" --ref-spp "$ref_spp" \
  --threads "$threads" --renderers bp-pt,cycles,cycles-guiding,luxcore --max-mean-rel 0.01 \
  --out "${PEERS_OUT:-$here/../../bench-out/peers/conventions-$tag}" --results "$results" \
  --label "conventions check (image mean within 1 %)"
