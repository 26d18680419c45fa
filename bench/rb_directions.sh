#!/usr/bin/env bash
# What stratified iteration directions (--rb-directions, passes/bundle_directions.h) do to the image
# level of a short render: SEEDS renders per sequence at equal work (ITERATIONS RB iterations, the
# combination at --ratio 1/4, so as many PT samples per pixel as iterations / 4), the image mean of each
# against a path-traced reference, and the spread of those levels between seeds. Equal work, so the
# figures do not depend on the machine or its load.
# Usage: bench/rb_directions.sh [SCENE] [SIZE] [ITERATIONS] [SEEDS] [REFERENCE_SPP]
#        defaults: rooms-lambert-100000 160x90 144 8 4096
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
if [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then sed -n '2,8p' "$0"; exit 2; fi
cd "$bench_root"
scene=$(bench_scene "${1:-rooms-lambert-100000}")
size=${2:-160x90}
iterations=${3:-144}
seeds=${4:-8}
ref_spp=${5:-4096}
mapfile -t wh < <(bench_size_args "$size")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| --rb-directions | image level vs reference, seeds 1–$seeds | mean | spread between seeds (SD) |"
echo "|---|---|---|---|"
for sequence in independent stratified; do
  for ((seed = 1; seed <= seeds; ++seed)); do
    bench_render "$scene" "${wh[@]}" --mode combined --ratio 1/4 --iterations "$iterations" --seed "$seed" \
      --rb-directions "$sequence" --reference "$ref" --out "$tmp/img" --stats "$tmp/$sequence-$seed.json" 2>/dev/null
  done
  python3 - "$sequence" "$tmp"/"$sequence"-*.json <<'PY'
import json, statistics, sys
levels = [json.load(open(p))["reference"]["layers"]["combined"]["relative_bias"] for p in sys.argv[2:]]
print(f"| {sys.argv[1]} | {' '.join(f'{100 * x:+.2f}' for x in levels)} % | {100 * statistics.mean(levels):+.2f} % "
      f"| {100 * statistics.stdev(levels):.2f} % |")
PY
done
echo
echo "($(basename "$scene") at $size, $iterations iterations and $((iterations / 4)) spp per render; reference $(basename "$ref"))"
