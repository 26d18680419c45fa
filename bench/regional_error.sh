#!/usr/bin/env bash
# The image's regional error: each render cut into a grid of blocks (8x8 by default, the grid of
# `render --regions`), the relative error of each block's mean luminance against a long path-traced
# reference, and each block's z-score against the regional error the render itself reports
# (--stats' regional_error). Per row: relMSE, the render's own estimate of it and the reference's own
# (which every measured relMSE contains), the worst block, the RMS over blocks, the largest |z|
# and its Šidák-corrected equivalent over the blocks (the |z| one block alone would need for the
# same p-value; under 4 is the bar), the render's own expected worst block, and the work done.
# Writes a Markdown table to stdout and, with --maps DIR, one SVG of block errors per row.
# Usage: bench/regional_error.sh [--scenes "S1 S2"] [--sizes "640x360"] [--budgets "30"]
#          [--seeds "1 2 3 4"] [--modes "combined pt"] [--ref-spp N] [--regions N] [--maps DIR]
#          [--stats DIR] [--work] [-- EXTRA RENDER OPTIONS]
#        --stats DIR: keeps each render's --stats JSON there (SCENE-SIZE-BUDGET-MODE-SEED.json:
#        --ratio auto's probe, kappa, the render's error estimate).
#        --work: budgets are "Nspp+Mit" or "Nspp" work counts (e.g. 8spp+256it at --ratio 1/32)
#        instead of seconds, so a loaded machine measures the same renders.
# Defaults: rooms-lambert-100000, 640x360, 30 s, seeds 1-4, combined and pt, 1024-spp reference.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
scenes="rooms-lambert-100000" sizes="640x360" budgets="30" seeds="1 2 3 4" modes="combined pt"
ref_spp=1024 regions=8 maps="" stats_dir="" work=0 extra=() refs=()
while [ $# -gt 0 ]; do
  case $1 in
    --scenes) scenes=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --budgets) budgets=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    --modes) modes=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --regions) regions=$2; shift 2 ;;
    --maps) maps=$2; shift 2 ;;
    --stats) stats_dir=$2; shift 2 ;;
    --work) work=1; shift ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "regional_error.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
