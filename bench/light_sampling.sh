#!/usr/bin/env bash
# Light sampling at equal time (issue #7): relMSE of PT, RB and the combination with and without
# light sampling on SCENE at 2, 6 and 30 s, against a long path-traced reference
# (bench/reference.sh), beside Blender Cycles' figures for the diffuse Cornell box at 128x128 on
# this 2-core machine (1.7 s -> 0.0019, 6.3 s -> 0.0004; given in the issue, not measured here).
# Prints a Markdown table.
# Usage: bench/light_sampling.sh [SCENE] [SIZE] [REFERENCE_SPP] [SECONDS...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
scene=${1:-scenes/cornell-box.gltf}
size=${2:-128}
ref_spp=${3:-16384}
shift $(( $# < 3 ? $# : 3 ))
budgets=("$@")
[ ${#budgets[@]} -gt 0 ] || budgets=(2 6 30)
ref=$(bench_reference "$scene" "$ref_spp" "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
relmse() {  # seconds, then render options: prints relMSE of the combined image
  local seconds=$1; shift
  bench_render "$scene" --width "$size" --height "$size" --time "$seconds" --reference "$ref" \
    --out "$tmp/img" --stats "$tmp/s.json" "$@" 2>/dev/null
  python3 -c 'import json,sys; print("%.5f" % json.load(open(sys.argv[1]))["reference"]["layers"]["combined"]["rel_mse"])' "$tmp/s.json"
}
header="| method |" rule="|---|"
for s in "${budgets[@]}"; do header+=" $s s |"; rule+="---|"; done
echo "$header"
echo "$rule"
row() {  # label, then render options
  local label=$1 line; shift
  line="| $label |"
  for s in "${budgets[@]}"; do line+=" $(relmse "$s" "$@") |"; done
  echo "$line"
}
row "PT with light sampling (\`--mode pt\`)" --mode pt
row "PT without (\`--mode pt --no-light-sampling\`)" --mode pt --no-light-sampling
row "RB (\`--mode rb\`)" --mode rb
row "combined with light sampling (\`--mode combined\`)" --mode combined
row "combined without (\`--mode combined --no-light-sampling\`)" --mode combined --no-light-sampling
echo
echo "(${size}x${size}, relMSE against a ${ref_spp}-spp path-traced reference; $("$BUNDLEPATH" devices | head -1))"
echo "Blender Cycles (from issue #7, same machine, 2 threads): 0.0019 at 1.7 s, 0.0004 at 6.3 s."
