#!/usr/bin/env bash
# Drives the split view's |A - truth| pane with xdotool (test_editor_split.cpp): the editor on the
# far-away demo scene with every truth delayed 6 s (SPLATLAB_TRUTH_DELAY_MS, a slow scan's truth); a
# screenshot once the first view's difference is shown, a 60 px drag in pane A, a screenshot 3 s later
# (the new view drawn, its truth still waiting), and one once that view's difference is shown. The truth
# runs below the UI's priority, so on a loaded machine it takes its time: the script waits for it, up to
# two minutes each, by the mean of a patch of the difference pane (its image is inferno's dark end, the
# empty pane the lighter background).
# Run under its own X server (xvfb-run), from the test.
#   split_truth_move.sh SPLATLAB OUT_DIR DRAG_X DRAG_Y PATCH   (PATCH: WxH+X+Y in the difference pane)
set -euo pipefail
source "$(dirname "$0")/editor_session.sh"
exe=$1 out=$2 x=$3 y=$4 patch=$5
cd "$out"
start_editor "$out" SPLATLAB_TRUTH_DELAY_MS=6000 SPLATLAB_CACHE_DIR="$out/cache" "$exe" editor \
  --scene far-away --split reconstruction,ewa --split-difference truth --size 1280x800 \
  --session-out "$out/session.json"
shown() { # the difference image fills the patch: its mean below the background's (0.063)
  import -window root "$1"
  [ "$(convert "$1" -crop "$patch" +repage -colorspace gray -format '%[fx:mean<0.03]' info:)" = 1 ]
}
for _ in $(seq 120); do shown "$out/truth_before.png" && break; sleep 1; done
xdotool mousemove --window "$w" "$x" "$y" mousedown 1 mousemove --window "$w" $((x + 30)) "$y" \
        mousemove --window "$w" $((x + 60)) "$y" mouseup 1 mousemove --window "$w" 1200 700
sleep 3
import -window root "$out/truth_moved.png"
for _ in $(seq 120); do shown "$out/truth_after.png" && break; sleep 1; done
stop_editor
