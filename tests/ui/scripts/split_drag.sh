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
xdotool mousemove --window "$w" "$x" "$y" mousedown 1 mousemove --window "$w" $((x + 50)) "$y" \
        mousemove --window "$w" $((x + 100)) "$y" mouseup 1 mousemove --window "$w" 1200 700
sleep 8 # the turned view's three panes drawn (about a second on llvmpipe)
import -window root "$out/split_drag.png"
stop_editor
