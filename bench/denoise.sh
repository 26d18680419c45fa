#!/usr/bin/env bash
# Which mode gives the lowest error after denoising, at equal wall time, against Cycles 5 with its
# OpenImageDenoise (what Blender users render finals with). Each bundlepath mode renders with
# --denoise (OIDN with albedo and normal, inside --time), so one render gives the denoised image and
# its raw one (the EXR's raw layer); Cycles renders --time seconds of sampling, its denoise after
# (bench/peers/cycles_peer.py --denoise). Two seeds of each; bench/error_split.py splits each error
# into variance, bias and the reference's own noise (from the path tracer's raw pair) and judges
# 8x8-pixel blocks.
#
#   bash bench/denoise.sh [--scene NAME] [--size WxH] [--budget S] [--ref-spp N] [--modes "..."]
#                         [--no-cycles] [--reuse] [--out DIR]
#
# Defaults: rooms-lambert-100000, 640x360, 30 s, a 2048-spp reference (bench/lib.sh caches it), the
# modes "default ratio=1/32 regional pt rb" (default: as it ships, which with --denoise is the path
# tracer alone; ratio=C: the combination at --ratio C, the consistent level; regional: --rb-level
# regional at --ratio auto's choice; pt: --mode pt; rb: --mode rb). Needs the
# peers' venv (bench/peers/setup.sh) and OIDN (scripts/setup.sh --oidn). Prints a Markdown table.
# --reuse keeps the renders already in --out (an interrupted run goes on).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
scene_name=rooms-lambert-100000 size=640x360 budget=30 ref_spp=2048 modes="default ratio=1/32 regional pt rb" cycles=1 reuse=0
out=$bench_root/bench-out/denoise
while [ $# -gt 0 ]; do
  case $1 in
    --scene) scene_name=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --budget) budget=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --modes) modes=$2; shift 2 ;;
    --no-cycles) cycles=0; shift ;;
    --reuse) reuse=1; shift ;;
    --out) out=$2; shift 2 ;;
    *) echo "denoise.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
venv=$(bash "$here/peers/setup.sh" 2>/dev/null | tail -n 1)
py=$venv/bin/python
scene=$(bench_scene "$scene_name")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
mapfile -t wh < <(bench_size_args "$size")
mkdir -p "$out"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%F %H:%M') UTC; $(nproc) cores" >&2
for seed in 1 2; do
  for m in $modes; do
    case $m in
      default) extra=() ;;
      regional) extra=(--rb-level regional --ratio 1/32) ;;
      pt) extra=(--mode pt) ;;
      rb) extra=(--mode rb) ;;
      ratio=*) extra=(--ratio "${m#ratio=}") ;;
      *) echo "denoise.sh: unknown mode $m" >&2; exit 2 ;;
    esac
    stem=$out/${m//\//_}-s$seed  # ratio=1/32 -> ratio=1_32
    [ "$reuse" -eq 1 ] && [ -f "$stem.exr" ] && continue
    bench_render "$scene" "${wh[@]}" --time "$budget" --seed "$seed" --denoise "${extra[@]}" \
      --out "$stem" --stats "$stem.json" 2> "$stem.log"
  done
  if [ "$cycles" -eq 1 ]; then
    [ "$reuse" -eq 1 ] && [ -f "$out/cycles-s$seed.exr" ] && continue
    OCL_ICD_VENDORS=/nonexistent "$py" "$here/peers/cycles_peer.py" "$scene" "$out/cycles-s$seed" "${wh[@]}" \
      --time "$budget" --threads "$(nproc)" --seed "$seed" --denoise > "$out/cycles-s$seed.log" 2>&1
  fi
done
pt_pair=()
for m in $modes; do [ "$m" = pt ] && pt_pair=(--pt "$out/pt-s1.exr" "$out/pt-s2.exr"); done
first=--header
for m in $modes; do
  for layer in RGB raw; do
    label="$m $([ $layer = RGB ] && echo '+ OIDN' || echo raw)"
    "$py" "$here/error_split.py" "$ref" --images "$out/${m//\//_}-s1.exr" "$out/${m//\//_}-s2.exr" "${pt_pair[@]}" \
      --layer "$layer" --label "$label" $first
    first=
  done
done
if [ "$cycles" -eq 1 ]; then
  "$py" "$here/error_split.py" "$ref" --images "$out/cycles-s1.exr" "$out/cycles-s2.exr" "${pt_pair[@]}" \
    --label "Cycles 5 + OIDN"
fi
echo "reference: $ref ($ref_spp spp); load average after: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
