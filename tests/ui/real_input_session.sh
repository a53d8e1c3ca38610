#!/usr/bin/env bash
# The workbench driven with real input (xdotool's XTEST mouse and keyboard, as a user's
# hands), under the X server this runs in (tests/ui/with_xvfb.sh). Four sessions, each a fresh start
# from a config folder of its own, each leaving `fird gui --stats` in OUT_DIR:
#   real_small.json     the window resized to 1000 x 650
#   real_restored.json  resized to 1000 x 650 and back to 1600 x 1000
#   real_dragged.json   then a left drag of 120 x 40 px across the viewport's centre
#   real_search.json    a search started with the O key and run to its end
# tests/ui/window_layout_test.cpp reads them (Gui.RealInput*).
#
# Usage: real_input_session.sh FIRD SCENE OUT_DIR
# ImGui 1.86 reads key and button state once per frame, so each press is held for a few
# frames (a press and release within one frame would be missed); every wait is bounded.
set -euo pipefail
trap 'echo "real_input_session.sh: failed at line $LINENO: $BASH_COMMAND" >&2' ERR
fird="$1" scene="$2" out="$3"
mkdir -p "$out"
cd "$out"

hold_s=1 # a key or button held this long spans several frames even on a loaded machine
settle_s=3 # the window and the layout follow a resize within this (lavapipe, 2 cores)

# Starts the workbench on the scene with a fresh config (and data) folder; sets $pid, $win.
start() {
    local name="$1"
    rm -rf "config_$name" "data_$name"
    XDG_CONFIG_HOME="$PWD/config_$name" XDG_DATA_HOME="$PWD/data_$name" \
        "$fird" --validation gui "$scene" --stats >"real_$name.json" 2>"real_$name.log" &
    pid=$!
    # The window appears within the bounded wait, or the session fails.
    win=""
    for _ in $(seq 1 600); do
        win="$(xdotool search --name '^FIRD workbench$' 2>/dev/null | head -1 || true)"
        [ -n "$win" ] && break
        kill -0 "$pid" 2>/dev/null || { echo "fird gui exited before its window appeared" >&2; cat "real_$name.log" >&2; exit 1; }
        sleep 0.1
    done
    [ -n "$win" ] || { echo "no workbench window within 60 s" >&2; exit 1; }
    sleep "$settle_s"
    xdotool windowsize --sync "$win" 1600 1000
    sleep "$settle_s"
}

press() { # KEY...: held together, released in reverse order
    xdotool windowfocus --sync "$win"
    local k
    for k in "$@"; do xdotool keydown "$k"; done
    sleep "$hold_s"
    for ((i = $#; i >= 1; i--)); do xdotool keyup "${!i}"; done
}

quit() { # Ctrl+Q, then the process must end (bounded) and succeed
    press ctrl q
    for _ in $(seq 1 300); do
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
    if kill -0 "$pid" 2>/dev/null; then
        echo "fird gui did not quit within 30 s of Ctrl+Q" >&2
        kill "$pid"
        exit 1
    fi
    wait "$pid"
}

start small
xdotool windowsize --sync "$win" 1000 650
sleep "$settle_s"
quit

start restored
xdotool windowsize --sync "$win" 1000 650
sleep "$settle_s"
xdotool windowsize --sync "$win" 1600 1000
sleep "$settle_s"
quit

# The drag starts at the viewport panel's centre as the restored session reported it.
read -r vx vy vw vh < <(/usr/bin/python3 -c 'import json,sys; print(*json.load(open(sys.argv[1]))["panels"]["viewport"])' real_restored.json)
x0=$(/usr/bin/python3 -c "print(int($vx + $vw / 2))")
y0=$(/usr/bin/python3 -c "print(int($vy + $vh / 2))")
start dragged
xdotool mousemove --window "$win" "$x0" "$y0"
sleep "$hold_s"
xdotool mousedown 1
sleep "$hold_s"
for _ in $(seq 1 10); do # 120 px right, 40 px down in ten moves
    xdotool mousemove_relative -- 12 4
    sleep 0.05
done
sleep "$hold_s"
xdotool mouseup 1
sleep "$hold_s"
quit

start search
press o
# Waits, bounded, for FILE to appear: wait_for FILE SECONDS WHAT.
wait_for() {
    for _ in $(seq 1 $(($2 * 10))); do
        [ -f "$1" ] && return 0
        sleep 0.1
    done
    echo "the search wrote no $1 within $2 s$3" >&2
    exit 1
}
result="data_search/fird/runs/$(basename "$scene" .toml)-optimize-1/search.json"
wait_for "$result" 240 "" # the scene's search takes seconds
# search.json is the run folder's first file: the worker then writes the pictures (~0.6 s
# here alone, over 3 s beside another session under ctest -j2) and the reflectors,
# reflectors.pvd last, traces the best and hands it to the panel. Waiting a fixed time after
# search.json lost that race under load (the sliders still at the start).
wait_for "$(dirname "$result")/reflectors.pvd" 60 " of its search.json"
sleep "$settle_s" # the best's trace, and the panel takes it on the next frames
quit
