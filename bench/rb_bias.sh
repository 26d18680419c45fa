#!/usr/bin/env bash
# Is --mode rb biased on the house (rooms-100000), or only noisy? (issue #12.) Renders SEEDS
# independent RB runs of ITERATIONS iterations each (default options otherwise: --warmup 16,
# Gouraud, default bins and patch size) and compares each run's image level (the mean over pixels
# and channels) with a cached path-traced reference. Reports the mean relative level over the
# seeds with its standard error, Student's t and its two-sided p (H0: RB's expectation is the
# reference), the median and the skewness of the per-seed levels, a second PT image against the
# reference (the reference's own level noise), the same per region (the material the eye sees:
# walls, floor, ceiling, furniture; bench/rb_regions.py), and the per-seed table. Prints Markdown.
# Usage: bench/rb_bias.sh [SEEDS] [ITERATIONS] [SIZE] [REFERENCE_SPP] [SCENE]
#        (defaults 24, 300, 96, 2048, rooms-100000: about 5 minutes on 2 cores, plus a 2-minute
#        reference once; 24 1000: about 16 minutes)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
cd "$bench_root"
seeds=${1:-24}
iterations=${2:-300}
size=${3:-96}
ref_spp=${4:-2048}
scene=$(bench_scene "${5:-rooms-100000}")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
t0=$(date +%s)
# The reference's own level noise: an independent PT image (another seed, 1/8 of the samples).
bench_render "$scene" --mode pt --width "$size" --height "$size" --spp $((ref_spp / 8)) --seed 8 \
  --out "$tmp/pt" 2>/dev/null
"$BUNDLEPATH" compare "$tmp/pt.exr" "$ref" --json > "$tmp/pt.json"
# Regions: a copy of the scene whose materials only emit a code each, path traced once (rb_regions.py).
python3 "$here/rb_regions.py" labels "$scene" "$tmp/labels.glb"
bench_render "$tmp/labels.glb" --mode pt --no-light-sampling --width "$size" --height "$size" --spp 16 \
  --out "$tmp/labels" 2>/dev/null
images=()
for ((s = 1; s <= seeds; s++)); do
  images+=("$tmp/rb-$s.exr")
  bench_render "$scene" --mode rb --width "$size" --height "$size" --iterations "$iterations" --seed "$s" \
    --out "$tmp/rb-$s" 2>/dev/null
  "$BUNDLEPATH" compare "$tmp/rb-$s.exr" "$ref" --json > "$tmp/rb-$s.json"
done
python3 "$here/rb_regions.py" levels "$tmp/labels.exr" "$tmp/labels.glb" "$ref" "${images[@]}" > "$tmp/regions.jsonl"
t1=$(date +%s)
python3 - "$tmp" "$seeds" "$iterations" "$size" "$ref_spp" "$(bench_scene_name "$scene")" $((t1 - t0)) \
  "$("$BUNDLEPATH" devices | head -1)" <<'PY'
import json, math, statistics, sys
tmp, seeds, iterations, size, ref_spp, scene, seconds, device = sys.argv[1:9]
seeds = int(seeds)
regions = [json.loads(line) for line in open(f"{tmp}/regions.jsonl")]

def student_t_two_sided_p(t, df):
    # p = I_x(df/2, 1/2) with x = df / (df + t^2): the regularized incomplete beta, by its continued fraction
    x, a, b = df / (df + t * t), df / 2.0, 0.5
    if x <= 0.0: return 0.0
    if x >= 1.0: return 1.0
    lbeta = math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x)
    def cf(a, b, x):
        c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
        d = 1.0 / (d if abs(d) > 1e-300 else 1e-300); h = d
        for m in range(1, 300):
            for num in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                        -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
                d = 1.0 + num * d; d = 1.0 / (d if abs(d) > 1e-300 else 1e-300)
                c = 1.0 + num / c if abs(c) > 1e-300 else 1e-300
                h *= d * c
        return h
    if x < (a + 1.0) / (a + b + 2.0): return math.exp(lbeta) * cf(a, b, x) / a
    return 1.0 - math.exp(lbeta) * cf(b, a, 1.0 - x) / b

runs = [json.load(open(f"{tmp}/rb-{s}.json")) for s in range(1, seeds + 1)]
rel = [r["relative_bias"] for r in runs]
pt = json.load(open(f"{tmp}/pt.json"))
m, sd = statistics.mean(rel), statistics.stdev(rel)
se = sd / math.sqrt(seeds)
t = m / se
p = student_t_two_sided_p(t, seeds - 1)
skew = sum((r - m) ** 3 for r in rel) / seeds / statistics.pstdev(rel) ** 3
below = sum(r < 0 for r in rel)
print(f"RB level against the PT reference on {scene}, {seeds} seeds x {iterations} iterations at {size}x{size} "
      f"(reference {ref_spp} spp):")
print()
print("| statistic | value |")
print("|---|---|")
print(f"| mean relative level (RB − PT) / PT | {100*m:+.2f} % |")
print(f"| standard error of the mean | {100*se:.2f} % |")
print(f"| t (H0: RB unbiased), df = {seeds - 1} | {t:+.2f} |")
print(f"| two-sided p | {p:.3f} |")
lo, hi = 0.0, 100.0  # the two-sided 95 % quantile of Student's t, by bisection
for _ in range(100):
    lo, hi = ((lo + hi) / 2, hi) if student_t_two_sided_p((lo + hi) / 2, seeds - 1) > 0.05 else (lo, (lo + hi) / 2)
print(f"| 95 % interval of the bias (± {lo:.2f} SE) | {100*(m - lo*se):+.2f} % … {100*(m + lo*se):+.2f} % |")
print(f"| per-seed standard deviation | {100*sd:.2f} % |")
print(f"| median / min / max | {100*statistics.median(rel):+.2f} % / {100*min(rel):+.2f} % / {100*max(rel):+.2f} % |")
skew_se = math.sqrt(6.0 * seeds * (seeds - 1) / ((seeds - 2) * (seeds + 1) * (seeds + 3)))
print(f"| skewness of the per-seed levels (its standard error) | {skew:+.2f} ({skew_se:.2f}) |")
print(f"| seeds below the reference | {below} of {seeds} |")
print(f"| PT, {int(ref_spp)//8} spp, seed 8, against the reference (its level noise) | {100*pt['relative_bias']:+.2f} % |")
print()
names = sorted(regions[0]["pixels"], key=lambda n: -regions[0]["pixels"][n])
print("Per region (the material the eye sees; edge pixels left out):")
print()
print("| region | pixels | mean level (RB − PT) / PT | standard error | t | p |")
print("|---|---|---|---|---|---|")
for name in ["all"] + names:
    x = [r["relative_level"][name] for r in regions]
    rm, rse = statistics.mean(x), statistics.stdev(x) / math.sqrt(seeds)
    px = int(size) ** 2 if name == "all" else regions[0]["pixels"][name]
    print(f"| {name} | {px} | {100*rm:+.2f} % | {100*rse:.2f} % | {rm/rse:+.2f} | {student_t_two_sided_p(rm/rse, seeds - 1):.2f} |")
print()
print("| seed | level (RB − PT) / PT | " + " | ".join(names) + " | relMSE |")
print("|---|---|" + "---|" * len(names) + "---|")
for s, (r, g) in enumerate(zip(runs, regions), 1):
    cells = " | ".join(f"{100*g['relative_level'][n]:+.1f} %" for n in names)
    print(f"| {s} | {100*r['relative_bias']:+.2f} % | {cells} | {r['rel_mse']:.4f} |")
print()
print(f"({seconds} s; {device})")
PY
