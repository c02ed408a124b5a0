# Sourced by the xdotool scripts: starts the editor and waits until it has drawn its first image, and
# stops it so that it writes its --session-out.
#   start_editor OUT_DIR [VAR=VALUE...] SPLATLAB editor ARGS...   sets $pid and $w (the window)
#   stop_editor
start_editor() {
  local out=$1
  shift
  rm -f "$out/ready"
  env SPLATLAB_READY_FILE="$out/ready" "$@" > "$out/editor.log" 2>&1 &
  pid=$!
  trap 'kill -TERM $pid 2>/dev/null || true' EXIT
  w=$(timeout 60 xdotool search --sync --onlyvisible --name SplatLab | head -1)
  for _ in $(seq 600); do [ -e "$out/ready" ] && break; sleep 0.2; done
  [ -e "$out/ready" ] || { echo "the editor was not ready after 120 s"; exit 1; }
}

stop_editor() {
  kill -TERM "$pid"
  wait "$pid"
  trap - EXIT
}
