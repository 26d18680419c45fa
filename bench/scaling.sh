#!/usr/bin/env bash
# Scaling: time per RB iteration and per PT sample against patches, bins, triangles and pixels, with
# the peak host memory of each run (/usr/bin/time's maximum resident set) and the device memory when
# the renderer's --stats reports it. Each row is one render: --time SECONDS, or the house series'
# iteration count. Writes OUT/scaling.csv and OUT/scaling.md.
#
# The series "house at fixed rooms" is one house (the 25-room Lambert house, rooms-lambert-100000)
# tessellated to 100 k, 300 k, 1 M and 3 M triangles (rooms-lambert-N-r5: make_rooms --rooms 5), so
# RB's cost follows the triangles alone: per row load and BVH build seconds, patches, RB ms per
# iteration (--mode rb, --house-iterations iterations) and peak memory; with --house-error also the
# relMSE after 30 s of the default combination and of --mode pt, with the combined run's peak memory,
# against one path-traced reference of the first (smallest) house (1024 spp, rendered once and cached:
# bench_reference in bench/lib.sh): every house of the series has the same surfaces and lights, so
# the same image. --quick makes it a 2 x 2-room house at 2 k and 8 k triangles.
#
# Usage: bench/scaling.sh [--quick] [--out DIR] [--time SECONDS] [--house-only] [--house-error]
#                         [--house-size WxH] [--house-iterations N] [--house-triangles "N N ..."]
#                         [--house-flags "FLAGS"]
#   --time S              seconds per row of the other series                        [4; quick 0.5]
#   --house-only          only the "house at fixed rooms" series
#   --house-error         add the combination-vs-PT column (a reference and a 30 s render per house)
#   --house-size WxH      the house series' image                          [640x360; quick 32x18]
#   --house-iterations N  RB iterations per house row (after the warm-up)          [32; quick 4]
#   --house-triangles L   the triangle counts  ["100000 300000 1000000 3000000"; quick "2000 8000"]
#   --house-flags F       more options for every render of the house series (e.g. --patch-clusters off)
# Environment: see bench/lib.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

quick=0; out=""; seconds=4; house_only=0; house_error=0
house_size=""; house_iterations=""; house_triangles=""; house_flags=""
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --time) seconds=$2; shift ;;
    --house-only) house_only=1 ;;
    --house-error) house_error=1 ;;
    --house-size) house_size=$2; shift ;;
    --house-iterations) house_iterations=$2; shift ;;
    --house-triangles) house_triangles=$2; shift ;;
    --house-flags) house_flags=$2; shift ;;
    -h|--help) sed -n '2,26p' "$0"; exit 0 ;;
    *) echo "scaling.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

# The fixed-rooms house: the rooms of rooms-lambert-100000 (5 x 5), the rest finer tessellation.
house_rooms=5
house_error_seconds=30
house_ref_spp=1024  # at 640x360, as bench/house.sh (the reference is keyed on the size and spp)
if [ $quick -eq 1 ]; then
  house_rooms=2; house_error_seconds=1; house_ref_spp=16
  house_size=${house_size:-32x18}; house_iterations=${house_iterations:-4}; house_triangles=${house_triangles:-2000 8000}
fi
house_size=${house_size:-640x360}; house_iterations=${house_iterations:-32}
house_triangles=${house_triangles:-100000 300000 1000000 3000000}
bench_resolutions "$house_size" > /dev/null

# series | scene | mode and flags | size: N (N x N) or WxH   (one row per run; --iterations or --spp
# in the flags: that many, else --time SECONDS)
ROWS=()
if [ $house_only -eq 0 ] && [ $quick -eq 0 ]; then
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
elif [ $house_only -eq 0 ]; then
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
[ $quick -eq 1 ] && seconds=0.5 && out=${out:-$bench_root/bench-out/quick}
house_series="house at fixed rooms (RB, ${house_rooms}×${house_rooms} Lambert rooms, ${house_size/x/×})"
[ -n "$house_flags" ] && house_series="$house_series, $house_flags"
for n in $house_triangles; do
  ROWS+=("$house_series|rooms-lambert-$n-r$house_rooms|--mode rb --iterations $house_iterations${house_flags:+ $house_flags}|$house_size")
done
house_first=$(set -- $house_triangles; echo "$1")
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
  IFS='|' read -r series name flags size <<< "$row"
  scene=$(bench_scene "$name")
  mapfile -t wh < <(bench_size_args "$size")
  budget=(--time "$seconds")
  case " $flags " in *" --iterations "*|*" --spp "*) budget=() ;; esac
  echo "scaling: $name $flags ${wh[1]}x${wh[3]}" >&2
  rm -f "$tmp/s.json" "$tmp/rss.txt" "$tmp/c.json"
  rc=0
  # shellcheck disable=SC2086
  "${timer[@]}" "$BUNDLEPATH" render "$scene" $flags "${wh[@]}" "${budget[@]}" \
    "${dev[@]}" --out "$tmp/img" --stats "$tmp/s.json" 2>>"$log" || rc=$?
  status=ok; [ $rc -eq 0 ] || status=exit-$rc
  error=()
  if [ $house_error -eq 1 ] && [ "$series" = "$house_series" ]; then
    # The default combination and the path tracer against the first house's path-traced reference
    # (cached, resumable).
    ref=$(bench_reference "$(bench_scene "rooms-lambert-$house_first-r$house_rooms")" "$house_ref_spp" "$size")
    rm -f "$tmp/p.json" "$tmp/rss-e.txt"
    for mode in combined pt; do
      echo "scaling: $name --mode $mode ${wh[1]}x${wh[3]} ${house_error_seconds} s against $(basename "$ref")" >&2
      timed=(); [ $mode = combined ] && [ ${#timer[@]} -gt 0 ] && timed=(/usr/bin/time -f "%M" -o "$tmp/rss-e.txt")
      # shellcheck disable=SC2086
      "${timed[@]}" "$BUNDLEPATH" render "$scene" --mode $mode "${wh[@]}" --time "$house_error_seconds" --reference "$ref" $house_flags \
        "${dev[@]}" --out "$tmp/img" --stats "$tmp/${mode:0:1}.json" 2>>"$log" ||
        echo "scaling: the $mode render of $name failed" >&2
    done
    error=(--error-stats "$tmp/c.json" --pt-error-stats "$tmp/p.json" --error-rss-kb "$tmp/rss-e.txt")
  fi
  # shellcheck disable=SC2086
  mode=$(set -- $flags; echo "$2")
  python3 "$here/report.py" append "$csv" scaling --stats "$tmp/s.json" --rss-kb "$tmp/rss.txt" --status "$status" \
    "${error[@]}" series="$series" scene="$name" mode="$mode" flags="$flags" width="${wh[1]}" height="${wh[3]}"
done
python3 "$here/report.py" scaling "$csv" "$out"
echo "scaling: wrote $csv and $out/scaling.md" >&2
