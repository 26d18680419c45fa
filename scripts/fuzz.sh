#!/usr/bin/env bash
# Fuzzes the glTF loader for SECONDS (default 60) with libFuzzer + ASan + UBSan: builds fuzz/ into
# build-fuzz (a standalone project, never part of the main build; FUZZ_BUILD_DIR=DIR for another) and
# runs it on a copy of the seed corpus (every file under tests/data/gltf/). Exits non-zero on a crash,
# sanitizer report, leak, timeout (> 5 s for one input) or out-of-memory; the reproducer lands in
# build-fuzz/artifacts/. scripts/test.sh (CI) runs it for 60 s after the test suite.
# Reproduce one:  build-fuzz/fuzz_gltf_loader build-fuzz/artifacts/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
dir="${FUZZ_BUILD_DIR:-build-fuzz}"
bash scripts/setup.sh --fuzz  # the project's packages, plus the fuzzer's

cxx="$(command -v clang++-14 || command -v clang++)"
start=$(date +%s)
cmake -S fuzz -B "$dir" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build "$dir" -j "$(nproc)"
echo "fuzz: target built in $(( $(date +%s) - start )) s"

corpus="$dir/corpus"
artifacts="$dir/artifacts"
rm -rf "$corpus"
mkdir -p "$corpus" "$artifacts"
find tests/data/gltf -type f \( -name '*.gltf' -o -name '*.glb' \) -exec cp {} "$corpus"/ \;

echo "fuzz: ${seconds} s on $(ls "$corpus" | wc -l) seed files"
status=0
"$dir/fuzz_gltf_loader" "$corpus" -dict=fuzz/gltf.dict -max_total_time="$seconds" -timeout=5 \
  -rss_limit_mb=2048 -report_slow_units=1 -print_final_stats=1 -artifact_prefix="$artifacts/" \
  2> "$dir/fuzz.log" || status=$?
grep -E '^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::average_exec_per_sec|Slowest unit)' "$dir/fuzz.log" || true
echo "fuzz: corpus now $(ls "$corpus" | wc -l) files"
if [ "$status" -ne 0 ]; then
  grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$dir/fuzz.log" | head -20
  echo "fuzz: FAILED (exit $status); full log in $dir/fuzz.log, reproducer in $artifacts/" >&2
  exit "$status"
fi
echo "fuzz: no crash"
