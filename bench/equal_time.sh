#!/usr/bin/env bash
# Equal-time comparison (the paper's claim): PT alone, RB alone and the combination with both weight
# modes, both betas of the product weights and several ratios, without light sampling (the paper's
# estimators) and with it, each for the same wall time, against a long path-traced reference
# (bench/reference.sh, cached under ~/.cache/bundlepath/references). Prints a Markdown table and writes the paper's
# Figure 4 as bench-out/<scene>-contact-sheet.png.
# Usage: bench/equal_time.sh [SCENE] [SECONDS] [SIZE] [REFERENCE_SPP]   (SCENE: a name of bench_scene, e.g.
#        cornell-glossy or rooms-100000, or a path; SIZE: N for NxN or WxH, e.g. 640x360 [128];
#        REFERENCE_SPP: the reference's spp at 128x128, scaled to SIZE by bench_reference_spp [16384])
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
scene=$(bench_scene "${1:-cornell-glossy}")
seconds=${2:-30}
size=${3:-128}
ref_spp=$(bench_reference_spp "${4:-16384}" "$size")
name=$(bench_scene_name "$scene")
mapfile -t wh < <(bench_size_args "$size")
sheet=bench-out/$name-contact-sheet.png
[ "${wh[1]}" = 128 ] && [ "${wh[3]}" = 128 ] || sheet=bench-out/$name-${wh[1]}x${wh[3]}-contact-sheet.png
mkdir -p bench-out
ref=$(bench_reference "$scene" "$ref_spp" "$size")
ref=${ref%.exr}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # label, then render options
  local label=$1; shift
  bench_render "$scene" "${wh[@]}" --time "$seconds" --reference "$ref.exr" \
    --out "$tmp/img" --stats "$tmp/s.json" "$@" 2>/dev/null
  python3 - "$label" "$tmp/s.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2]))
m = s["reference"]["layers"]["combined"]
work = f"{s['spp']} spp" + (f" + {s['iterations']} it" if s.get("iterations") else "")
if "ratio_auto" in s:
    c = float(s["ratio"])  # "inf": the path tracer alone
    work += f" (auto: c = {c:g})" if c >= 1 else f" (auto: c = 1/{1 / c:g})"
print(f"| {sys.argv[1]} | {work} | {m['rel_mse']:.5f} | {m['rmse']:.4f} | {m['mean_bias']:+.4f} | {1/(m['rel_mse']*s['render_seconds']):.1f} |")
PY
}
echo "| method | work done in ${seconds} s | relMSE | RMSE | mean bias | efficiency 1/(relMSE·s) |"
echo "|---|---|---|---|---|---|"
# The paper's setting: neither estimator samples the lights.
run "PT, no light sampling" --mode pt --no-light-sampling
run "RB (\`--mode rb\`)" --mode rb
for ratio in 1 1/4 1/16; do
  run "combined, product weights, ratio $ratio, no light sampling" --mode combined --weights product --ratio $ratio \
    --no-light-sampling
done
run "combined, product weights with \`--beta balance\`, ratio 1/4, no light sampling" --mode combined --beta balance \
  --ratio 1/4 --no-light-sampling
for ratio in 1 1/4; do
  run "combined, paper weights, ratio $ratio" --mode combined --weights paper --ratio $ratio
done
# With light sampling (docs/design.md §3), the default.
run "PT (\`--mode pt\`)" --mode pt
for ratio in 4 1 1/4 1/16; do
  run "combined, product weights, ratio $ratio" --mode combined --weights product --ratio $ratio
done
run "combined, product weights, \`--ratio auto\` (the default)" --mode combined --weights product --ratio auto
run "combined, product weights with \`--beta balance\`, ratio 1/4" --mode combined --beta balance --ratio 1/4
bench_render "$scene" "${wh[@]}" --time "$seconds" --mode combined --ratio 1/4 --no-light-sampling \
  --reference "$ref.exr" --contact-sheet "$sheet" --out "$tmp/sheet" 2>/dev/null
echo
echo "(${wh[1]}x${wh[3]}, reference ${ref_spp} spp; $("$BUNDLEPATH" devices | head -1))"
