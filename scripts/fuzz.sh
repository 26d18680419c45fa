#!/usr/bin/env bash
# Fuzzes the glTF loader for SECONDS (default 60) with libFuzzer + ASan + UBSan: builds fuzz/ into
# build-fuzz (a standalone project, never part of the main build) and runs it on a copy of the seed
# corpus (every file under tests/data/gltf/). Exits non-zero on a crash, sanitizer report, leak,
# timeout (> 5 s for one input) or out-of-memory; the reproducer lands in build-fuzz/artifacts/.
# Reproduce one:  build-fuzz/fuzz_gltf_loader build-fuzz/artifacts/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
bash scripts/setup.sh clang-14 libclang-rt-14-dev  # the project's packages, plus the fuzzer's

cxx="$(command -v clang++-14 || command -v clang++)"
cmake -S fuzz -B build-fuzz -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build build-fuzz -j "$(nproc)"

corpus=build-fuzz/corpus
artifacts=build-fuzz/artifacts
rm -rf "$corpus"
mkdir -p "$corpus" "$artifacts"
find tests/data/gltf -type f \( -name '*.gltf' -o -name '*.glb' \) -exec cp {} "$corpus"/ \;

echo "fuzz: ${seconds} s on $(ls "$corpus" | wc -l) seed files"
status=0
build-fuzz/fuzz_gltf_loader "$corpus" -dict=fuzz/gltf.dict -max_total_time="$seconds" -timeout=5 \
  -rss_limit_mb=2048 -report_slow_units=1 -print_final_stats=1 -artifact_prefix="$artifacts/" \
  2> build-fuzz/fuzz.log || status=$?
grep -E '^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::average_exec_per_sec|Slowest unit)' build-fuzz/fuzz.log || true
echo "fuzz: corpus now $(ls "$corpus" | wc -l) files"
if [ "$status" -ne 0 ]; then
  grep -E 'ERROR|SUMMARY|runtime error|Test unit written' build-fuzz/fuzz.log | head -20
  echo "fuzz: FAILED (exit $status); full log in build-fuzz/fuzz.log" >&2
  exit "$status"
fi
echo "fuzz: no crash"
