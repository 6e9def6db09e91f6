#!/usr/bin/env bash
# Usage: tests/with-xvfb.sh COMMAND [ARGS...]
#
# Runs COMMAND against a private Xvfb server (1280x800x24, xcb platform).
# Xvfb chooses a free display number itself (-displayfd), so tests running in
# parallel never share a server; `xvfb-run -a` can race and hand two tests the
# same display, and the first to finish then takes it away from the other.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 COMMAND [ARGS...]" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/linkscape-xvfb.XXXXXX")
# -noreset: by default the server resets when its last client disconnects, and
# a test that closes one render window and opens the next can hit the reset.
Xvfb -displayfd 3 -screen 0 1280x800x24 -nolisten tcp -noreset 3>"$work/display" 2>"$work/xvfb.log" &
xvfb_pid=$!
trap 'kill "$xvfb_pid" 2>/dev/null; wait "$xvfb_pid" 2>/dev/null; rm -rf "$work"' EXIT

for _ in $(seq 100); do
  [ -s "$work/display" ] && break
  kill -0 "$xvfb_pid" 2>/dev/null || { echo "with-xvfb: Xvfb did not start:" >&2; cat "$work/xvfb.log" >&2; exit 1; }
  sleep 0.05
done
[ -s "$work/display" ] || { echo "with-xvfb: Xvfb gave no display within 5 s" >&2; exit 1; }

export DISPLAY=":$(head -n1 "$work/display")"
export QT_QPA_PLATFORM=xcb
"$@"
