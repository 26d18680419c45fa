#!/usr/bin/env bash
# RB's error through a glazed window at fixed work: scenes/glass-window.gltf (a room lit only by a
# sun through a thin pane) against the same room with the pane taken out (an open window), each
# rendered --mode combined --ratio 1/4 at 16 and 64 spp (64 and 256 ray-bundle iterations) and
# compared with a 1024-spp path-traced reference of its own (`bundlepath compare --json`).
#
# Usage: bench/glass_window.sh [OUT_DIR]   [default: bench/results/glass-window]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
bin=${BUNDLEPATH:-$root/build/bundlepath}
out=${1:-$here/results/glass-window}
mkdir -p "$out"
python3 - "$root/scenes/glass-window.gltf" "$out/open-window.gltf" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
pane = next(i for i, n in enumerate(doc["nodes"]) if n.get("name") == "glass")
doc["scenes"][0]["nodes"] = [i for i in doc["scenes"][0]["nodes"] if i != pane]
json.dump(doc, open(sys.argv[2], "w"))
PY
for name in glass-window open-window; do
  scene=$root/scenes/glass-window.gltf
  [ "$name" = open-window ] && scene=$out/open-window.gltf
  "$bin" render "$scene" --width 96 --mode pt --spp 1024 --seed 11 --out "$out/ref-$name" > /dev/null
  for spp in 16 64; do
    "$bin" render "$scene" --width 96 --mode combined --ratio 1/4 --spp "$spp" --seed 3 --out "$out/$name-$spp" > /dev/null
    echo "$name $spp spp: $("$bin" compare "$out/$name-$spp.exr" "$out/ref-$name.exr" --json)"
  done
done | tee "$out/compare.txt"
