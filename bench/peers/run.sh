#!/usr/bin/env bash
# The side-by-side harness of issue 29: one glTF scene rendered by bundlepath (defaults, --mode pt,
# --mode rb), Blender Cycles 5 (bpy 5.0.1; light tree, with and without path guiding) and
# LuxCoreRender 2.11 (pyluxcore; PATHCPU + DLS cache, mesh lights by light sampling only, with and
# without the PhotonGI indirect cache),
# each at the same wall-clock budgets and threads, one after the other, each compared with
# bundlepath's own long path-traced reference (bench/lib.sh bench_reference, seed 7) whose noise is
# measured against a second, independent reference (seed 8). Writes one Markdown table.
#
#   bash bench/peers/run.sh [--scene NAME] [--sizes 640x360,1280x720] [--budgets 10,30,120]
#                           [--threads 1] [--ref-spp N] [--renderers LIST] [--seed K]
#                           [--out DIR] [--results FILE.md] [--max-mean-rel X] [--label TEXT]
#                           [--second-seed]
#
#   --scene       cornell-box, cornell-glossy, rooms-100000, rooms-lambert-100000, or a .gltf/.glb
#                 (bench/lib.sh bench_scene)                                        [cornell-box]
#   --renderers   comma-separated, in order, from: bp (defaults, combined), bp-pt, bp-rb, cycles,
#                 cycles-guiding, luxcore, luxcore-photongi                         [all seven]
#                 (and luxcore-mis: mesh lights under LuxCore's MIS, for the record; luxcore-ocl:
#                 PATHOCL on every OpenCL device, its kernel compilation apart from set-up)
#   --ref-spp     the references' spp at 128x128 (scaled to SIZE by bench_reference_spp) [the
#                 scene's in bench/lib.sh BENCH_STUDY_SCENES, else 8192]
#   --threads     CPU threads of every renderer: Cycles' render.threads, LuxCore's
#                 native.threads.count, and PoCL's POCL_MAX_PTHREAD_COUNT for bundlepath on a PoCL
#                 CPU device (a GPU is what it is)                                  [1]
#   --max-mean-rel X  exit 1 when a render's image mean differs from the reference's by more
#                 than X (relative; the conventions check, bench/peers/check_conventions.sh)
#   --second-seed also render each at seed + 1: the table adds each renderer's own noise (half the
#                 relMSE between its two renders) and what its relMSE holds beyond that noise and
#                 the reference's (a model difference, a cache's or a discretisation's bias)
#   --out         renders, logs and JSON figures                     [bench-out/peers/<scene>]
#   --results     the table                        [bench/peers/results/<scene>-<date>.md]
#
# Needs bash bench/peers/setup.sh first (the venv, PEERS_VENV, default bench-out/peers-venv) and
# bundlepath (BUNDLEPATH, default build/bundlepath). Budgets are rendering time: bundlepath's
# --time, Cycles' time limit (it counts sampling only and overruns: the table gives the time Cycles
# reports), LuxCore's from its first pass (it builds its DLS and PhotonGI caches after starting);
# set-up (loading, kernels, BVH, caches) is its own column.
# Every render runs under `nice -n ${PEERS_NICE:-19}`; give the full table an idle machine.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
scene_name=cornell-box
sizes=640x360,1280x720
budgets=10,30,120
threads=1
ref_spp=
renderers=bp,bp-pt,bp-rb,cycles,cycles-guiding,luxcore,luxcore-photongi
seed=1
out=
results=
max_mean_rel=
label=
second_seed=
cmdline="bash bench/peers/run.sh $*"
while [ $# -gt 0 ]; do
  case $1 in
    --scene) scene_name=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --budgets) budgets=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --renderers) renderers=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --results) results=$2; shift 2 ;;
    --max-mean-rel) max_mean_rel=$2; shift 2 ;;
    --label) label=$2; shift 2 ;;
    --second-seed) second_seed=1; shift ;;
    -h|--help) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

cd "$root"
# shellcheck source=bench/lib.sh
source "$root/bench/lib.sh"
venv=${PEERS_VENV:-$root/bench-out/peers-venv}
py=$venv/bin/python
nice_n=${PEERS_NICE:-19}
for r in ${renderers//,/ }; do
  case $r in
    bp|bp-pt|bp-rb|cycles|cycles-guiding|luxcore|luxcore-photongi|luxcore-mis|luxcore-ocl) ;;
    *) echo "run.sh: unknown renderer $r" >&2; exit 2 ;;
  esac
