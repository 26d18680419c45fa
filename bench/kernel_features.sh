#!/usr/bin/env bash
# Specialised against generic kernels (issue #5, "model only what a scene needs"): each program is
# built with only the features the render uses (-DBP_FEATURE_PHONG, -DBP_FEATURE_LIGHT_SAMPLING;
# host/device/kernel_features.h) or with all of them (--kernels generic). For each case: cold build
# time (no binary cache), render time of a fixed amount of work (the two builds alternate, best of
# REPEATS), and the device memory the run holds. Prints a Markdown table.
# Usage: bench/kernel_features.sh [SIZE] [REPEATS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
size=${1:-128}
repeats=${2:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d.get(sys.argv[2], 0))' "$@"; }
measure() {  # kernels, then render options: prints "build_s render_s bytes options"
  local kernels=$1; shift
  BUNDLEPATH_CACHE_DIR=off POCL_KERNEL_CACHE=0 bench_render "$@" --kernels "$kernels" --width "$size" \
    --height "$size" --out "$tmp/img" --stats "$tmp/cold.json" 2>/dev/null
  local best=""
  for _ in $(seq "$repeats"); do
    bench_render "$@" --kernels "$kernels" --width "$size" --height "$size" --out "$tmp/img" --stats "$tmp/s.json" 2>/dev/null
    local t; t=$(field "$tmp/s.json" render_seconds)
    best=$(python3 -c "print(min(float('$t'), float('${best:-inf}')))")
  done
  local bytes; bytes=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["scene_device_bytes"] + d.get("rb_device_bytes_estimate", 0))' "$tmp/s.json")
  echo "$(field "$tmp/cold.json" kernel_build_seconds) $best $bytes $(field "$tmp/s.json" kernel_options)"
}
echo "| scene, mode | switches of the specialised build | cold build generic → specialised (s) | render generic → specialised (s) | speed-up | device memory (MiB) |"
echo "|---|---|---|---|---|---|"
row() {  # label, then render options
  local label=$1; shift
  read -r bg rg mem _ < <(measure generic "$@")
  read -r bs rs _ opts < <(measure specialised "$@")
  python3 - "$label" "${opts:-}" "$bg" "$bs" "$rg" "$rs" "$mem" <<'PY'
import sys
label, opts, bg, bs, rg, rs, mem = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:])
print(f"| {label} | `{opts}` | {bg:.2f} → {bs:.2f} | {rg:.3f} → {rs:.3f} | {rg / rs:.2f}x | {mem / 2**20:.1f} |")
PY
}
row "cornell-box (Lambert), pt" scenes/cornell-box.gltf --mode pt --spp 64
row "cornell-box (Lambert), pt, no light sampling" scenes/cornell-box.gltf --mode pt --spp 64 --no-light-sampling
row "cornell-box (Lambert), combined" scenes/cornell-box.gltf --mode combined --spp 32
row "cornell-glossy, combined" scenes/cornell-glossy.gltf --mode combined --spp 32
row "cornell-glossy, rb" scenes/cornell-glossy.gltf --mode rb --iterations 200
echo
echo "(${size}x${size}, best of $repeats renders; memory: scene buffers + the ray-bundle pass's estimate; $("$BUNDLEPATH" devices | head -1))"
