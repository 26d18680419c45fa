#!/usr/bin/env bash
# Issue #16: is the error estimate right? Renders each scene with --mode pt, rb and combined at a
# short and a long budget (one seed) and prints the relMSE the render estimated of itself
# ("estimated_rel_mse", docs/design.md §9) beside the relMSE measured against a path-traced reference
# (cached, bench/lib.sh), the reference's own noise (its estimated relMSE, which every measured value
# contains), the variance measured from a second render with another seed and the same work
# (E[(I1 − I2)²] = 2 Var, so it holds no bias), and what is left, measured − reference noise −
# estimated: RB's discretisation bias, which no variance sees. Also the blocking check of RB's batch length: the estimate from batches of
# 64, 128, 256, 512 iterations of the same long rb render (--error-levels), and the lag-1
# autocorrelation of consecutive 64- and 128-iteration batch means it implies,
# rho1(b) = est(2b)/est(b) − 1. Then --target-error on each scene (pt and combined), stopped with
# the measured relMSE it reached. Writes OUT/error-estimate.md, OUT/error-estimate.csv and a
# scatter plot OUT/error-estimate.png (estimated against measured, log-log; gnuplot).
# Usage: bench/error_estimate.sh [SIZE] [SHORT_SECONDS] [LONG_SECONDS] [TARGET] [OUT] [SCENES...]
#        defaults: 128 4 16 0.001 bench/results  cornell-box cornell-glossy rooms-lambert-100000:20:80
#        (a scene NAME:SHORT:LONG has budgets of its own: an RB iteration of the house costs about
#        30 ms at 128x128, so 12 s would give it 5 batches of 64 iterations)
#        (scene reference spp from BENCH_STUDY_SCENES: 16384 for the boxes, 8192 for the house)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
if [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then sed -n '2,18p' "$0"; exit 2; fi
cd "$bench_root"
size=${1:-128}
short_default=${2:-4}
long_default=${3:-16}
target=${4:-0.001}
out=${5:-bench/results}
shift $(($# < 5 ? $# : 5))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-box cornell-glossy rooms-lambert-100000:20:80)
mkdir -p "$out"
mapfile -t wh < <(bench_size_args "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
csv=$out/error-estimate.csv
echo "scene,mode,budget,work,batches,estimated,measured,reference_noise,bias_left,ratio,two_seed_variance,ratio_to_variance" > "$csv"
blocking=$tmp/blocking.md
targets=$tmp/targets.md
: > "$blocking"
: > "$targets"

ref_spp_of() {  # the study's reference spp of a scene name (bench/lib.sh), 16384 if not listed
  local entry
  for entry in "${BENCH_STUDY_SCENES[@]}"; do
    if [ "${entry% *}" = "$1" ]; then echo "${entry#* }"; return; fi
  done
  echo 16384
}

for spec in "${scenes[@]}"; do
  IFS=: read -r name short long <<< "$spec"
  short=${short:-$short_default}
  long=${long:-$long_default}
  scene=$(bench_scene "$name")
  ref=$(bench_reference "$scene" "$(bench_reference_spp "$(ref_spp_of "$name")" "$size")" "$size")
  for mode in pt rb combined; do
    for budget in "$short" "$long"; do
      levels=()
      if [ "$mode" = rb ] && [ "$budget" = "$long" ]; then levels=(--error-levels 4); fi
      bench_render "$scene" "${wh[@]}" --mode "$mode" --time "$budget" --seed 1 --reference "$ref" "${levels[@]}" \
        --out "$tmp/img" --stats "$tmp/s.json" 2>/dev/null
      # The same work with seed 2 (counts, not time; combined at the ratio and eye-direct choice seed 1 made).
      mapfile -t same < <(python3 - "$mode" "$tmp/s.json" <<'PY'
import json, sys
mode, s = sys.argv[1], json.load(open(sys.argv[2]))
if mode == "pt":
    print("--spp"); print(s["spp"])
elif mode == "rb":
    print("--iterations"); print(s["iterations"])
else:
    c = float(s["ratio"])  # "inf": auto chose the path tracer alone, and chooses it again at these counts
    print("--ratio"); print("auto" if c == float("inf") else f"{round(c)}" if c >= 1 else f"1/{round(1 / c)}")
    print("--spp"); print(s["spp"])
    if "eye_direct" in s:
        print("--eye-direct"); print(s["eye_direct"])
PY
)
      bench_render "$scene" "${wh[@]}" --mode "$mode" --seed 2 "${same[@]}" --out "$tmp/img2" 2>/dev/null
      "$BUNDLEPATH" compare "$tmp/img.exr" "$tmp/img2.exr" --json > "$tmp/c12.json"
      "$BUNDLEPATH" compare "$tmp/img2.exr" "$tmp/img.exr" --json > "$tmp/c21.json"
      python3 - "$name" "$mode" "$budget" "$tmp/s.json" "${ref%.exr}.json" "$csv" "$blocking" "$tmp" <<'PY'
import json, math, os, sys
name, mode, budget, stats_path, ref_stats, csv, blocking, tmp = sys.argv[1:]
s = json.load(open(stats_path))
# (I1 − I2)² / 2 over (I² + 0.01), each image the other's denominator once: the variance one render has.
two_seed = 0.25 * (json.load(open(os.path.join(tmp, "c12.json")))["rel_mse"] +
                   json.load(open(os.path.join(tmp, "c21.json")))["rel_mse"])
# The reference's own noise: its own estimate; a reference rendered before issue #16 has none, and
# then it is a PT render's estimate scaled by spp / reference spp (relMSE ∝ 1/N), kept per scene.
ref = json.load(open(ref_stats))
noise_file = os.path.join(tmp, f"ref-noise-{name}")
ref_noise = ref.get("estimated_rel_mse")
if ref_noise is None and mode == "pt" and s["estimated_rel_mse"]:
    ref_noise = s["estimated_rel_mse"] * s["spp"] / ref["spp"]
    open(noise_file, "w").write(repr(ref_noise))
if ref_noise is None:
    ref_noise = float(open(noise_file).read()) if os.path.exists(noise_file) else 0.0
est = s["estimated_rel_mse"]
meas = s["reference"]["layers"]["combined"]["rel_mse"]
work = f"{s['spp']} spp" + (f" + {s['iterations']} it" if s.get("iterations") else "")
left = meas - ref_noise - (est or 0.0)
ratio = est / (meas - ref_noise) if est and meas > ref_noise else float("nan")
with open(csv, "a") as f:
    est_text = f"{est:.6g}" if est is not None else "nan"  # fewer than two batches: no estimate
    to_var = est / two_seed if est and two_seed > 0 else float("nan")
    batches = "/".join(str(l["batches"]) for l in s["error_estimate"]["layers"])  # PT/RB for the combination
    f.write(f"{name},{mode},{budget},{work},{batches},{est_text},{meas:.6g},{ref_noise:.3g},{left:.3g},{ratio:.3f},"
            f"{two_seed:.6g},{to_var:.3f}\n")
if mode == "rb" and len(s["error_estimate"]["levels"]) > 1:
    lv = s["error_estimate"]["layers"][0]["levels"]
    e = [l["estimated_rel_mse"] or float("nan") for l in lv]
    rho = [e[j + 1] / e[j] - 1 for j in range(len(e) - 1) if e[j] and e[j + 1]]
    with open(blocking, "a") as f:
        f.write(f"| {name} | {s['iterations']} | " + " | ".join(f"{x:.3g} ({l['batches']})" for x, l in zip(e, lv)) +
                " | " + " / ".join(f"{r:+.2f}" for r in rho[:2]) + " |\n")
PY
    done
  done
  for mode in pt combined; do
    bench_render "$scene" "${wh[@]}" --mode "$mode" --target-error "$target" --time $((4 * long < 60 ? 4 * long : 60)) --seed 2 \
      --reference "$ref" --out "$tmp/img" --stats "$tmp/s.json" 2>/dev/null
    python3 - "$name" "$mode" "$tmp/s.json" "${ref%.exr}.json" "$tmp" >> "$targets" <<'PY'
import json, os, sys
name, mode, path, ref_stats, tmp = sys.argv[1:]
s = json.load(open(path))
ref_noise = json.load(open(ref_stats)).get("estimated_rel_mse")
noise_file = os.path.join(tmp, f"ref-noise-{name}")
if ref_noise is None:
    ref_noise = float(open(noise_file).read()) if os.path.exists(noise_file) else 0.0
work = f"{s['spp']} spp" + (f" + {s['iterations']} it" if s.get("iterations") else "")
meas = s["reference"]["layers"]["combined"]["rel_mse"]
print(f"| {name} | {mode} | {s['target_error']:g} | {'yes' if s['target_reached'] else 'no (time cap)'} | {work}, "
      f"{s['render_seconds']:.1f} s | {s['estimated_rel_mse'] or float('nan'):.3g} | {meas:.3g} | {meas - ref_noise:.3g} |")
PY
  done
done

{
  echo "| scene | mode | budget (s) | work done | batches K (combined: PT/RB) | estimated relMSE | measured relMSE (vs reference) | reference's own noise | estimated / (measured − noise) | measured − noise − estimated | variance from two seeds | estimated / two-seed variance |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  tail -n +2 "$csv" | while IFS=, read -r sc mo bu wo k es me rn le ra tv rv; do
    echo "| $sc | $mo | $bu | $wo | $k | $es | $me | $rn | $ra | $le | $tv | $rv |"
  done
  echo
  echo "Blocking check of RB's batch length (the long \`--mode rb\` render, \`--error-levels 4\`): estimated relMSE (batches)"
  echo
  echo "| scene | iterations | 64 it | 128 it | 256 it | 512 it | lag-1 autocorrelation of 64- / 128-it batch means |"
  echo "|---|---|---|---|---|---|---|"
  cat "$blocking"
  echo
  echo "\`--target-error $target\` (cap: --time 4 × the long budget, at most 60 s; seed 2):"
  echo
  echo "| scene | mode | target | reached | work, time | estimated relMSE | measured relMSE | measured − reference noise |"
  echo "|---|---|---|---|---|---|---|---|"
  cat "$targets"
  echo
  echo "(${size}, one seed; references: path-traced, bench/lib.sh; $("$BUNDLEPATH" devices 2>/dev/null | head -1 | sed 's/^ *//'))"
  echo "(command: bash bench/error_estimate.sh $size $short_default $long_default $target $out ${scenes[*]})"
} > "$out/error-estimate.md"
cat "$out/error-estimate.md"

if command -v gnuplot >/dev/null; then
  dat=$out/error-estimate.dat
  tail -n +2 "$csv" | awk -F, '{ printf "%s-%s-%ss %s %s %s %s\n", $1, $2, $3, $6, $7 - $8, $2, $11 }' > "$dat"
  cat > "$out/error-estimate.gp" <<GP
set terminal pngcairo size 720,640 noenhanced
set output '$out/error-estimate.png'
set logscale xy
set xrange [1e-4:1]
set yrange [1e-4:1]
set xlabel 'measured relMSE − reference noise (filled), or two-seed variance (open)'
set ylabel 'estimated relMSE (no reference)'
set key top left
set grid
f(x) = x
set title 'error estimate against measured error, ${size}, short and long budgets'
plot f(x) lc rgb 'black' title 'estimated = measured', 1.5*x lc rgb 'gray' dt 2 title '×1.5', x/1.5 lc rgb 'gray' dt 2 notitle, \
  '$dat' using (strcol(4) eq "pt" ? \$3 : 1/0):2 with points pt 7 ps 1.3 title 'pt', \
  '' using (strcol(4) eq "rb" ? \$3 : 1/0):2 with points pt 5 ps 1.3 title 'rb', \
  '' using (strcol(4) eq "combined" ? \$3 : 1/0):2 with points pt 9 ps 1.6 title 'combined', \
  '' using 5:2 with points pt 6 ps 1.8 lc rgb 'black' title 'x = variance from two seeds (no bias; all modes)'
GP
  gnuplot "$out/error-estimate.gp" && echo "plot: $out/error-estimate.png"
fi
