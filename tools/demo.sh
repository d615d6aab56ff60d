#!/usr/bin/env bash
# Installs what is missing, builds, runs the default scene and writes its trajectory and a
# plot: build/demo/trajectory.csv and build/demo/demo.png; then, where they are built, the
# trajectory played back by rengine-view (build/demo/view.png) and the space game's
# autoplay (build/demo/spacegame.png), in a window, or under xvfb-run without a display.
#   tools/demo.sh [SCENE.json]   (default: the Dzhanibekov tumbling box)
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/deps.sh
rengine_install_deps python3-matplotlib
rengine_build
scene="${1:-../shared/scenes/dzhanibekov.json}"
mkdir -p build/demo
build/bin/rengine-sim "$scene" --out build/demo/trajectory.csv --every 6
build/bin/rengine-sim "$scene" --describe > build/demo/describe.json
# Debian's matplotlib lives in /usr/bin/python3, not in whatever python3 is first on PATH.
/usr/bin/python3 tools/plot_trajectory.py build/demo/trajectory.csv build/demo/describe.json \
  build/demo/demo.png
echo "wrote build/demo/trajectory.csv and build/demo/demo.png"
if [ -x build/bin/rengine-spacegame ] && [ -x build/bin/rengine-view ]; then
  display=()
  [ -z "${DISPLAY:-}" ] && display=(xvfb-run -a -s "-screen 0 1280x800x24")
  "${display[@]}" build/bin/rengine-view "$scene" build/demo/trajectory.csv --frames 240 --speed 10 \
    --screenshot build/demo/view.png
  "${display[@]}" build/bin/rengine-spacegame --autoplay --frames 900 \
    --screenshot build/demo/spacegame.png
  echo "wrote build/demo/view.png and build/demo/spacegame.png"
fi
