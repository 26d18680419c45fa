# shellcheck shell=bash
# Shared by the bench scripts (source it; it does not run anything by itself).
#
# Environment (all optional):
#   BUNDLEPATH        the renderer binary                 [build/bundlepath]
#   BENCH_BUILD_DIR   where bench executables live        [the binary's folder]
#   BENCH_CACHE       reference images, generated scenes [${XDG_CACHE_HOME:-~/.cache}/bundlepath]
#   BENCH_DEVICE      passed to every render as --device  [the renderer's default]
#   BENCH_REF_FLAGS   extra flags for reference renders (e.g. light sampling, once it exists)
#
# bench_reference SCENE SPP SIZE   -> prints the path of a cached PT reference (.exr), rendering it
#                                     first if needed (resumable chunks, see bench/reference.sh);
#                                     SIZE is WxH (640x360) or N (NxN)
# bench_size_args SIZE             -> --width W --height H, one a line
# bench_resolutions LIST           -> the sizes of "128x128,640x360" (commas or spaces), one a line
# bench_reference_spp SPP SIZE     -> a reference's spp at SIZE: SPP up to 128x128 pixels; larger,
#                                     the same pixel samples as a power of 2, and at least those of
#                                     1024 spp at 640x360 (1024 spp there, 256 at 1280x720), at most SPP
# bench_rooms_scene TRIANGLES [SEED [VARIANT [ROOMS]]] -> prints the path of a cached procedural rooms
#                                     scene (.glb); VARIANT lambert or ggx, ROOMS rooms per side
# bench_render ARGS...             -> the renderer with BENCH_DEVICE applied, stderr kept in a log
# bench_has_flag FLAG              -> true when `render --help` mentions FLAG
# bench_budgets CAP                -> the wall-time budgets 1, 2, 4, ... up to CAP seconds, one a line
# bench_require_gnuplot SCRIPT     -> exits 2 naming SCRIPT when gnuplot is missing

