#!/usr/bin/env bash
# Does the combination converge to the true image? The same render at growing work (fixed --ratio,
# --spp N, so the figures do not depend on the machine's speed), two seeds each, under each
# --rb-level; bench/error_split.py splits each error into variance, squared bias and the reference's
# own noise (from two --mode pt renders at the largest count) and judges 8x8-pixel blocks. A
# consistent level's squared bias falls with the work; a biased one's stays.
#
#   bash bench/consistency.sh [--scene NAME] [--size WxH] [--ratio C] [--spps "64 512 4096"]
#                             [--levels "consistent regional"] [--ref-spp N] [--out DIR]
#
# Defaults: cornell-box at 64x64, --ratio 1/4, 64, 512 and 4096 spp, a 65536-spp reference
# (bench/lib.sh caches it). Needs the peers' venv for numpy and OpenEXR (bench/peers/setup.sh).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
scene_name=cornell-box size=64x64 ratio=1/4 spps="64 512 4096" levels="consistent regional" ref_spp=65536
out=$bench_root/bench-out/consistency
while [ $# -gt 0 ]; do
  case $1 in
    --scene) scene_name=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --ratio) ratio=$2; shift 2 ;;
    --spps) spps=$2; shift 2 ;;
    --levels) levels=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "consistency.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
py=$(bash "$here/peers/setup.sh" 2>/dev/null | tail -n 1)/bin/python
scene=$(bench_scene "$scene_name")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
mapfile -t wh < <(bench_size_args "$size")
mkdir -p "$out"
last=${spps##* }
for seed in 1 2; do
  bench_render "$scene" "${wh[@]}" --mode pt --spp "$last" --seed "$seed" --out "$out/pt-s$seed" 2> /dev/null
  for spp in $spps; do
    for level in $levels; do
      bench_render "$scene" "${wh[@]}" --ratio "$ratio" --spp "$spp" --seed "$seed" --rb-level "$level" \
        --out "$out/$level-$spp-s$seed" 2> /dev/null
    done
  done
done
first=--header
for level in $levels; do
  for spp in $spps; do
    "$py" "$here/error_split.py" "$ref" --images "$out/$level-$spp-s1.exr" "$out/$level-$spp-s2.exr" \
      --pt "$out/pt-s1.exr" "$out/pt-s2.exr" --label "$level, $spp spp" $first
    first=
  done
done
"$py" "$here/error_split.py" "$ref" --images "$out/pt-s1.exr" "$out/pt-s2.exr" --pt "$out/pt-s1.exr" \
  "$out/pt-s2.exr" --label "pt, $last spp"
echo "reference: $ref ($ref_spp spp)" >&2
