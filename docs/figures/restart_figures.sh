#!/usr/bin/env bash
# A stage SIGKILLed mid-session (issue 17: the launcher restarts it, frames flow again within 1 s,
# nothing else restarts): `tryon run` on the 150-frame walk, all four stages real, headless,
# recorded; 2 s after the capture starts the stage named is killed; then, from the recorded
# session (`tryon path --each`), the longest run of frames that stage did not publish, and that
# run in ms at 30 fps, and which stages the launcher restarted.
#   docs/figures/restart_figures.sh BUILD_DIR [STAGE...]   (default: tryon-bodyfit tryon-sim
#                                                           tryon-mirror)
# RESTART_FIG_TRYON: the `tryon` that reads the recorded sessions (default the build's; a build
# from before `tryon path --each` is measured with a newer one's).
set -euo pipefail
build=$(realpath "${1:?usage: restart_figures.sh BUILD_DIR [STAGE...]}")
shift
stages=("$@")
[ ${#stages[@]} -gt 0 ] || stages=(tryon-bodyfit tryon-sim tryon-mirror)
cd "$(dirname "$0")/../.."
. docs/figures/walk_session.sh
rec=$(walk_recording)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for stage in "${stages[@]}"; do
    rm -rf "$out/run" && mkdir -p "$out/run/rec"
    "$(bin tryon)" run "$rec" --body bodyfit --backend c --headless --out "$out/run/frames" \
        --png-every 100000 --record "$out/run/rec" >"$out/run/out.txt" 2>"$out/run/err.txt" &
    launcher=$!
    for _ in $(seq 200); do
        grep -q "started tryon-capture" "$out/run/err.txt" 2>/dev/null && break
        sleep 0.05
    done
    sleep 2
    pid=$(sed -n "s/^tryon: started $stage (pid \([0-9]*\)).*/\1/p" "$out/run/err.txt" | tail -n 1)
    [ -n "$pid" ] && kill -KILL "$pid"
    wait "$launcher" || true
    # the column of the stage in `tryon path --each`: bodyfit, sim, mirror work (4, 6, 8)
    case $stage in tryon-bodyfit) col=4 ;; tryon-sim) col=6 ;; *) col=8 ;; esac
    "${RESTART_FIG_TRYON:-$(bin tryon)}" path "$out/run/rec/session.lcmlog" --each | awk -v c="$col" -v s="$stage" '
        /^ *[0-9]+ / { if ($c == "-") { run++; if (run > worst) worst = run } else run = 0 }
        END { printf "%s killed: longest run of frames it did not publish %d (%.0f ms at 30 fps)\n",
                     s, worst, worst * 1000 / 30 }'
    grep -o "tryon-[a-z]* (pid [0-9]*) was killed by signal 9; restarting it" "$out/run/err.txt" |
        sed 's/^/    /' || echo "    (no restart said)"
done
