#!/usr/bin/env bash
# Drives the split view with xdotool (test_editor_split.cpp): the editor on headsq with --split and
# --split-difference; a 100 px drag to the right in the right pane; a screenshot once the turned view is
# drawn. Run under its own X server (xvfb-run), from the test.
#   split_drag.sh SPLATLAB VOLUME OUT_DIR DRAG_X DRAG_Y
# The editor closes on SIGTERM and writes OUT_DIR/session.json (--session-out).
set -euo pipefail
source "$(dirname "$0")/editor_session.sh"
exe=$1 volume=$2 out=$3 x=$4 y=$5
cd "$out"
start_editor "$out" "$exe" editor "$volume" --up -z --camera 40,20,2.5,30 \
  --compositing sheet-front-to-back --split reconstruction,low-pass --split-difference --size 1280x800 \
  --session-out "$out/session.json"
# 100 px to the right in the right pane, the pointer moving on (off the viewport) after the release.
before=$(cat "$out/ready")   # the finished images the editor has shown
xdotool mousemove --window "$w" "$x" "$y" mousedown 1 mousemove --window "$w" $((x + 50)) "$y" \
        mousemove --window "$w" $((x + 100)) "$y" mouseup 1 mousemove --window "$w" 1200 700
# The turned view's three panes: a newer finished image, then none for 2 s (the drag's steps may each
# finish one). About a second on llvmpipe; far longer in the sanitizers' build on a loaded machine.
for _ in $(seq 600); do [ "$(cat "$out/ready")" != "$before" ] && break; sleep 0.2; done
last=$(cat "$out/ready")
for _ in $(seq 60); do
  sleep 2
  now=$(cat "$out/ready")
  [ "$now" = "$last" ] && break
  last=$now
done
sleep 0.5 # the image onto the screen by the next UI frame
import -window root "$out/split_drag.png"
stop_editor
