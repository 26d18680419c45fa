#!/usr/bin/env bash
# Builds the host code with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan and runs
# the whole test suite there. The kernels run in PoCL, which is not instrumented: ASan and UBSan see
# host code only, LeakSanitizer sees every allocation, so its reports from the OpenCL runtime are
# suppressed by tests/sanitizers/lsan.supp (libraries by name only; leaks with any host frame on
# top still fail). Any sanitizer report fails the test that triggered it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh

start=$(date +%s)
cmake -S . -B build-asan -DBUNDLEPATH_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBUNDLEPATH_BUILD_BENCH=OFF
cmake --build build-asan -j "$(nproc)"
built=$(date +%s)

supp="$PWD/tests/sanitizers/lsan.supp"
# detect_leaks stays on; abort_on_error gives a core-less abort that ctest reports as a failure.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
export LSAN_OPTIONS="suppressions=$supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" --timeout 1200 || status=$?
end=$(date +%s)
echo "sanitizers: build $((built - start)) s, tests $((end - built)) s"
exit "$status"
