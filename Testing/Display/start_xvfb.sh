#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Starts the one X server that every rendering test of a ctest run shares (fixture Display).
# Xvfb picks a free display itself (-displayfd) and writes its number once it accepts
# connections; the state file then tells with_display.sh where it is and stop_xvfb.sh whom to
# stop. Usage: start_xvfb.sh STATE_FILE
set -eu
state="$1"
rm -f "$state" "$state.display"
# setsid: the server outlives this script (ctest waits for the fixture test to end).
# -noreset: by default the server resets whenever its last client disconnects, and a window
# opened during the reset fails ("bad X server connection"): the flake of one-window-at-a-time
# tests such as Examples.farin_cubic.
setsid Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$state.display" \
  >"$state.log" 2>&1 </dev/null &
pid=$!
i=0
while [ ! -s "$state.display" ]; do
  if ! kill -0 "$pid" 2>/dev/null || [ "$i" -ge 300 ]; then
    echo "start_xvfb.sh: Xvfb did not start (see $state.log)" >&2
    cat "$state.log" >&2 || true
    exit 1
  fi
  i=$((i + 1))
  sleep 0.1
done
display=$(tr -d '\n' <"$state.display")
printf 'CTSPLINES_XVFB_DISPLAY=:%s\nCTSPLINES_XVFB_PID=%s\n' "$display" "$pid" >"$state"
echo "Xvfb on :$display (pid $pid)"
