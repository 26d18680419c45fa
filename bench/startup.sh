#!/usr/bin/env bash
# Cold and warm start of `bundlepath render`: the first run compiles the kernels (empty kernel
# and PoCL caches), the second finds them in the caches. Prints kernel build and total wall time.
# Usage: bench/startup.sh [SCENE]   (BUNDLEPATH=... picks the binary, see bench/lib.sh)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
scene=${1:-$bench_root/scenes/cornell-box.gltf}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export BUNDLEPATH_CACHE_DIR=$tmp/kernels POCL_CACHE_DIR=$tmp/pocl
for run in cold warm; do
  start=$(date +%s.%N)
  bench_render "$scene" --width 64 --height 64 --spp 1 --out "$tmp/img" --stats "$tmp/$run.json" 2>/dev/null
  end=$(date +%s.%N)
  python3 - "$tmp/$run.json" "$run" "$start" "$end" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]:5s} start: kernel build {s['kernel_build_seconds']:.3f} s, whole run {float(sys.argv[4]) - float(sys.argv[3]):.3f} s (from cache: {s['kernel_from_cache']}) on {s['device']}")
PY
done
