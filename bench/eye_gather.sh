#!/usr/bin/env bash
# The eye estimate in blocks against every iteration's gather (--rb-eye-gather blocks|every,
# docs/design.md §8): for each scene and resolution, the same render (same seed and work) with each,
# alternating, REPEATS times; the median render seconds of each, their ratio, the RB kernels' device
# seconds of the eye estimate (rb_eye + rb_eye_patches + rb_eye_block) and the relMSE of the blocks
# image against the every-iteration one (float rounding: ~1e-12). Writes OUT/eye-gather.md.
# Usage: bench/eye_gather.sh [--out DIR] [--repeats N] [--iterations N] [--sizes "640x360 1280x720"]
#                            [--modes "rb combined"] [SCENE...]
# Defaults: --repeats 3 --iterations 256, both sizes and modes (combined at --ratio 1/16, the
# iterations' sixteenth in spp), scenes cornell-box cornell-glossy rooms-lambert-100000.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
out=""; repeats=3; iterations=256; sizes="640x360 1280x720"; modes="rb combined"; scenes=()
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --iterations) iterations=$2; shift ;;
    --sizes) sizes=$2; shift ;;
    --modes) modes=$2; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "eye_gather.sh: unknown option $1" >&2; exit 2 ;;
    *) scenes+=("$1") ;;
  esac
  shift
done
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-box cornell-glossy rooms-lambert-100000)
out=${out:-$bench_root/bench/results}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
md=$out/eye-gather.md
{
  echo "| scene | size | mode | work | every s | blocks s | every / blocks | eye kernels every s | eye kernels blocks s | relMSE blocks vs every |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} > "$md"
for name in "${scenes[@]}"; do
  scene=$(bench_scene "$name")
  for size in $sizes; do
    mapfile -t wh < <(bench_size_args "$size")
    for mode in $modes; do
      work=(--mode rb --iterations "$iterations")
      [ "$mode" = combined ] && work=(--mode combined --ratio 1/16 --spp $((iterations / 16)))
      # Untimed first: kernel builds and the scene's caches.
      bench_render "$scene" --width 32 --height 18 "${work[@]}" --out "$tmp/warm" 2>/dev/null
      for r in $(seq "$repeats"); do
        for gather in every blocks; do
          bench_render "$scene" "${wh[@]}" "${work[@]}" --seed 7 --rb-eye-gather "$gather" --out "$tmp/$gather" \
            --stats "$tmp/$gather-$r.json" 2>/dev/null
        done
      done
      relmse=$("$BUNDLEPATH" compare "$tmp/blocks.exr" "$tmp/every.exr" --json |
               python3 -c 'import json,sys; print("%.2g" % json.load(sys.stdin)["rel_mse"])')
      python3 - "$name" "$size" "$mode" "$repeats" "$tmp" "$relmse" >> "$md" <<'PY'
import json, statistics, sys
name, size, mode, repeats, tmp, relmse = sys.argv[1:]
def runs(gather):
    return [json.load(open(f"{tmp}/{gather}-{r}.json")) for r in range(1, int(repeats) + 1)]
def eye(s):
    return sum(l["device_seconds"] for k, l in s["launches"].items() if k in ("rb_eye", "rb_eye_patches", "rb_eye_block"))
every, blocks = runs("every"), runs("blocks")
te = statistics.median(s["render_seconds"] for s in every)
tb = statistics.median(s["render_seconds"] for s in blocks)
s = blocks[0]
work = f"{s['spp']} spp + {s['iterations']} it" if mode == "combined" else f"{s['iterations']} it"
print(f"| {name} | {size} | {mode} | {work} | {te:.2f} | {tb:.2f} | {te / tb:.2f} | "
      f"{statistics.median(eye(s) for s in every):.2f} | {statistics.median(eye(s) for s in blocks):.2f} | {relmse} |")
PY
    done
  done
done
device=$("$BUNDLEPATH" devices 2>/dev/null | grep -m1 '\[0\]' || true)
{
  echo
  echo "(median of $repeats alternating runs, seed 7; $device)"
  echo "(command: bash bench/eye_gather.sh --repeats $repeats --iterations $iterations --sizes \"$sizes\" --modes \"$modes\" ${scenes[*]})"
} >> "$md"
cat "$md"
