#!/bin/sh
# tryon-bodyfit's CPU a frame (docs/bodyfit.md, "CPU a frame in the pipeline"): this build and
# an earlier one (FIT_CPU_BASE_COMMIT, default 20edd69, before the CPU round), alternated
# FIT_CPU_RUNS times (2) because a busy machine's load changes within minutes:
#   1. building the models: CPU seconds of `tryon-bodyfit` started and stopped after 3 s with
#      no DEPTH (what a start, or a restart after a crash, costs before the first frame);
#   2. the fit alone: `tryon-bench-fit` on the 150-frame walk, this thread's CPU ms a frame
#      (cpu_ms_median; this build also every thread's and each sub-stage's);
#   3. the pipeline: `tryon run` on the same walk, headless, the C sim; the launcher's CPU line
#      for tryon-bodyfit over the bodies it published (what "CPU s / frames" measured) and,
#      this build only, tryon-bodyfit's own last line (starting / a body / a DEPTH);
#   4. what no load changes (FIT_CPU_CALLGRIND=0 skips it; about 2 minutes a build): the
#      instructions `valgrind --tool=callgrind` counts in tryon-bench-fit's first 31 frames of
#      the walk, inclusive, for building the tracker's models and for each frame's fit.
# usage: docs/figures/bodyfit_cpu_figures.sh BUILD_DIR   (output in BUILD_DIR/fit-cpu/)
set -eu
B=${1:-build}
RUNS=${FIT_CPU_RUNS:-2}
BASE=${FIT_CPU_BASE_COMMIT:-20edd69}
OUT=$B/fit-cpu
TOP=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"
B=$(cd "$B" && pwd)
export LP_NUM_THREADS="${LP_NUM_THREADS:-1}" OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"

rec=$B/recordings/figures_walk_150_6000 # the walk of docs/figures/latency_figures.sh
[ -f "$rec/INDEX.txt" ] ||
  "$B/recordings/tryon-synth" --out "$rec" --motion walk --frames 150 --vertices 6000 >/dev/null

base=$B/fit-cpu-base # the earlier build's tryon-bodyfit and tryon-bench-fit, built once
if [ ! -x "$base/build/bodyfit/tryon-bodyfit" ]; then
  rm -rf "$base" && mkdir -p "$base"
  git -C "$TOP" archive "$BASE" | tar -x -C "$base"
  cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$base/build" -j2 --target tryon-bodyfit tryon-bench-fit >/dev/null
fi

start_cpu() { # BODYFIT: CPU seconds (user + system) of a start with no frame (a channel prefix
  # of its own: nothing arrives)
  TRYON_CHANNEL_PREFIX=FITCPU$$_ /usr/bin/time -f "%U %S" timeout -s INT 3 "$1" 2>&1 >/dev/null |
    awk 'NF == 2 && $1 ~ /^[0-9.]+$/ { print $1 + $2 }'
}

pipeline() { # LABEL BIN_DIR: one `tryon run`, one line
  d=$(mktemp -d)
  TRYON_BIN_DIR=$2 "$B/launcher/tryon" run "$rec" --body bodyfit --backend c --headless \
    --out "$d/png" --png-every 100000 > "$d/run.txt" 2>&1 || true
  logs=$(awk '/^== logs:/ { print $3 }' "$d/run.txt")
  awk -v l="$1" -v load="$(cut -d' ' -f1 /proc/loadavg)" '
    $1 == "bodyfit" && NF > 5 { bodies = $2 }
    $1 == "tryon-bodyfit" && $3 == "s" { cpu = $2 }
    END { printf "%s load %s: %.2f s / %d bodies = %.2f ms a body\n", l, load, cpu, bodies,
          bodies ? 1000 * cpu / bodies : -1 }' "$d/run.txt"
  if [ -n "$logs" ]; then
    grep -h "tryon-bodyfit: CPU" "$logs"/* 2>/dev/null | sed 's/^/    /' || true
    rm -rf "$logs"
  fi
  rm -rf "$d"
}

: > "$OUT/start.txt"
: > "$OUT/bench.txt"
: > "$OUT/pipeline.txt"
i=0
while [ "$i" -lt "$RUNS" ]; do
  i=$((i + 1))
  for which in base this; do
    if [ $which = base ]; then bin=$base/build/bodyfit; else bin=$B/bodyfit; fi
    echo "$which load $(cut -d' ' -f1 /proc/loadavg): $(start_cpu "$bin/tryon-bodyfit") s" \
      >> "$OUT/start.txt"
    echo "$which load $(cut -d' ' -f1 /proc/loadavg) $("$bin/tryon-bench-fit" "$rec" | tail -n 1)" \
      >> "$OUT/bench.txt"
    pipeline $which "$bin" >> "$OUT/pipeline.txt"
  done
done
if [ "${FIT_CPU_CALLGRIND:-1}" = 1 ] && command -v valgrind >/dev/null; then
  : > "$OUT/instructions.txt"
  for which in base this; do
    if [ $which = base ]; then bin=$base/build/bodyfit; else bin=$B/bodyfit; fi
    valgrind --tool=callgrind --callgrind-out-file="$OUT/callgrind.$which" \
      "$bin/tryon-bench-fit" --frames 31 "$rec" >/dev/null 2>&1
    callgrind_annotate --inclusive=yes "$OUT/callgrind.$which" 2>/dev/null | awk -v w=$which '
      { gsub(",", "", $1) }
      / [?]+:fit_tracker_create / { c = $1 } / [?]+:fit_tracker_frame / { f = $1 }
      / [?]+:fit_segmenter_frame / { s = $1 } / [?]+:fit_solve / { v = $1 }
      / [?]+:cvs_nearest_set / { n = $1 }
      END { printf "%s: Minstr building the models %.0f; a frame (31, the first included): " \
            "fit %.1f, of which segmenter %.1f, nearest set %.1f, solver %.1f\n", w, c / 1e6,
            f / 31e6, s / 31e6, n / 31e6, v / 31e6 }' >> "$OUT/instructions.txt"
  done
fi
cat "$OUT"/start.txt "$OUT"/bench.txt "$OUT"/pipeline.txt "$OUT"/instructions.txt 2>/dev/null
