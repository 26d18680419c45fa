#!/usr/bin/env bash
# Renders a long path-traced reference of SCENE once and caches it outside the source tree
# (${BENCH_CACHE:-~/.cache/bundlepath}/references/<scene>-<content hash>-pt-<size>-<spp>.exr; the
# hash of the scene file keeps a changed scene from reusing a stale image). The render runs in
# chunks of BENCH_REF_CHUNK seconds (120) with --checkpoint, so a reference that is interrupted
# (Ctrl-C, a killed job, a reboot) continues where it stopped when asked for again; the result is
# bit for bit the uninterrupted render (seed 7). Prints the .exr's path.
# Usage: bench/reference.sh SCENE [SPP] [SIZE]     (defaults 16384 spp, 128x128; SIZE: N or WxH)
#   SCENE: a .gltf/.glb path, a name under scenes/ (cornell-box), rooms-N (procedural rooms of
#   N triangles, written by the make_rooms tool) or rooms-lambert-N (the same, every material
#   Lambert). BENCH_REF_FLAGS adds renderer flags.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
if [ $# -lt 1 ] || [ "$1" = -h ] || [ "$1" = --help ]; then sed -n '2,11p' "$0"; exit 2; fi
scene=$(bench_scene "$1")
bench_reference "$scene" "${2:-16384}" "${3:-128}"
