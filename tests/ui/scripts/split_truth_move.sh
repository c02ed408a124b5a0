#!/usr/bin/env bash
# Drives the split view's |A - truth| pane with xdotool (test_editor_split.cpp): the editor on the
# far-away demo scene with every truth delayed 2 s (SPLATLAB_TRUTH_DELAY_MS, a slow scan's truth);
# a screenshot once the first view's (coarse) truth is shown, a 60 px drag in pane A, a screenshot 1.5 s
# later (the new view drawn, its truth still waiting), and one once that view's coarse truth is in.
# Run under its own X server (xvfb-run), from the test.
#   split_truth_move.sh SPLATLAB OUT_DIR DRAG_X DRAG_Y
set -euo pipefail
source "$(dirname "$0")/editor_session.sh"
exe=$1 out=$2 x=$3 y=$4
cd "$out"
start_editor "$out" SPLATLAB_TRUTH_DELAY_MS=2000 SPLATLAB_CACHE_DIR="$out/cache" "$exe" editor \
  --scene far-away --split reconstruction,ewa --split-difference truth --size 1280x800 \
  --session-out "$out/session.json"
sleep 5 # rest 0.3 s, the delay and the coarse truth (79 x 120 px, a fraction of a second)
import -window root "$out/truth_before.png"
xdotool mousemove --window "$w" "$x" "$y" mousedown 1 mousemove --window "$w" $((x + 30)) "$y" \
        mousemove --window "$w" $((x + 60)) "$y" mouseup 1 mousemove --window "$w" 1200 700
sleep 1.5
import -window root "$out/truth_moved.png"
sleep 5
import -window root "$out/truth_after.png"
stop_editor
