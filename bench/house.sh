#!/usr/bin/env bash
# Issue #12's claim: on a large interior at a real resolution the default combination beats both
# estimators alone. Renders SCENE (default the Lambert house, rooms-lambert-100000) at SIZE for
# SECONDS each with --mode pt, --mode rb and --mode combined at its defaults (plus the combination
# with --eye-direct pt and with --light-selection power, to show what each part buys), REPEATS
# times with different seeds, against a long path-traced reference (bench/reference.sh, cached).
# Prints a Markdown table: relMSE (median and each run), relMSE times the render's seconds (median:
# the inverse of the efficiency, comparable where runs stop at different batch ends near the
# budget), the image mean against the reference's, and the work done.
# Usage: bench/house.sh [SCENE] [SECONDS] [SIZE] [REFERENCE_SPP] [REPEATS] [-- 'OPTIONS' ...]
#        defaults: rooms-lambert-100000 30 640x360 1024 2   (REFERENCE_SPP at SIZE, not scaled)
#        After --: the rows are pt, rb, the default combination and one `--mode combined OPTIONS`
#        row per argument (e.g. -- '--ratio 64' '--beta balance') instead of the two above.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
if [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then sed -n '2,12p' "$0"; exit 2; fi
cd "$bench_root"
scene=$(bench_scene "${1:-rooms-lambert-100000}")
seconds=${2:-30}
size=${3:-640x360}
ref_spp=${4:-1024}
repeats=${5:-2}
extra_rows=()
if [ $# -gt 5 ]; then
  [ "$6" = -- ] || { echo "house.sh: the sixth argument must be --, then one quoted option list per row" >&2; exit 2; }
  extra_rows=("${@:7}")
fi
mapfile -t wh < <(bench_size_args "$size")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() {  # label, then render options
  local label=$1; shift
  local -a stats=()
  for ((r = 1; r <= repeats; ++r)); do
    bench_render "$scene" "${wh[@]}" --time "$seconds" --seed "$r" --reference "$ref" --out "$tmp/img" \
      --stats "$tmp/s$r.json" "$@" 2>/dev/null
    stats+=("$tmp/s$r.json")
  done
  python3 - "$label" "$ref" "${stats[@]}" <<'PY'
import json, statistics, subprocess, sys
label, ref = sys.argv[1], sys.argv[2]
runs = [json.load(open(p)) for p in sys.argv[3:]]
rel = [s["reference"]["layers"]["combined"]["rel_mse"] for s in runs]
bias = [s["reference"]["layers"]["combined"]["relative_bias"] for s in runs]
s = runs[0]
work = f"{s['spp']} spp" + (f" + {s['iterations']} it" if s.get("iterations") else "")
if "ratio_auto" in s:
    c = float(s["ratio"])  # "inf": the path tracer alone
    work += f" (c = {c:g})" if c >= 1 else f" (c = 1/{1 / c:g})"
mean_dev = " / ".join(f"{100 * b:+.2f} %" for b in bias)
rel_s = statistics.median(r * s["render_seconds"] for r, s in zip(rel, runs))
print(f"| {label} | {work} | {statistics.median(rel):.3g} | {' / '.join(f'{x:.3g}' for x in rel)} | {rel_s:.3g} | {mean_dev} |")
PY
}
echo "| method, ${size}, ${seconds} s | work done (seed 1) | relMSE (median) | relMSE per seed | relMSE·s (median) | image mean vs reference |"
echo "|---|---|---|---|---|---|"
run "\`--mode pt\`" --mode pt
run "\`--mode rb\`" --mode rb
run "\`--mode combined\` (defaults)" --mode combined
if [ ${#extra_rows[@]} -eq 0 ]; then
  run "\`--mode combined --eye-direct pt\`" --mode combined --eye-direct pt
  run "\`--mode combined --light-selection power\`" --mode combined --light-selection power
fi
for row in "${extra_rows[@]}"; do
  read -r -a opts <<<"$row"
  run "\`--mode combined $row\`" --mode combined "${opts[@]}"
done
echo
echo "(reference: $(basename "$ref"), $ref_spp spp; $("$BUNDLEPATH" devices 2>/dev/null | head -1))"
