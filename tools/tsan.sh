#!/usr/bin/env bash
# Builds build-tsan/ with clang and ThreadSanitizer and runs the tests that step worlds on
# several threads (threads_tests: 1, 2 and 4 threads and a game's job system; broadphase_tests).
# A data race between the step's tasks would make results depend on timing; TSan finds the
# race even when this run's results happen to agree. Installs what is missing, like
# tools/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/deps.sh
rengine_install_deps clang libclang-rt-14-dev
flags="-fsanitize=thread -fno-omit-frame-pointer"
rengine_clang_configure build-tsan "$flags" -DRENGINE_BUILD_TOOLS=OFF
cmake --build build-tsan --target threads_tests broadphase_tests
export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
build-tsan/bin/threads_tests
build-tsan/bin/broadphase_tests
echo "tsan: passed"
