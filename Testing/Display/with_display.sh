#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a rendering test on the fixture's X server. Usage: with_display.sh STATE_FILE COMMAND...
set -eu
state="$1"
shift
if [ ! -f "$state" ]; then
  echo "with_display.sh: no X server (fixture Display.Start did not run or failed)" >&2
  exit 1
fi
. "$state"
DISPLAY="$CTSPLINES_XVFB_DISPLAY"
export DISPLAY
exec "$@"
