#!/usr/bin/env bash
# Makes docs/images/rerun_replay.png: the Rerun viewer showing `softarm demo`'s replay, rendered headless.
#
#     softarm demo --folder /tmp/demo && bash docs/scripts/rerun_screenshot.sh /tmp/demo/replay.rrd
#
# Needs Xvfb, xdotool, ImageMagick and a software Vulkan driver (Debian: xvfb xdotool imagemagick
# mesa-vulkan-drivers). The pointer is parked outside the 1400x860 window so that no hover tooltip is drawn.
set -euo pipefail
rrd=${1:?give the .rrd to show}
out=$(dirname "$0")/../images/rerun_replay.png
Xvfb :97 -screen 0 3000x2000x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb' EXIT
sleep 1
DISPLAY=:97 xdotool mousemove 2990 1990
DISPLAY=:97 XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp} rerun "$rrd" --screenshot-to /tmp/rerun_screenshot.png \
    --window-size 1400x860 >/dev/null 2>&1
convert /tmp/rerun_screenshot.png -resize 1400x860 -strip "PNG8:$out"
echo "$out"
