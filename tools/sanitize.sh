#!/usr/bin/env bash
# Builds build-asan/ with clang, AddressSanitizer and UndefinedBehaviorSanitizer (float
# division by zero and float-to-int overflow included, no recovery, leaks detected), and runs
# the tests there (all but tests/sanitizer-skip.txt). Installs what is missing, like tools/test.sh. Extra arguments go to ctest.
#
# -O1 -gline-tables-only (tools/deps.sh): reports carry file and line, and it builds far
# quicker than -O2 -g. The microbenchmarks are not built (ctest runs none), and the few
# tests in tests/sanitizer-skip.txt are left to the Release job.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/deps.sh
rengine_install_deps clang libclang-rt-14-dev
# fuzzer-no-link: coverage instrumentation, so the same build also holds the libFuzzer
# targets of tests/fuzz (tools/fuzz.sh); the tests' own mains are unaffected.
flags="-fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero,fuzzer-no-link -fno-sanitize-recover=all -fno-omit-frame-pointer"
rengine_clang_configure build-asan "$flags" -DRENGINE_BUILD_FUZZERS=ON -DRENGINE_BUILD_BENCH=OFF
cmake --build build-asan
[ "${RENGINE_SANITIZE_BUILD_ONLY:-0}" = 1 ] && exit 0
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# install_consumer builds a separate project against the installed engine with the default
# compiler and no sanitizer runtime; it is a packaging test, covered by the Release run.
skip=$(grep -v '^#' tests/sanitizer-skip.txt | sed 's/[.]/[.]/g' | paste -sd '|')
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E "^(install_consumer|$skip)\$" "$@"
