#!/bin/sh
# A person's first frames in tryon-bodyfit (docs/bodyfit.md, "A person's first frames"): this
# build against an earlier one (FITSTART_BASE_COMMIT, default 37e0003: the first frame fitted
# in 88 iterations, with tryon-bench-fit's --first lines), built once in BUILD_DIR/fitstart-base. Output in BUILD_DIR/fitstart/:
#   first.txt      tryon-bench-fit --first 15 on walk and still, three shapes, both builds
#                  alternated FITSTART_RUNS times (3): a line a frame, 'first recording frame
#                  state wall_ms segment_cpu fit_cpu skin_cpu iterations shape_steps
#                  shape_moved_mm', each block headed by the build and the load average
#   headline_*.txt the 18 headline recordings (docs/figures/bodyfit_figures.sh's) with the base,
#                  this build's defaults, --start-turns 2 and 4, --init-iterations 8, 16 and 40
#                  (errors: deterministic)
#   instructions.txt  valgrind --tool=callgrind's count in fit_tracker_frame, the walk's frame 0
#                  alone and frames 0-1, both builds (what no load changes; FITSTART_CALLGRIND=0
#                  skips it, about 2 minutes a build)
#   pipeline.txt   tryon run on the 150-frame walk (docs/figures/latency_figures.sh's), headless,
#                  the C sim, --record, then tryon path --each: its first 16 frames and the
#                  summary, both builds alternated FITSTART_RUNS times
#   shape.txt      this build, --first 45 on still and walk: the shape's largest parameter
#                  change a frame (what a garment made on the first body misses)
# usage: docs/figures/fitstart_figures.sh BUILD_DIR
set -eu
B=${1:-build}
RUNS=${FITSTART_RUNS:-3}
BASE=${FITSTART_BASE_COMMIT:-37e0003}
TOP=$(cd "$(dirname "$0")/../.." && pwd)
B=$(cd "$B" && pwd)
OUT=$B/fitstart
REC=${TRYON_FIT_RECORDINGS:-$B/fit-recordings}
mkdir -p "$OUT" "$REC"
export LP_NUM_THREADS="${LP_NUM_THREADS:-1}" OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
load() { cut -d' ' -f1 /proc/loadavg; }

rec() { # MOTION SHAPE: bodyfit_figures.sh's recording, made once
  d="$REC/${1}_s$2_45"
  [ -f "$d/INDEX.txt" ] || "$B/recordings/tryon-synth" --out "$d" --motion "$1" --shape "$2" \
    --noise on --seed 1 --frames 45 --vertices 6000 >/dev/null
  echo "$d"
}
walk=$B/recordings/figures_walk_150_6000
[ -f "$walk/INDEX.txt" ] ||
  "$B/recordings/tryon-synth" --out "$walk" --motion walk --frames 150 --vertices 6000 >/dev/null

base=$B/fitstart-base
if [ ! -x "$base/build/bodyfit/tryon-bodyfit" ]; then
  rm -rf "$base" && mkdir -p "$base"
  git -C "$TOP" archive "$BASE" | tar -x -C "$base"
  cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$base/build" -j2 --target tryon-bodyfit tryon-bench-fit >/dev/null
fi
bindir() { if [ "$1" = base ]; then echo "$base/build/bodyfit"; else echo "$B/bodyfit"; fi; }

set --
for s in 0 1 2; do set -- "$@" "$(rec walk $s)" "$(rec still $s)"; done
: > "$OUT/first.txt"
i=0
while [ "$i" -lt "$RUNS" ]; do
  i=$((i + 1))
  for which in base this; do
    echo "== $which run $i load $(load)" >> "$OUT/first.txt"
    "$(bindir $which)/tryon-bench-fit" --first 15 "$@" | grep '^first' >> "$OUT/first.txt"
  done
done

set --
for m in still arm_raise turn walk fast_swing occlusion; do
  for s in 0 1 2; do set -- "$@" "$(rec $m $s)"; done
done
"$base/build/bodyfit/tryon-bench-fit" "$@" > "$OUT/headline_base.txt"
"$B/bodyfit/tryon-bench-fit" "$@" > "$OUT/headline_this.txt"
"$B/bodyfit/tryon-bench-fit" --start-turns 2 "$@" > "$OUT/headline_spread2.txt"
"$B/bodyfit/tryon-bench-fit" --start-turns 4 "$@" > "$OUT/headline_spread4.txt"
for n in 8 16 40; do
  "$B/bodyfit/tryon-bench-fit" --init-iterations $n "$@" > "$OUT/headline_init$n.txt"
done

if [ "${FITSTART_CALLGRIND:-1}" = 1 ] && command -v valgrind >/dev/null; then
  : > "$OUT/instructions.txt"
  for which in base this; do
    for n in 1 2; do
      valgrind --tool=callgrind --toggle-collect=fit_tracker_frame \
        --callgrind-out-file="$OUT/callgrind.$which.$n" "$(bindir $which)/tryon-bench-fit" \
        --frames $n "$(rec walk 0)" >/dev/null 2>&1
      echo "$which frames $n: $(callgrind_annotate "$OUT/callgrind.$which.$n" 2>/dev/null |
        awk '/PROGRAM TOTALS/ { print $1 }') instructions in fit_tracker_frame" \
        >> "$OUT/instructions.txt"
    done
  done
fi

: > "$OUT/pipeline.txt"
i=0
while [ "$i" -lt "$RUNS" ]; do
  i=$((i + 1))
  for which in base this; do
    d=$(mktemp -d)
    TRYON_BIN_DIR=$(bindir $which) "$B/launcher/tryon" run "$walk" --body bodyfit --backend c \
      --headless --out "$d/png" --png-every 100000 --record "$d/rec" > "$d/run.txt" 2>&1 || true
    {
      echo "== $which run $i load $(load)"
      grep -E '^(stage|capture|bodyfit|sim|mirror) ' "$d/run.txt" | head -n 5
      "$B/launcher/tryon" path "$d/rec/session.lcmlog" --each 2>&1 |
        sed -n '/^== each frame/,$p' | head -n 17
    } >> "$OUT/pipeline.txt"
    rm -rf "$d"
  done
done

"$B/bodyfit/tryon-bench-fit" --first 45 "$(rec still 0)" "$(rec still 1)" "$(rec still 2)" \
  "$(rec walk 0)" | grep '^first' > "$OUT/shape.txt"
echo "fitstart figures in $OUT"
