#!/usr/bin/env bash
# Drives the editor as a user would, with xdotool, while every frame takes 2 s (SPLATLAB_RENDER_DELAY_MS):
# the input replays of test_editor_input.cpp. Run under its own X server (xvfb-run), from the test.
#   replay_input.sh SPLATLAB OUT_DIR slow|burst
# slow:  one TF point dragged up 20 px, a step at a time with pauses.
# burst: the same drag with every event at once (press, moves, release, the pointer moving on), a second
#        drag of the point and Ctrl+Z; a viewport drag; Ctrl+A and a file name typed into the TF panel's
#        file field, then Save. Each burst falls within one UI frame, while a slow render is in flight.
# Both: the TF's fifth point selected and its Opacity slider dragged past its left end (to 0), the
# pointer moving on to the right after the release (slow: step by step; burst: at once).
# The editor closes on SIGTERM and writes OUT_DIR/session.json (--session-out).
set -euo pipefail
source "$(dirname "$0")/editor_session.sh"
exe=$1 out=$2 mode=$3
cd "$out"
# The bundled bonsai open, its gradients computed (no progress modal holds the input) and a first image
# on screen; from here every frame takes 2 s.
start_editor "$out" SPLATLAB_RENDER_DELAY_MS=2000 "$exe" editor --size 1280x800 --session-out "$out/session.json"
# The TF curve's point at (129, 183) in this layout (1280x800 under the 19 px menu bar, bonsai preset): up 20 px.
if [ "$mode" = slow ]; then
  xdotool mousemove --window "$w" 129 183; sleep 0.3
  xdotool mousedown 1; sleep 0.3
  xdotool mousemove --window "$w" 129 173; sleep 0.3
  xdotool mousemove --window "$w" 129 163; sleep 0.3
  xdotool mouseup 1; sleep 0.3
  xdotool mousemove --window "$w" 1200 719; sleep 0.5
else
  xdotool mousemove --window "$w" 129 183 mousedown 1 mousemove --window "$w" 129 173 \
          mousemove --window "$w" 129 163 mouseup 1 mousemove --window "$w" 1200 719
  sleep 0.5
  # A second gesture on the same point, then one Ctrl+Z (the TF panel has focus): back to the first's end.
  xdotool mousemove --window "$w" 129 163 mousedown 1 mousemove --window "$w" 129 143 mouseup 1 \
          mousemove --window "$w" 129 419 key ctrl+z
  sleep 0.5
  # The viewport: 100 px right and 20 px down, the pointer moving on after the release.
  xdotool mousemove --window "$w" 800 319 mousedown 1 mousemove --window "$w" 850 329 \
          mousemove --window "$w" 900 339 mouseup 1 mousemove --window "$w" 1200 719
  sleep 0.5
  # The TF panel's file field: click, select all, type a name; then Save.
  xdotool mousemove --window "$w" 120 458 click 1 key ctrl+a type --delay 5 typed_tf.json
  xdotool mousemove --window "$w" 75 485 click 1
fi
# The fifth point at (189, 140): a click selects it, and its fields appear with the Extinction slider at
# y 370 (x 9..244).
xdotool mousemove --window "$w" 189 140 click 1 mousemove --window "$w" 1200 719
sleep 0.5
if [ "$mode" = slow ]; then
  xdotool mousemove --window "$w" 150 370; sleep 0.3
  xdotool mousedown 1; sleep 0.3
  xdotool mousemove --window "$w" 60 370; sleep 0.3
  xdotool mousemove --window "$w" 2 370; sleep 0.3
  xdotool mouseup 1; sleep 0.3
  xdotool mousemove --window "$w" 1200 719
else
  xdotool mousemove --window "$w" 150 370 mousedown 1 mousemove --window "$w" 60 370 \
          mousemove --window "$w" 2 370 mouseup 1 mousemove --window "$w" 1200 719
fi
sleep 2
stop_editor
