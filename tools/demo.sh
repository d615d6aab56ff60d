#!/usr/bin/env bash
# Installs what is missing, builds, runs the default scene and writes its trajectory and a
# plot: build/demo/trajectory.csv and build/demo/demo.png; then, where they are built, the
# trajectory played back by rengine-view (build/demo/view.png) and the space game's
# autoplay (build/demo/spacegame.png, its last frame, and build/demo/spacegame.gif, every 6th
# of its 900 frames at 640x360 put together by ImageMagick), in a window, or under xvfb-run
# without a display; and says how to play the game on a machine with a display.
#   tools/demo.sh [SCENE.json]   (default: the Dzhanibekov tumbling box)
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/deps.sh
rengine_install_deps python3-matplotlib
rengine_build
scene="${1:-scenes/dzhanibekov.json}"
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
  # The same autoplay seen from behind the crew member walking round the station's ring.
  "${display[@]}" build/bin/rengine-spacegame --autoplay --frames 300 --crew \
    --screenshot build/demo/crew.png
  echo "wrote build/demo/view.png, build/demo/spacegame.png and build/demo/crew.png"
  # The animation: the same autoplay (the same hash) without the HUD, every 6th frame kept
  # (10 a second of its 60), then a looping GIF of them. ImageMagick is for the demo only.
  rengine_install_deps imagemagick
  rm -rf build/demo/frames
  "${display[@]}" build/bin/rengine-spacegame --autoplay --frames 900 --width 640 --height 360 \
    --no-hud --record build/demo/frames --record-every 6
  # Debian's convert, not whatever convert is first on PATH. -delay is in 1/100 s: 10 frames a
  # second, real time; -layers Optimize keeps only what changes from frame to frame.
  /usr/bin/convert -delay 10 -loop 0 build/demo/frames/frame_*.png -layers Optimize \
    build/demo/spacegame.gif
  echo "wrote build/demo/spacegame.gif ($(ls build/demo/frames | wc -l) frames of build/demo/frames/," \
    "$(du -k build/demo/spacegame.gif | cut -f1) KB)"
  cat <<'PLAY'
to play on a machine with a display: build/bin/rengine-spacegame
  W/S thrust  A/D yaw  up/down pitch  Q/E roll  left/right strafe  R/V up/down
  space laser  F missile  G dock (near a port)  C camera  1-4 debug drawing  Esc quit
  (build/bin/rengine-spacegame --autoplay flies the scripted run in the window, unthrottled)
PLAY
fi