cd "$bench_root"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -z "$maps" ] || mkdir -p "$maps"
[ -z "$stats_dir" ] || mkdir -p "$stats_dir"
echo "| scene | size | budget | mode | seed | work | relMSE | relMSE estimated (own) | reference's own | worst block | block RMS | worst \|z\| | Šidák z | expected worst (own) | dof |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene_name in $scenes; do
  scene=$(bench_scene "$scene_name")
  label=$(basename "$scene_name"); label=${label%.gl*}  # a path's file name, without .gltf or .glb
  for size in $sizes; do
    mapfile -t wh < <(bench_size_args "$size")
    ref=$(bench_reference "$scene" "$(bench_reference_spp "$ref_spp" "$size")" "$size")
    refs+=("$(basename "$ref" .exr)")
    for budget in $budgets; do
      for mode in $modes; do
        for seed in $seeds; do
          budget_args=(--time "$budget")
          if [ "$work" = 1 ]; then
            spp=${budget%%spp*}; it=""
            case $budget in *+*it) it=${budget##*+}; it=${it%it} ;; esac
            if [ "$mode" = pt ]; then budget_args=(--spp "$spp")
            elif [ -n "$it" ]; then budget_args=(--ratio "$spp/$it" --iterations "$it")
            else budget_args=(--spp "$spp"); fi
          fi
          stats=$tmp/$label-$size-$budget-$mode-$seed.json
          bench_render "$scene" "${wh[@]}" --mode "$mode" "${budget_args[@]}" --seed "$seed" --regions "$regions" \
            --reference "$ref" --out "$tmp/img" --stats "$stats" "${extra[@]}" 2>/dev/null
          python3 - "$stats" "$label" "$size" "$budget" "$mode" "$seed" "$maps" "${ref%.exr}.json" <<'PY'
import json, math, os, sys
from statistics import NormalDist
path, scene, size, budget, mode, seed, maps, ref_stats = sys.argv[1:9]
s = json.load(open(path))
reg = s["regional_error"]
ref = reg["reference"]
errors = [e for e in ref["relative_error"] if e is not None]
# z against the render's own regional error and, where the reference's stats have theirs on the
# same grid, the reference's too: z = (Y - R) / sqrt(σ² + σ_R²).
ref_se = None
ref_noise = None  # the reference's own estimated relMSE: every measured relMSE contains it
if os.path.exists(ref_stats):
    ref_noise = json.load(open(ref_stats)).get("estimated_rel_mse")
    r = json.load(open(ref_stats)).get("regional_error")
    if r and r["regions"] == reg["regions"]:
        ref_se = r["relative_stderr"]
zs = []
for b, (e, own) in enumerate(zip(ref["relative_error"], reg["relative_stderr"])):
    if e is None or own is None or own <= 0:
        continue
    var = own * own + (ref_se[b] ** 2 if ref_se and ref_se[b] is not None else 0.0)
    zs.append(abs(e) / math.sqrt(var))
blocks = len(errors)
worst = max(abs(e) for e in errors)
rms = math.sqrt(sum(e * e for e in errors) / blocks)
worst_z = max(zs) if zs else float("nan")
# Šidák: the p-value of the largest |z| over B blocks, as the |z| of one block with that p-value.
if zs:
    p_one = 2.0 * (1.0 - NormalDist().cdf(worst_z))
    p_any = 1.0 - (1.0 - p_one) ** len(zs)
    sidak_z = NormalDist().inv_cdf(1.0 - max(p_any, 1e-300) / 2.0) if p_any < 1.0 else 0.0
else:
    sidak_z = float("nan")
work = f"{s['spp']} spp" + (f" + {s['iterations']} it" if s.get("iterations") else "")
rel = s["reference"]["layers"]["combined"]["rel_mse"]
own = reg.get("expected_worst_error")
own_text = f"{100 * own:.2f} %" if own is not None else "—"
budget_text = f"{budget} s" if budget.replace(".", "").isdigit() else budget
est = s.get("estimated_rel_mse")
est_text = f"{est:.4g}" if est is not None else "—"
noise_text = f"{ref_noise:.2g}" if ref_noise is not None else "—"
print(f"| {scene} | {size} | {budget_text} | {mode} | {seed} | {work} | {rel:.4g} | {est_text} | {noise_text} | {100 * worst:.2f} % | "
      f"{100 * rms:.2f} % | {worst_z:.2f} | {sidak_z:.2f} | {own_text} | {reg['degrees_of_freedom']:.0f} |")
if maps:
    cols, rows = reg["regions"]
    cell = 24
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * cell}" height="{rows * cell + 16}">']
    for b, e in enumerate(ref["relative_error"]):
        x, y = (b % cols) * cell, (b // cols) * cell
        v = 0.0 if e is None else max(-1.0, min(1.0, e / 0.05))  # saturates at ±5 %
        r, g, bl = (255, int(255 * (1 - v)), int(255 * (1 - v))) if v > 0 else (int(255 * (1 + v)), int(255 * (1 + v)), 255)
        out.append(f'<rect x="{x}" y="{y}" width="{cell}" height="{cell}" fill="rgb({r},{g},{bl})"/>')
        if e is not None:
            out.append(f'<text x="{x + 2}" y="{y + 15}" font-size="8">{100 * e:+.1f}</text>')
    out.append(f'<text x="0" y="{rows * cell + 12}" font-size="10">{scene} {mode} seed {seed}: red +5 %, blue -5 %</text></svg>')
    open(f"{maps}/{scene}-{size}-{budget}-{mode}-{seed}.svg", "w").write("\n".join(out))
PY
          [ -z "$stats_dir" ] || cp "$stats" "$stats_dir/"
        done
      done
    done
  done
done
echo
echo "(references: ${refs[*]}; $("$BUNDLEPATH" devices 2>/dev/null | head -1); $(date -u +%Y-%m-%d))"
