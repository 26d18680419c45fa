#!/usr/bin/env bash
# Smooth-shaded rims and silhouettes against Cycles 5: the scene of scenes/blender/make_smooth_edges.py
# (Blender 5, its own glTF exporter: a Shade Smooth capped cylinder, whose rim normals average the
# cap's and the side's, a smooth torus, a subdivided smooth Suzanne, a floor; one sun and a uniform
# grey world) rendered per camera by bundlepath (--mode pt) and by Cycles (bench/smooth_edges_cycles.py,
# two seeds), compared by bench/smooth_edges_compare.py: where the interpolated shading normal faces
# away from the viewer while the geometric one faces it, Cycles draws the material's colour; a
# renderer whose BSDF is 0 there draws black blocks.
#
#   bash bench/smooth_edges.sh [--spp N] [--cycles-spp N] [--cameras a,b,...] [--width W] [--height H]
#                              [--seed K] [--threads T] [--out DIR] [--remake] [--cycles-geometry-offset X]
#
# Defaults: 320 x 180, ours 1024 spp (seed 1), Cycles 1024 spp at seeds 1 and 2 (the reference is
# their mean; their difference its noise), cameras group_10, group_25, group_45, cylinder_15,
# suzanne_20 (every camera the scene has), Cycles on 2 threads, out bench-out/smooth-edges/.
# Cycles' renders and the scene are cached in --out (keyed by the scene's hash, camera, size, spp,
# geometry offset, seed): only ours is rendered on each run; --remake rebuilds the scene (and so the
# references). --cycles-geometry-offset: Cycles' shadow-terminator geometry offset of every mesh, 0 by
# default (Blender's own default, 0.1, lets a smooth face whose flat normal is turned from the sun,
# but whose interpolated normal is not, see the sun: a light-side difference this bench keeps out).
# Prints one Markdown table (a row per camera) and writes it to OUT/table-<binary tag>-go<offset>.md,
# with OUT/<camera>-<binary tag>-go<offset>.png (ours | Cycles | 4x4 block differences, yellow = a
# black block) and .json. The binary is copied to OUT/bin/ first (named by its hash; it embeds its
# kernels), so a rebuild during the run does not mix two binaries in one table.
#
# Environment: BUNDLEPATH (the renderer; default build/bundlepath), PYTHON (the peers' venv
# with bpy 5.0.1, numpy, OpenEXR; default bench-out/peers-venv/bin/python: bench/peers/setup.sh). Every render
# runs under nice -n 10. Exit status: 0 whatever the table says (it is a measurement); 1 when a
# render fails; 2 on bad usage.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
spp=1024
cycles_spp=1024
geometry_offset=0
cameras=group_10,group_25,group_45,cylinder_15,suzanne_20
width=320
height=180
seed=1
threads=2
out=$root/bench-out/smooth-edges
remake=0
while [ $# -gt 0 ]; do
  case $1 in
    --spp) spp=$2; shift 2 ;;
    --cycles-spp) cycles_spp=$2; shift 2 ;;
    --cycles-geometry-offset) geometry_offset=$2; shift 2 ;;
    --cameras) cameras=$2; shift 2 ;;
    --width) width=$2; shift 2 ;;
    --height) height=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --remake) remake=1; shift ;;
    -h|--help) sed -n '2,29p' "$0"; exit 0 ;;
    *) echo "smooth_edges.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
