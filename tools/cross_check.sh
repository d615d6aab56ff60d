#!/usr/bin/env bash
# The same scene gives the same bits on x86-64 and 64-bit ARM, with gcc and clang, at -O2 and
# -O3: builds rengine-sim in each configuration below (the engine and rengine-sim only: no
# tests, benchmarks or samples, so none of their dependencies), runs every reference scene
# (scenes/*.json, their own step counts, one thread; ARM builds under qemu-aarch64) and
# compares each final hash= with the first configuration's. Prints a table; exits 1 on any
# difference. Installs what is missing (Debian 12, as root or through sudo): the arm64
# cross compiler, qemu-user, and the arm64 multiarch Qhull (Eigen, nlohmann-json and CLI11
# are headers, shared by both architectures).
#   tools/cross_check.sh                       the eight configurations (first run: about 35 min
#                                              of building on two cores, then 4 min of runs)
#   tools/cross_check.sh x86-gcc-O3 arm-gcc-O3 only those (the first is the reference)
# Builds go to build-cross/NAME (with ccache where installed); x86-gcc-O3 is the tests'
# build (Release), whose hashes tests/tools/cli_test.cpp pins.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"

all=(x86-gcc-O3 x86-gcc-O2 x86-clang-O3 x86-clang-O2 arm-gcc-O3 arm-gcc-O2 arm-clang-O3 arm-clang-O2)
configs=("$@")
[ ${#configs[@]} -eq 0 ] && configs=("${all[@]}")

# ---- packages ----
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  echo "adding the arm64 architecture to dpkg" >&2
  $sudo dpkg --add-architecture arm64
  $sudo apt-get update -qq
fi
wanted=(cmake ninja-build g++ clang libeigen3-dev nlohmann-json3-dev libcli11-dev libqhull-dev
        g++-aarch64-linux-gnu qemu-user libqhull-dev:arm64 libstdc++-12-dev:arm64)
missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

# ---- builds ----
# NAME = arch-compiler-level. The optimisation level replaces the build type's flags.
build() {
  local name="$1" arch compiler level dir
  IFS=- read -r arch compiler level <<<"$name"
  dir="$root/build-cross/$name"
  local args=(-G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-$level -DNDEBUG"
              -DRENGINE_BUILD_TESTS=OFF -DRENGINE_BUILD_SAMPLES=OFF -DRENGINE_BUILD_BENCH=OFF
              -DRENGINE_INSTALL=OFF "${launcher[@]}")
  case "$arch-$compiler" in
    x86-gcc) args+=(-DCMAKE_CXX_COMPILER=g++) ;;
    x86-clang) args+=(-DCMAKE_CXX_COMPILER=clang++) ;;
    arm-gcc|arm-clang)
      args+=(-DCMAKE_TOOLCHAIN_FILE="$root/cmake/toolchains/aarch64-linux-gnu.cmake"
             -DRENGINE_CROSS_COMPILER="$compiler") ;;
    *) echo "unknown configuration: $name (known: ${all[*]})" >&2; exit 2 ;;
  esac
  if [ ! -f "$dir/build.ninja" ]; then
    cmake -S "$root" -B "$dir" "${args[@]}" >"$dir.log" 2>&1 ||
      { cat "$dir.log" >&2; echo "configuring $name failed" >&2; exit 2; }
  fi
  local start=$SECONDS
  nice ninja -C "$dir" rengine-sim >>"$dir.log" 2>&1 ||
    { tail -n 30 "$dir.log" >&2; echo "building $name failed" >&2; exit 2; }
  echo "built $name in $((SECONDS - start)) s" >&2
}
mkdir -p build-cross
for c in "${configs[@]}"; do build "$c"; done

# ---- runs ----
# Every reference scene, with the step count it gives itself (under qemu the slowest,
# debris_cloud_1000, takes about 15 s).
scenes=()
for f in scenes/*.json; do scenes+=("$(basename "$f" .json)"); done
run() {
  local name="$1" scene="$2" sim="$root/build-cross/$1/bin/rengine-sim" out
  case "$name" in
    arm-*) out=$(nice qemu-aarch64 "$sim" "scenes/$scene.json" --threads 1 --out /dev/null 2>&1) || true ;;
    *) out=$(nice "$sim" "scenes/$scene.json" --threads 1 --out /dev/null 2>&1) || true ;;
  esac
  grep -o 'hash=[0-9a-f]*' <<<"$out" | tail -n 1 | cut -d= -f2 || true  # none: "(failed)" below
}
declare -A hash
for c in "${configs[@]}"; do
  start=$SECONDS
  for s in "${scenes[@]}"; do hash[$c/$s]=$(run "$c" "$s"); done
  echo "ran $c in $((SECONDS - start)) s" >&2
done

# ---- table ----
differ=0
printf '| %-20s |' scene
for c in "${configs[@]}"; do printf ' %-17s |' "$c"; done
printf '\n| %s |' "$(printf -- '-%.0s' {1..20})"
for c in "${configs[@]}"; do printf ' %s |' "$(printf -- '-%.0s' {1..17})"; done
printf '\n'
for s in "${scenes[@]}"; do
  ref="${hash[${configs[0]}/$s]}"
  printf '| %-20s |' "$s"
  for c in "${configs[@]}"; do
    h="${hash[$c/$s]}"
    if [ -z "$h" ] || [ "$h" != "$ref" ]; then
      differ=1
      printf ' %-17s |' "${h:-(failed)} *"
    elif [ "$c" = "${configs[0]}" ]; then
      printf ' %-17s |' "$h"
    else
      printf ' %-17s |' "same"
    fi
  done
  printf '\n'
done
if [ "$differ" -ne 0 ]; then
  echo "cross_check: hashes differ (marked *) from ${configs[0]}" >&2
  exit 1
fi
echo "cross_check: every scene gives the same hash in all ${#configs[@]} configurations" >&2
