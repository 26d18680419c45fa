#!/usr/bin/env bash
# Scaling: time per RB iteration and per PT sample against patches, bins, triangles and pixels, with
# the peak host memory of each run (/usr/bin/time's maximum resident set) and the device memory when
# the renderer's --stats reports it. Each row is one timed render of --time SECONDS. Writes
# OUT/scaling.csv and OUT/scaling.md.
#
# Usage: bench/scaling.sh [--quick] [--out DIR] [--time SECONDS]
# Environment: see bench/lib.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

quick=0; out=""; seconds=4
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --time) seconds=$2; shift ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "scaling.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

# series | scene | mode and flags | width   (one row per run)
if [ $quick -eq 0 ]; then
  ROWS=(
    "patches (RB, 1024² bins, 128×128)|rooms-25000|--mode rb --bins 1024|128"
    "patches (RB, 1024² bins, 128×128)|rooms-100000|--mode rb --bins 1024|128"
    "patches (RB, 1024² bins, 128×128)|rooms-1000000|--mode rb --bins 1024|128"
    "bins (RB, rooms-100000, 128×128)|rooms-100000|--mode rb --bins 256|128"
    "bins (RB, rooms-100000, 128×128)|rooms-100000|--mode rb --bins 512|128"
    "bins (RB, rooms-100000, 128×128)|rooms-100000|--mode rb --bins 2048|128"
    "triangles (PT, 128×128)|rooms-1000|--mode pt|128"
    "triangles (PT, 128×128)|rooms-25000|--mode pt|128"
    "triangles (PT, 128×128)|rooms-100000|--mode pt|128"
    "triangles (PT, 128×128)|rooms-1000000|--mode pt|128"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode pt|64"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode pt|256"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode pt|512"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode rb|64"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode rb|256"
    "pixels (cornell-glossy, defaults)|cornell-glossy|--mode rb|512"
  )
else
  seconds=0.5
  out=${out:-$bench_root/bench-out/quick}
  ROWS=(
    "patches (RB, 128² bins)|rooms-2000|--mode rb --bins 128|32"
    "patches (RB, 128² bins)|rooms-8000|--mode rb --bins 128|32"
    "bins (RB)|rooms-8000|--mode rb --bins 256|32"
    "triangles (PT)|rooms-2000|--mode pt|32"
    "triangles (PT)|rooms-8000|--mode pt|32"
    "pixels|cornell-glossy|--mode pt|64"
    "pixels|cornell-glossy|--mode rb|64"
  )
fi
out=${out:-$bench_root/bench/results}
mkdir -p "$out"
csv=$out/scaling.csv
log=$out/scaling.log
: > "$csv"; : > "$log"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
timer=()
if [ -x /usr/bin/time ]; then timer=(/usr/bin/time -f "%M" -o "$tmp/rss.txt")
else echo "scaling.sh: /usr/bin/time missing (bash bench/setup.sh installs 'time'); no memory figures" >&2
fi
dev=()
mapfile -t dev < <(bench_device_args)

for row in "${ROWS[@]}"; do
  IFS='|' read -r series name flags width <<< "$row"
  scene=$(bench_scene "$name")
  echo "scaling: $name $flags ${width}px" >&2
  rm -f "$tmp/s.json" "$tmp/rss.txt"
  rc=0
  # shellcheck disable=SC2086
  "${timer[@]}" "$BUNDLEPATH" render "$scene" $flags --width "$width" --height "$width" --time "$seconds" \
    "${dev[@]}" --out "$tmp/img" --stats "$tmp/s.json" 2>>"$log" || rc=$?
  status=ok; [ $rc -eq 0 ] || status=exit-$rc
  # shellcheck disable=SC2086
  mode=$(set -- $flags; echo "$2")
  python3 "$here/report.py" append "$csv" scaling --stats "$tmp/s.json" --rss-kb "$tmp/rss.txt" --status "$status" \
    series="$series" scene="$name" mode="$mode" flags="$flags" width="$width" height="$width"
done
python3 "$here/report.py" scaling "$csv" "$out"
echo "scaling: wrote $csv and $out/scaling.md" >&2