PYTHON=${PYTHON:-$root/bench-out/peers-venv/bin/python}
BUNDLEPATH=${BUNDLEPATH:-$root/build/bundlepath}
case $BUNDLEPATH in /*) ;; *) BUNDLEPATH=$PWD/$BUNDLEPATH ;; esac
[ -x "$BUNDLEPATH" ] || { echo "smooth_edges.sh: no renderer at $BUNDLEPATH (set BUNDLEPATH)" >&2; exit 2; }
[ -x "$PYTHON" ] || { echo "smooth_edges.sh: no python at $PYTHON (set PYTHON)" >&2; exit 2; }
mkdir -p "$out"

scene=$out/smooth-edges.glb
if [ "$remake" = 1 ] || [ ! -f "$scene" ] || ! grep -qs "^LIGHT " "$out/make.log"; then
  nice -n 10 "$PYTHON" "$root/scenes/blender/make_smooth_edges.py" "$scene" "$width" "$height" > "$out/make.log" 2>&1 ||
    { tail -20 "$out/make.log" >&2; exit 1; }
fi
# The world's radiance and the sun, as the scene script printed them ("LIGHT sun 3 W/m^2 world R,G,B").
world=$(sed -n 's/^LIGHT sun .* world \([0-9.,]*\)$/\1/p' "$out/make.log")
sun=$(sed -n 's/^LIGHT sun \([0-9.]*\) .*/\1/p' "$out/make.log")
[ -n "$world" ] || { echo "smooth_edges.sh: no LIGHT line in $out/make.log (run with --remake)" >&2; exit 1; }
tag=$(sha256sum "$scene" | cut -c1-10)
bin_tag=$(sha256sum "$BUNDLEPATH" | cut -c1-8)
bin=$out/bin/bundlepath-$bin_tag
if [ ! -x "$bin" ]; then mkdir -p "$out/bin"; cp "$BUNDLEPATH" "$bin.tmp"; mv "$bin.tmp" "$bin"; fi
cycles_version=$("$PYTHON" -c 'import bpy; print(bpy.app.version_string)' 2> /dev/null | tail -1)

render_cycles() {  # CAMERA SEED -> prints the EXR's path
  local prefix=$out/cycles-$tag-$1-${width}x$height-$cycles_spp-go$geometry_offset-s$2
  if [ ! -f "$prefix.exr" ]; then
    echo "smooth_edges.sh: Cycles $1 seed $2 ($cycles_spp spp)" >&2
    nice -n 10 "$PYTHON" "$root/bench/smooth_edges_cycles.py" "$scene" "$prefix.tmp" --camera "$1" --world "$world" \
      --width "$width" --height "$height" --spp "$cycles_spp" --seed "$2" --threads "$threads" \
      --geometry-offset "$geometry_offset" > "$prefix.log" 2>&1 || { tail -20 "$prefix.log" >&2; exit 1; }
    mv "$prefix.tmp.exr" "$prefix.exr"
    mv "$prefix.tmp.json" "$prefix.json"
  fi
  echo "$prefix.exr"
}
render_ours() {  # CAMERA -> prints the EXR's path
  local prefix=$out/ours-$bin_tag-$tag-$1-${width}x$height-$spp-s$seed
  echo "smooth_edges.sh: bundlepath $1 ($spp spp)" >&2
  nice -n 10 "$bin" render "$scene" --mode pt --spp "$spp" --width "$width" --height "$height" --seed "$seed" \
    --environment "$world" --camera "$1" --out "$prefix" > "$prefix.log" 2>&1 || { cat "$prefix.log" >&2; exit 1; }
  if grep -i "warning" "$prefix.log" >&2; then echo "smooth_edges.sh: (the warnings above are bundlepath's)" >&2; fi
  echo "$prefix.exr"
}

table=$out/table-$bin_tag-go$geometry_offset.md
{
  echo "Smooth edges: bundlepath \`$BUNDLEPATH\` (sha256 $bin_tag…) \`--mode pt --spp $spp --seed $seed\` against"
  echo "Cycles ${cycles_version:-5} at $cycles_spp spp x 2 seeds (shadow-terminator geometry offset $geometry_offset); ${width}x$height;"
  echo "scene $tag…; sun ${sun} W/m^2 (angle 0), world ${world} W sr^-1 m^-2."
  echo
} > "$table"
header=(--header)
IFS=, read -r -a cams <<< "$cameras"
for cam in "${cams[@]}"; do
  c1=$(render_cycles "$cam" 1)
  c2=$(render_cycles "$cam" 2)
  ours=$(render_ours "$cam")
  "$PYTHON" "$root/bench/smooth_edges_compare.py" "$ours" "$c1" "$c2" --label "$cam" "${header[@]}" \
    --png "$out/$cam-$bin_tag-go$geometry_offset.png" --json "$out/$cam-$bin_tag-go$geometry_offset.json" >> "$table"
  header=()
done
cat "$table"
echo "smooth_edges.sh: wrote $table and $out/<camera>-$bin_tag-go$geometry_offset.png" >&2
