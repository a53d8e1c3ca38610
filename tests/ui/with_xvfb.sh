#!/usr/bin/env bash
# Runs a command under a virtual X server of its own: Xvfb picks a free display itself
# (-displayfd) and says which, so tests started at once never race for one (xvfb-run -a
# picks its number before starting the server, and two runs can pick the same). With
# -noreset: a server resets when its last client leaves, and a session that starts the
# next window then (tests/ui/real_input_session.sh runs several) could not connect.
# Usage: with_xvfb.sh WxHxDEPTH COMMAND [ARG...]; exits with COMMAND's status.
set -euo pipefail
screen="$1"
shift
dir="$(mktemp -d)"
Xvfb -displayfd 3 -screen 0 "$screen" -nolisten tcp -noreset 3>"$dir/display" 2>"$dir/xvfb.log" &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null; wait "$xvfb" 2>/dev/null; rm -rf "$dir"' EXIT
for _ in $(seq 1 300); do # the server says its display once it accepts connections (30 s bound)
    [ -s "$dir/display" ] && break
    kill -0 "$xvfb" 2>/dev/null || { echo "with_xvfb.sh: Xvfb did not start: $(tail -1 "$dir/xvfb.log")" >&2; exit 1; }
    sleep 0.1
done
[ -s "$dir/display" ] || { echo "with_xvfb.sh: Xvfb named no display within 30 s" >&2; exit 1; }
DISPLAY=":$(tr -d '[:space:]' <"$dir/display")" "$@"
