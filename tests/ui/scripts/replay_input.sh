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
exe=$1 out=$2 mode=$3
cd "$out"
rm -f "$out/ready"
SPLATLAB_READY_FILE="$out/ready" SPLATLAB_RENDER_DELAY_MS=2000 "$exe" editor --size 1280x800 \
  --session-out "$out/session.json" > editor.log 2>&1 &
pid=$!
trap 'kill -TERM $pid 2>/dev/null || true' EXIT
w=$(timeout 60 xdotool search --sync --onlyvisible --name SplatLab | head -1)
# The bundled bonsai open, its gradients computed (no progress modal holds the input) and a first image
# on screen; from here every frame takes 2 s.
for _ in $(seq 600); do [ -e "$out/ready" ] && break; sleep 0.2; done
[ -e "$out/ready" ] || { echo "the editor was not ready after 120 s"; exit 1; }
# The TF curve's point at (129, 164) in this layout (1280x800, bonsai preset): up 20 px.
if [ "$mode" = slow ]; then
  xdotool mousemove --window "$w" 129 164; sleep 0.3
  xdotool mousedown 1; sleep 0.3
  xdotool mousemove --window "$w" 129 154; sleep 0.3
  xdotool mousemove --window "$w" 129 144; sleep 0.3
  xdotool mouseup 1; sleep 0.3
  xdotool mousemove --window "$w" 1200 700; sleep 0.5
else
  xdotool mousemove --window "$w" 129 164 mousedown 1 mousemove --window "$w" 129 154 \
          mousemove --window "$w" 129 144 mouseup 1 mousemove --window "$w" 1200 700
  sleep 0.5
  # A second gesture on the same point, then one Ctrl+Z (the TF panel has focus): back to the first's end.
  xdotool mousemove --window "$w" 129 144 mousedown 1 mousemove --window "$w" 129 124 mouseup 1 \
          mousemove --window "$w" 129 400 key ctrl+z
  sleep 0.5
  # The viewport: 100 px right and 20 px down, the pointer moving on after the release.
  xdotool mousemove --window "$w" 800 300 mousedown 1 mousemove --window "$w" 850 310 \
          mousemove --window "$w" 900 320 mouseup 1 mousemove --window "$w" 1200 700
  sleep 0.5
  # The TF panel's file field: click, select all, type a name; then Save.
  xdotool mousemove --window "$w" 120 439 click 1 key ctrl+a type --delay 5 typed_tf.json
  xdotool mousemove --window "$w" 75 466 click 1
fi
# The fifth point at (189, 121): a click selects it, and its fields appear with the Extinction slider at
# y 351 (x 9..244).
xdotool mousemove --window "$w" 189 121 click 1 mousemove --window "$w" 1200 700
sleep 0.5
if [ "$mode" = slow ]; then
  xdotool mousemove --window "$w" 150 351; sleep 0.3
  xdotool mousedown 1; sleep 0.3
  xdotool mousemove --window "$w" 60 351; sleep 0.3
  xdotool mousemove --window "$w" 2 351; sleep 0.3
  xdotool mouseup 1; sleep 0.3
  xdotool mousemove --window "$w" 1200 700
else
  xdotool mousemove --window "$w" 150 351 mousedown 1 mousemove --window "$w" 60 351 \
          mousemove --window "$w" 2 351 mouseup 1 mousemove --window "$w" 1200 700
fi
sleep 2
kill -TERM "$pid"
wait "$pid"
