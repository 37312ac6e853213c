#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Stops the X server of start_xvfb.sh (fixture cleanup). Usage: stop_xvfb.sh STATE_FILE
state="$1"
[ -f "$state" ] || exit 0
. "$state"
kill "$CTSPLINES_XVFB_PID" 2>/dev/null || true
rm -f "$state" "$state.display" "$state.log"