done
# The venv also holds numpy and OpenEXR for the comparisons, so even a bundlepath-only run needs it.
if [ ! -x "$py" ] || ! "$py" -c 'import numpy, OpenEXR' 2> /dev/null; then
  echo "run.sh: no peers' venv at $venv (bash bench/peers/setup.sh, or set PEERS_VENV)" >&2
  exit 2
fi
scene=$(bench_scene "$scene_name")
[ -f "$scene" ] || { echo "run.sh: no scene $scene" >&2; exit 2; }
tag=$(bench_scene_name "$scene")
out=${out:-$root/bench-out/peers/$tag}
results=${results:-$here/results/$tag-$(date -u +%Y-%m-%d).md}
mkdir -p "$out" "$(dirname "$results")"
if [ -z "$ref_spp" ]; then
  ref_spp=8192
  for entry in "${BENCH_STUDY_SCENES[@]}"; do
    read -r n s <<< "$entry"
    [ "$n" = "$scene_name" ] && ref_spp=$s
  done
fi

bp_env=()
if "$BUNDLEPATH" devices 2>&1 | grep -q "Portable Computing Language; CPU"; then
  bp_env=(env "POCL_MAX_PTHREAD_COUNT=$threads")
fi

render_one() {  # RENDERER SIZE BUDGET PREFIX SEED -> PREFIX.exr, PREFIX.json (samples, render/set-up s)
  local r=$1 size=$2 budget=$3 prefix=$4 seed=$5 w=${2%x*} h=${2#*x}
  local t0 t1 rc=0
  t0=$(date +%s.%N)
  case $r in
    bp|bp-pt|bp-rb)
      local -a mode=()
      [ "$r" = bp-pt ] && mode=(--mode pt)
      [ "$r" = bp-rb ] && mode=(--mode rb)
      local -a dev
      mapfile -t dev < <(bench_device_args)
      nice -n "$nice_n" "${bp_env[@]}" "$BUNDLEPATH" render "$scene" "${mode[@]}" --width "$w" --height "$h" \
        --time "$budget" --seed "$seed" --out "$prefix" --stats "$prefix.bp.json" "${dev[@]}" \
        > "$prefix.log" 2>&1 || rc=$?
      t1=$(date +%s.%N)
      [ $rc = 0 ] || { tail -5 "$prefix.log" >&2; return $rc; }
      python3 - "$prefix.bp.json" "$prefix.json" "$t0" "$t1" "$r" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
wall = float(sys.argv[4]) - float(sys.argv[3])
spp = s.get("spp", 0)
its = sum(d.get("rb_iterations", 0) for d in s.get("devices", []))
samples = {"bp": "%d spp + %d it" % (spp, its), "bp-pt": "%d spp" % spp, "bp-rb": "%d it" % its}[sys.argv[5]]
json.dump({"renderer": "bundlepath", "spp": spp, "rb_iterations": its, "samples": samples,
           "render_seconds": s["render_seconds"], "setup_seconds": wall - s["render_seconds"],
           "wall_seconds": wall, "device": s.get("device", "")}, open(sys.argv[2], "w"), indent=1)
PY
      ;;
    cycles|cycles-guiding)
      local -a g=()
      [ "$r" = cycles-guiding ] && g=(--guiding)
      nice -n "$nice_n" "$py" "$here/cycles_peer.py" "$scene" "$prefix" --width "$w" --height "$h" \
        --time "$budget" --threads "$threads" --seed "$seed" "${g[@]}" > "$prefix.log" 2>&1 || rc=$?
      [ $rc = 0 ] || { tail -5 "$prefix.log" >&2; return $rc; }
      ;;
    luxcore|luxcore-photongi|luxcore-mis|luxcore-ocl)
      local -a g=()
      [ "$r" = luxcore-photongi ] && g=(--photongi)
      [ "$r" = luxcore-mis ] && g=(--mesh-lights mis)
      [ "$r" = luxcore-ocl ] && g=(--engine pathocl)
      nice -n "$nice_n" "$py" "$here/luxcore_peer.py" "$scene" "$prefix" --width "$w" --height "$h" \
        --time "$budget" --threads "$threads" --seed "$seed" "${g[@]}" > "$prefix.log" 2>&1 || rc=$?
      [ $rc = 0 ] || { tail -5 "$prefix.log" >&2; return $rc; }
      ;;
  esac
}

