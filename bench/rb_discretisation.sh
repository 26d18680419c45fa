#!/usr/bin/env bash
# RB's discretisation error on the Cornell box: --mode rb at shrinking patch sizes against a long
# path-traced reference (cached under ~/.cache/bundlepath/references). Prints a Markdown table.
# Usage: [SCENE=scenes/cornell-ggx.gltf] bench/rb_discretisation.sh [ITERATIONS] [REFERENCE_SPP] [SIZE]
#        (defaults: scenes/cornell-box.gltf, 20000, 32768, 64)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
iterations=${1:-20000}
ref_spp=${2:-32768}
scene=${SCENE:-scenes/cornell-box.gltf}
size=${3:-64}
ref=$(bench_reference "$scene" "$ref_spp" "$size")
ref=${ref%.exr}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| patch size (m) | patches | bins | relMSE | mean \|RB − PT\| / mean PT | bias | s |"
echo "|---|---|---|---|---|---|---|"
for ps in 0.1 0.05 0.025 0.0125; do
  bench_render $scene --mode rb --width $size --height $size --iterations "$iterations" \
    --patch-size "$ps" --out "$tmp/rb" --stats "$tmp/rb.json" 2>/dev/null
  "$BUNDLEPATH" compare "$tmp/rb.exr" "$ref.exr" --json > "$tmp/cmp.json"
  python3 - "$ps" "$tmp/rb.json" "$tmp/cmp.json" <<'PY'
import json, sys
s, c = json.load(open(sys.argv[2])), json.load(open(sys.argv[3]))
print(f"| {sys.argv[1]} | {s['patches']} | {s['bins']} | {c['rel_mse']:.4f} | {100*c['relative_mean_abs_difference']:.1f} % "
      f"| {100*c['relative_bias']:+.1f} % | {s['render_seconds']:.0f} |")
PY
done
# The reference's own noise: a second, independent path-traced image of the same spp against it.
bench_render $scene --mode pt --width $size --height $size --spp "$ref_spp" --seed 8 --out "$tmp/pt" \
  --stats "$tmp/pt.json" 2>/dev/null
"$BUNDLEPATH" compare "$tmp/pt.exr" "$ref.exr" --json > "$tmp/cmp.json"
python3 - "$tmp/pt.json" "$tmp/cmp.json" <<'PY'
import json, sys
s, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
print(f"| PT vs PT (noise floor) | – | – | {c['rel_mse']:.4f} | {100*c['relative_mean_abs_difference']:.1f} % "
      f"| {100*c['relative_bias']:+.1f} % | {s['render_seconds']:.0f} |")
PY
echo "(${iterations} RB iterations per row, reference ${ref_spp} spp, ${size}x${size}; $("$BUNDLEPATH" devices | head -1))"
