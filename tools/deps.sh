# Sourced by tools/test.sh and tools/demo.sh: installs the Debian packages REngine needs,
# only those missing, so a ready machine never calls apt.
#   rengine_install_deps [extra packages...]
# Optional packages are not in the list: pass them as extras when wanted, e.g.
#   rengine_install_deps libbullet-dev   # Bullet: bench_bullet and rengine-bench's Bullet series
REngine_BUILD_PACKAGES=(
  cmake ninja-build g++         # toolchain
  libeigen3-dev                 # REngineMath
  nlohmann-json3-dev            # scene files (REngine::Scene)
  libcli11-dev                  # rengine-sim's command line
  libqhull-dev                  # convex hulls (RConvexPolyhedron::Hull)
  libgtest-dev                  # tests
  libbenchmark-dev              # tools/bench (Google Benchmark)
  libccd-dev libfcl-dev         # independent oracles for the collision tests
  # rengine-spacegame: window and GL, the HUD, screenshots (stb_image_write); its
  # windowed test runs under a virtual display with Mesa's software OpenGL.
  libsdl2-dev libepoxy-dev libimgui-dev libstb-dev pkgconf   # (pkgconf: CMake finds them by pkg-config)
  xvfb xauth libgl1-mesa-dri
)

rengine_install_deps() {
  local wanted=("${REngine_BUILD_PACKAGES[@]}" "$@") missing=() p
  for p in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing: ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Configures build/ (Release, Ninja) once and builds everything.
rengine_build() {
  local root
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  if [ ! -f "$root/build/build.ninja" ]; then
    cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release
  fi
  cmake --build "$root/build"
}

# Configures DIR once with clang and the given compile and link FLAGS (RelWithDebInfo made
# -O1 -gline-tables-only: reports carry file and line, and it builds far quicker than -O2 -g);
# further arguments go to cmake. tools/sanitize.sh, tools/tsan.sh.
rengine_clang_configure() {
  local dir="$1" flags="$2"
  shift 2
  if [ ! -f "$dir/build.ninja" ]; then
    CC=clang CXX=clang++ cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags"
  fi
}