rows=$out/rows.jsonl
: > "$rows"
load_start=$(cut -d' ' -f1 /proc/loadavg)
for size in $(bench_resolutions "$sizes"); do
  spp=$(bench_reference_spp "$ref_spp" "$size")
  echo "run.sh: references of $tag at $size ($spp spp, seeds 7 and 8) ..." >&2
  # shellcheck disable=SC2016  # $1.. expand in the child shell
  ref=$(nice -n "$nice_n" bash -c 'source "$1/bench/lib.sh"; bench_reference "$2" "$3" "$4"' _ "$root" "$scene" "$spp" "$size")
  # shellcheck disable=SC2016
  ref2=$(BENCH_REF_FLAGS="${BENCH_REF_FLAGS:+$BENCH_REF_FLAGS }--seed 8" nice -n "$nice_n" \
    bash -c 'source "$1/bench/lib.sh"; bench_reference "$2" "$3" "$4"' _ "$root" "$scene" "$spp" "$size")
  noise=$("$py" "$here/compare.py" "$ref2" "$ref")
  python3 - "$rows" "$size" "$spp" "$ref" "$noise" <<'PY'
import json, sys
json.dump({"kind": "reference", "size": sys.argv[2], "spp": int(sys.argv[3]), "path": sys.argv[4],
           "noise": json.loads(sys.argv[5])}, open(sys.argv[1], "a"))
open(sys.argv[1], "a").write("\n")
PY
  for budget in ${budgets//,/ }; do
    for r in ${renderers//,/ }; do
      prefix=$out/$r-$size-${budget}s
      echo "run.sh: $r at $size, $budget s ..." >&2
      render_one "$r" "$size" "$budget" "$prefix" "$seed"
      stats=()  # the second seed's render; bundlepath's own error per block, and the reference's
      if [ -n "$second_seed" ]; then
        echo "run.sh: $r at $size, $budget s, seed $((seed + 1)) ..." >&2
        render_one "$r" "$size" "$budget" "$prefix-seed2" "$((seed + 1))"
        stats=(--second "$prefix-seed2.exr")
      fi
      [ -f "$prefix.bp.json" ] && stats+=(--stats "$prefix.bp.json" --reference-stats "${ref%.exr}.json")
      cmp=$("$py" "$here/compare.py" "$prefix.exr" "$ref" "${stats[@]}")
      python3 - "$rows" "$size" "$budget" "$r" "$prefix.json" "$cmp" <<'PY'
import json, sys
run = json.load(open(sys.argv[5]))
row = {"kind": "render", "size": sys.argv[2], "budget": float(sys.argv[3]), "renderer": sys.argv[4],
       "run": run, "compare": json.loads(sys.argv[6])}
with open(sys.argv[1], "a") as f:
    f.write(json.dumps(row) + "\n")
c = row["compare"]
print("run.sh:   relMSE %.4g, worst 8x8 block %.1f %%, image mean %+.2f %%, %s, render %.1f s, set-up %.1f s"
      % (c["rel_mse"], 100 * c["worst_block"], 100 * c["mean_rel"], run.get("samples", "%s spp" % run.get("spp")),
         run["render_seconds"], run["setup_seconds"]), file=sys.stderr)
if "noise_rel_mse" in c:
    print("run.sh:   its own noise (two seeds) %.4g" % c["noise_rel_mse"], file=sys.stderr)
PY
    done
  done
done

versions=$("$py" - <<'PY' 2> /dev/null || echo "peers: versions unknown"
import importlib.metadata as m
print("bpy %s, pyluxcore %s" % (m.version("bpy"), m.version("pyluxcore")))
PY
)
bp_version=$("$BUNDLEPATH" --version 2>&1 | head -1)
commit=$(git -C "$root" rev-parse --short HEAD 2> /dev/null || echo unknown)
cpu=$(sed -n 's/^model name\s*:\s*//p' /proc/cpuinfo | head -1)
python3 "$here/table.py" "$rows" --scene "$tag" --command "$cmdline" --machine "$cpu, $(nproc) cores" \
  --versions "$bp_version (commit $commit); $versions" --threads "$threads" --label "$label" \
  --load "$load_start, $(cut -d' ' -f1 /proc/loadavg)" \
  ${max_mean_rel:+--max-mean-rel "$max_mean_rel"} > "$results.tmp" || rc=$?
mv "$results.tmp" "$results"
echo "run.sh: wrote $results" >&2
exit "${rc:-0}"
