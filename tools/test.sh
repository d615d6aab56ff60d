#!/usr/bin/env bash
# Installs what is missing, builds build/ (Release, Ninja) and runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/deps.sh
rengine_install_deps
rengine_build
ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