bench_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# The scenes of the convergence study and the ratio sweep: name (scenes/NAME.gltf, rooms-N or
# rooms-lambert-N = procedural rooms of N triangles) and the reference's spp at 128x128
# (bench_reference_spp scales it to other sizes).
# shellcheck disable=SC2034  # used by the scripts that source this file
BENCH_STUDY_SCENES=(
  "cornell-box 16384"
  "cornell-glossy 16384"
  "rooms-100000 8192"
  "rooms-lambert-100000 8192"
)
BUNDLEPATH=${BUNDLEPATH:-$bench_root/build/bundlepath}
case $BUNDLEPATH in /*) ;; *) BUNDLEPATH=$PWD/$BUNDLEPATH ;; esac
BENCH_BUILD_DIR=${BENCH_BUILD_DIR:-$(dirname "$BUNDLEPATH")}
BENCH_CACHE=${BENCH_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/bundlepath}
BENCH_REF_CHUNK=${BENCH_REF_CHUNK:-120}   # seconds per resumable reference chunk
export BUNDLEPATH BENCH_BUILD_DIR BENCH_CACHE

if [ ! -x "$BUNDLEPATH" ]; then
  echo "bench: no renderer at $BUNDLEPATH (build it, or set BUNDLEPATH=...)" >&2
  exit 2
fi

bench_device_args() {
  if [ -n "${BENCH_DEVICE:-}" ]; then printf '%s\n' --device "$BENCH_DEVICE"; fi
}

bench_render() {
  local -a dev
  mapfile -t dev < <(bench_device_args)
  "$BUNDLEPATH" render "$@" "${dev[@]}"
}

bench_budgets() {
  local b
  for ((b = 1; b <= $1; b *= 2)); do echo "$b"; done
}

bench_require_gnuplot() {
  command -v gnuplot >/dev/null && return 0
  echo "$1: gnuplot is missing (bash bench/setup.sh installs it), or pass --no-plots" >&2
  exit 2
}

bench_has_flag() {
  # The help is read whole before grep looks: `render --help | grep -q` under pipefail failed at
  # random, when grep stopped reading at the first match and the renderer died of SIGPIPE.
  local help
  help=$("$BUNDLEPATH" render --help 2>&1) || return 1
  grep -q -- "$1\b" <<< "$help"
}

# A short tag of a scene file's contents, so a changed scene never reuses a stale reference.
bench_scene_tag() {
  sha256sum "$1" | cut -c1-10
}

bench_scene_name() {
  local b
  b=$(basename "$1")
  echo "${b%.*}"
}

bench_size_args() {
  case $1 in
    *x*) printf '%s\n' --width "${1%x*}" --height "${1#*x}" ;;
    *) printf '%s\n' --width "$1" --height "$1" ;;
  esac
}

bench_resolutions() {
  local r
  for r in ${1//,/ }; do
    if ! [[ $r =~ ^[0-9]+(x[0-9]+)?$ ]]; then echo "bench: resolution '$r' is not WxH (e.g. 640x360)" >&2; return 2; fi
    echo "$r"
  done
}

bench_reference_spp() {
  python3 - "$1" "$2" <<'PY'
import sys
spp, size = int(sys.argv[1]), sys.argv[2]
w, _, h = size.partition("x")
pixels = int(w) * int(h or w)
def pow2_floor(x):
    p = 1
    while p * 2 <= x:
        p *= 2
    return p
# The pixel samples of SPP at 128x128, and at least those of 1024 spp at 640x360 (the same time).
same = max(pow2_floor(spp * 128 * 128 / pixels), pow2_floor(1024 * 640 * 360 / pixels))
print(spp if pixels <= 128 * 128 else min(spp, same))
PY
}

# bench_reference SCENE SPP SIZE: the one place that renders and caches path-traced references.
# The render runs in chunks of BENCH_REF_CHUNK seconds with a checkpoint, so an interrupted
# reference (Ctrl-C, a killed job) continues where it stopped the next time it is asked for.
bench_reference() {
  local scene=$1 spp=$2 size=$3
  local dir=$BENCH_CACHE/references
  local -a wh
  mapfile -t wh < <(bench_size_args "$size")
  size=${wh[1]}; [ "${wh[1]}" = "${wh[3]}" ] || size=${wh[1]}x${wh[3]}  # NxN keeps the name N (older caches)
  mkdir -p "$dir"
  local flags_tag=""
  if [ -n "${BENCH_REF_FLAGS:-}" ]; then flags_tag=-$(echo "$BENCH_REF_FLAGS" | sha256sum | cut -c1-6); fi
  local ref
  ref=$dir/$(bench_scene_name "$scene")-$(bench_scene_tag "$scene")-pt-$size-$spp$flags_tag
  if [ -f "$ref.exr" ]; then echo "$ref.exr"; return 0; fi
  local ck=$ref.checkpoint part=$ref.partial
  local -a resume=()
  # shellcheck disable=SC2206
  local -a extra=(${BENCH_REF_FLAGS:-})
  while :; do
    if [ -f "$ck" ]; then resume=(--resume "$ck"); echo "bench: resuming reference $(basename "$ref") ..." >&2
    else echo "bench: rendering reference $(basename "$ref") ($spp spp at ${wh[1]}x${wh[3]}, once; cached in $dir) ..." >&2
    fi
    local rc=0
    bench_render "$scene" --mode pt "${wh[@]}" --spp "$spp" --seed 7 "${extra[@]}" \
      --time "$BENCH_REF_CHUNK" --checkpoint "$ck" --checkpoint-every 30 "${resume[@]}" \
      --out "$part" --stats "$part.json" >&2 2>>"$ref.log" || rc=$?
    if [ $rc -ne 0 ]; then
      echo "bench: reference render failed (exit $rc); see $ref.log (rerun to resume)" >&2
      return $rc
    fi
    local done_spp
    done_spp=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["spp"])' "$part.json")
    if [ "$done_spp" -ge "$spp" ]; then break; fi
    echo "bench: reference at $done_spp / $spp spp" >&2
  done
  mv "$part.json" "$ref.json"
  mv "$part.png" "$ref.png" 2>/dev/null || true
  mv "$part.exr" "$ref.exr"
  rm -f "$ck"
  echo "$ref.exr"
}

# bench_rooms_scene TRIANGLES [SEED [VARIANT [ROOMS]]]: a procedural rooms scene
# (host/scene/procedural.cpp) written as .glb by bench/make_rooms, cached (a pure function of the
# triangle count, seed, materials and rooms); VARIANT "lambert" writes every material pure Lambert
# (make_rooms --lambert), "ggx" glTF metallic-roughness, "ggxR" that with every glossy material at
# roughness R (make_rooms --ggx --roughness R); ROOMS fixes the rooms per side (make_rooms
# --rooms: the same house tessellated finer). ROOMS equal to the default grid, round(sqrt(N / 4000)),
# is the same file as no ROOMS, so it keeps that name and its cached references.
bench_rooms_scene() {
  local n=$1 seed=${2:-1} variant=${3:-} rooms=${4:-}
  local dir=$BENCH_CACHE/scenes
  mkdir -p "$dir"
  local stem=rooms-$n
  local -a make_flags=()
  if [ -n "$variant" ]; then stem=rooms-$variant-$n; make_flags=(--"$variant"); fi
  if [[ $variant =~ ^ggx([0-9.]+)$ ]]; then make_flags=(--ggx --roughness "${BASH_REMATCH[1]}"); fi
  if [ -n "$rooms" ] && [ "$rooms" != "$(awk -v n="$n" 'BEGIN { g = int(sqrt(n / 4000) + 0.5); print g < 1 ? 1 : g }')" ]; then
    stem=$stem-r$rooms; make_flags+=(--rooms "$rooms")
  fi
  local out=$dir/$stem-s$seed.glb
  if [ ! -f "$out" ]; then
    local tool=$BENCH_BUILD_DIR/bench/make_rooms
    [ -x "$tool" ] || tool=$BENCH_BUILD_DIR/make_rooms
    if [ ! -x "$tool" ]; then
      echo "bench: $tool missing (build the 'make_rooms' target)" >&2
      return 2
    fi
    "$tool" "$n" "$out.tmp.glb" --seed "$seed" "${make_flags[@]}" >&2
    mv "$out.tmp.glb" "$out"
  fi
  echo "$out"
}

# bench_rooms_spec N[-rR] VARIANT: bench_rooms_scene for the tail of a rooms scene name.
bench_rooms_spec() {
  if [[ $1 =~ ^([0-9]+)-r([0-9]+)$ ]]; then bench_rooms_scene "${BASH_REMATCH[1]}" 1 "$2" "${BASH_REMATCH[2]}"
  else bench_rooms_scene "$1" 1 "$2"
  fi
}

# bench_scene NAME: a scene name of the study -> a file. cornell-box, cornell-glossy (scenes/),
# rooms-N (procedural, N triangles), rooms-lambert-N (the same house, every material Lambert),
# rooms-ggx-N (the same house in glTF metallic-roughness: make_rooms --ggx), rooms-ggxR-N (that house
# with every glossy material at roughness R: rooms-ggx0.1-100000), each with an optional
# -rR (R x R rooms whatever N is: rooms-lambert-1000000-r5 is rooms-lambert-100000's house at 1 M
# triangles), or a path.
bench_scene() {
  case $1 in
    rooms-lambert-*) bench_rooms_spec "${1#rooms-lambert-}" lambert ;;
    rooms-ggx-*) bench_rooms_spec "${1#rooms-ggx-}" ggx ;;
    rooms-ggx[0-9]*-*) local tail=${1#rooms-ggx}; bench_rooms_spec "${tail#*-}" "ggx${tail%%-*}" ;;
    rooms-*) bench_rooms_spec "${1#rooms-}" "" ;;
    *.gltf|*.glb) echo "$1" ;;
    *) echo "$bench_root/scenes/$1.gltf" ;;
  esac
}
