#!/usr/bin/env bash
# Runs the libFuzzer targets of tests/fuzz: for each, replays its committed corpus (every
# seed and reproducer must pass), then fuzzes for a while. Builds them in build-asan/ with the
# sanitizers (tools/sanitize.sh's build, which includes them).
#
#   tools/fuzz.sh [--seconds N] [--merge] [target ...]   # default: all five, 60 s each
#   tools/fuzz.sh --ci                                    # replay, then a fixed fuzz run
#
# --ci fuzzes a fixed number of inputs from a fixed seed (about 30 s a target here), so a CI
# run is reproducible: what passes on a developer's machine passes in CI, and a failure there
# replays anywhere. Open-ended fuzzing (random seeds, wall-clock budgets) is for developers.
#
# New inputs that add coverage go to build-asan/fuzz-new/<target>/, not to the committed
# corpus, unless --merge (then they are minimised into tests/fuzz/corpus/<target>/). A crash,
# a failed check, a leak, a timeout or an out-of-memory stops with exit 1 and names the
# reproducer file (libFuzzer writes it to build-asan/fuzz-crashes/).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60 merge=0 ci=0 targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --ci) ci=1; shift ;;
    --merge) merge=1; shift ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_scene fuzz_hull fuzz_narrowphase fuzz_world fuzz_state)
RENGINE_SANITIZE_BUILD_ONLY=1 ./tools/sanitize.sh
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p build-asan/fuzz-crashes
for t in "${targets[@]}"; do
  corpus=tests/fuzz/corpus/$t
  scratch=build-asan/fuzz-new/$t
  mkdir -p "$scratch"
  flags=(-max_len=262144 -timeout=10 -rss_limit_mb=2048 -artifact_prefix=build-asan/fuzz-crashes/$t-
         -dict=tests/fuzz/scene.dict)
  [ "$t" = fuzz_scene ] || flags=("${flags[@]:0:4}")
  echo "== $t: replaying $(ls "$corpus" | wc -l) inputs"
  build-asan/bin/$t "${flags[@]}" -runs=0 "$corpus"
  log=build-asan/fuzz-$t.log
  status=0
  if [ "$ci" = 1 ]; then
    case "$t" in  # inputs for about 30 s each on a 2-core machine under the sanitizers
      fuzz_scene) runs=400000 ;; fuzz_hull) runs=60000 ;; fuzz_narrowphase) runs=40000 ;; fuzz_state) runs=1500 ;;
      *) runs=12000 ;;
    esac
    echo "== $t: fuzzing $runs inputs from seed 1"
    rm -rf "$scratch" && mkdir -p "$scratch"
    build-asan/bin/$t "${flags[@]}" -seed=1 -runs="$runs" -print_final_stats=1 \
      "$scratch" "$corpus" >"$log" 2>&1 || status=$?
  else
    echo "== $t: fuzzing for ${seconds} s"
    build-asan/bin/$t "${flags[@]}" -max_total_time="$seconds" -print_final_stats=1 \
      "$scratch" "$corpus" >"$log" 2>&1 || status=$?
  fi
  grep -E "^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb)" "$log" || true
  if [ "$status" -ne 0 ]; then
    grep -E "check failed|ERROR|SUMMARY|runtime error|artifact|Test unit written" "$log" >&2 || tail -20 "$log" >&2
    echo "$t: FAILED (exit $status); reproducer in build-asan/fuzz-crashes/, log $log" >&2
    exit 1
  fi
  if [ "$merge" = 1 ]; then build-asan/bin/$t "${flags[@]}" -merge=1 "$corpus" "$scratch"; fi
done
echo "each target's corpus replayed and fuzzed without a failure"
echo "fuzz: ${#targets[@]} passed, 0 failed"
