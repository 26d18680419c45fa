#!/usr/bin/env bash
# The README's second command: installs what is missing, builds (Release), runs the whole test suite,
# then fuzzes the glTF loader for BUNDLEPATH_FUZZ_SECONDS (default 60; 0 skips it) with
# scripts/fuzz.sh. A failed test or a fuzzer finding (crash, sanitizer report, leak, hang) fails it.
set -euo pipefail
cd "$(dirname "$0")/.."
fuzz_seconds="${BUNDLEPATH_FUZZ_SECONDS:-60}"
# gnuplot-nox: the bench smoke test (bench_quick_smoke) then draws its plots too; ffmpeg: the
# walkthrough's --video test (Walkthrough.VideoEncodesEveryFrame) then runs rather than skips;
# --oidn: OpenImageDenoise for --denoise, whose tests then must find it (BUNDLEPATH_TEST_REQUIRE_OIDN).
if [ "$fuzz_seconds" -gt 0 ]; then bash scripts/setup.sh --fuzz --oidn gnuplot-nox ffmpeg; else bash scripts/setup.sh --oidn gnuplot-nox ffmpeg; fi
export BUNDLEPATH_TEST_REQUIRE_OIDN=1
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
status=0
ctest --test-dir build --output-on-failure -j "$(nproc)" --timeout 600 || status=$?
fuzz_status=0
if [ "$fuzz_seconds" -gt 0 ]; then bash scripts/fuzz.sh "$fuzz_seconds" || fuzz_status=$?; fi
if [ "$status" -ne 0 ]; then echo "test: the test suite failed" >&2; exit "$status"; fi
if [ "$fuzz_status" -ne 0 ]; then echo "test: the fuzzer found a problem" >&2; exit "$fuzz_status"; fi
