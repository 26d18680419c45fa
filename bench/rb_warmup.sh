#!/usr/bin/env bash
# How much image level RB loses without a warm-up: iteration t only carries paths of up to t
# bounces, so a short run that starts from zero radiance is biased low. Compares the mean level of
# short runs (several seeds) with a long run, for several warm-up lengths. Prints a Markdown table.
# Usage: bench/rb_warmup.sh [SCENE]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
scene=${1:-scenes/cornell-box.gltf}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
size=64
bench_render "$scene" --mode rb --width $size --height $size --iterations 20000 --warmup 64 --seed 99 \
  --out "$tmp/long" 2>/dev/null
echo "| iterations | warm-up | mean level vs 20000-iteration run (8 seeds) | extra time |"
echo "|---|---|---|---|"
for n in 50 200 1000; do
  for w in 0 4 16 64; do
    rel=()
    for seed in 1 2 3 4 5 6 7 8; do
      bench_render "$scene" --mode rb --width $size --height $size --iterations $n --warmup $w --seed $seed \
        --out "$tmp/s" 2>/dev/null
      rel+=("$("$BUNDLEPATH" compare "$tmp/s.exr" "$tmp/long.exr" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["relative_bias"])')")
    done
    python3 - "$n" "$w" "${rel[@]}" <<'PY'
import statistics, sys
n, w, r = int(sys.argv[1]), int(sys.argv[2]), [float(x) for x in sys.argv[3:]]
m, se = statistics.mean(r), statistics.stdev(r) / len(r) ** 0.5
print(f"| {n} | {w} | {100*m:+.2f} % ± {100*se:.2f} % | {100*w/n:.0f} % |")
PY
  done
done
