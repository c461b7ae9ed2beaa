#!/bin/sh
# The body-fit figures in docs/bodyfit.md: makes tryon-synth recordings (noise on, seed 1),
# runs tryon-bench-fit over them, keeps each final JSON line in $OUT/*.jsonl and the tables in
# $OUT/*.txt, and draws docs/figures/bodyfit_*.png with gnuplot.
# usage: docs/figures/bodyfit_figures.sh BUILD_DIR [SECTION...]   (sections: headline sweep
#        fails tradeoffs smooth cloth pipeline shape alternate jitter; all by default; a section left
#        out keeps its data from an earlier run; alternate builds FIT_BASE_COMMIT, default
#        9271c41, the build before the still jitter round (400 points), in BUILD_DIR/fit-base)
# Recordings go to $TRYON_FIT_RECORDINGS (default BUILD_DIR/fit-recordings): about 600 KiB a
# frame, 0.6 GB for the whole set.
set -eu
B=${1:-build}
[ $# -gt 0 ] && shift
SECTIONS=${*:-headline sweep fails tradeoffs smooth cloth pipeline shape alternate jitter}
want() { case " $SECTIONS " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }
BENCH=$B/bodyfit/tryon-bench-fit
SYNTH=$B/recordings/tryon-synth
REC=${TRYON_FIT_RECORDINGS:-$B/fit-recordings}
OUT=$B/fit-figures
FIG=$(dirname "$0")
FRAMES=45
mkdir -p "$OUT" "$REC"
rec() { # MOTION SHAPE [FRAMES]: the recording's directory, made once
  d="$REC/${1}_s$2_${3:-$FRAMES}"
  [ -f "$d/INDEX.txt" ] || "$SYNTH" --out "$d" --motion "$1" --shape "$2" --noise on --seed 1 \
      --frames "${3:-$FRAMES}" --vertices 6000 >/dev/null
  echo "$d"
}

# 1. the headline: every motion, all three shapes, 45 frames (1.5 s) each, the defaults
if want headline; then
  set --
  for m in still arm_raise turn walk fast_swing occlusion; do
    for s in 0 1 2; do set -- "$@" "$(rec $m $s)"; done
  done
  "$BENCH" "$@" > "$OUT/headline.txt"
  tail -n 1 "$OUT/headline.txt" > "$OUT/headline.jsonl"
  # standing still alone: the jitter figure
  "$BENCH" "$REC/still_s0_$FRAMES" "$REC/still_s1_$FRAMES" "$REC/still_s2_$FRAMES" \
      > "$OUT/still.txt"
  # run to run: the same run twice must print the same errors
  "$BENCH" "$REC/walk_s0_$FRAMES" | tail -n 1 > "$OUT/determinism.jsonl"
  "$BENCH" "$REC/walk_s0_$FRAMES" | tail -n 1 >> "$OUT/determinism.jsonl"
fi

# 1b. where the shape error comes from: standing still, slim_tall and broad_short, fitted with
#     the estimated shape, with the true shape held (--true-shape), and with the true shape but
#     one parameter the average's (--true-shape-except K, K in fit_shape order): what each
#     parameter's error costs; one line per setting, "setting s1 surface joints s2 surface joints"
if want shape; then
  : > "$OUT/shape.txt"
  for k in estimated true 0 1 2 3 4 5 6 7 8; do
    case $k in
      estimated) args="" ;;
      true) args="--true-shape" ;;
      *) args="--true-shape-except $k" ;;
    esac
    # shellcheck disable=SC2086 # args are words
    "$BENCH" $args "$(rec still 1)" "$(rec still 2)" 2>/dev/null |
      awk -v k="$k" '/^still_/ { r = r " " $1 " " $7 " " $8 } END { print k r }' \
      >> "$OUT/shape.txt"
  done
fi

# 1c. speed against an earlier build on the same recordings, alternated three times (a busy
#     machine's load changes within minutes; the errors are deterministic, the times are not)
base_bench() { # the bench of FIT_BASE_COMMIT, built once in $B/fit-base
  base=$B/fit-base
  if [ ! -x "$base/build/bodyfit/tryon-bench-fit" ]; then
    rm -rf "$base" && mkdir -p "$base"
    git -C "$FIG/../.." archive "${FIT_BASE_COMMIT:-9271c41}" | tar -x -C "$base"
    cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$base/build" -j2 --target tryon-bench-fit >/dev/null
  fi
  echo "$base/build/bodyfit/tryon-bench-fit"
}
if want alternate; then
  base_bench=$(base_bench)
  set --
  for m in still arm_raise turn walk fast_swing occlusion; do
    for s in 0 1 2; do set -- "$@" "$(rec $m $s)"; done
  done
  : > "$OUT/alternate.txt"
  for i in 1 2 3; do
    for b in "$base_bench" "$BENCH"; do
      echo "$b load $(cut -d' ' -f1 /proc/loadavg) $("$b" "$@" | tail -n 1)" >> "$OUT/alternate.txt"
    done
  done
fi

# 1d. the still jitter and the filter's lag (docs/bodyfit-history.md, 2026-11-25): still on
#     three shapes, the walk, the fast swing on three shapes; the build before (400 points, the
#     shape's half steps, the speed estimate at 0.7 Hz), then today's with one setting changed;
#     per recording "name:joints_mm/jitter_mm/bad_as_tracking"
if want jitter; then
  JIT_RECS="$(rec still 0) $(rec still 1) $(rec still 2) $(rec walk 0) $(rec fast_swing 0)
            $(rec fast_swing 1) $(rec fast_swing 2)"
  : > "$OUT/jitter.txt"
  row() { # LABEL BENCH ARGS...: one line
    label=$1 bench=$2 && shift 2
    # shellcheck disable=SC2086 # the recordings are words
    "$bench" "$@" $JIT_RECS 2>/dev/null | awk -v a="$label" \
      '/_45 / { n = $1; sub(/_45$/, "", n); r = r sprintf(" %s:%s/%s/%s", n, $8, $9, $14) }
       END { print a ":" r }' >> "$OUT/jitter.txt"
  }
  row "before (9271c41)" "$(base_bench)"
  row "400 points" "$BENCH" --points 400
  row "speed 0.7 Hz" "$BENCH" --smooth-speed-hz 0.7
  row "speed 1.0 Hz" "$BENCH" --smooth-speed-hz 1.0
  row "defaults (800 points, speed 1.5 Hz)" "$BENCH"
  row "speed 1.0 Hz, beta_rot 6" "$BENCH" --smooth-speed-hz 1.0 --smooth-beta-rot 6
  row "no filter" "$BENCH" --smooth 0
  row "true shape held" "$BENCH" --true-shape
fi

# 2. sweeps: points used, iterations, coarse mesh resolution (walk, fast swing, turn, one shape
#    each); x = CPU ms per frame, y = surface error
SWEEP_RECS="$(rec walk 0) $(rec fast_swing 1) $(rec turn 2)"
if want sweep; then
  : > "$OUT/points.jsonl"; : > "$OUT/iterations.jsonl"; : > "$OUT/fitverts.jsonl"
  for p in 100 200 400 800 1600; do
    "$BENCH" --points $p $SWEEP_RECS | tail -n 1 >> "$OUT/points.jsonl"
  done
  for i in 2 4 6 10 16; do
    "$BENCH" --iterations $i $SWEEP_RECS | tail -n 1 >> "$OUT/iterations.jsonl"
  done
  for v in 1000 1500 3000 6000; do
    "$BENCH" --fit-vertices $v $SWEEP_RECS | tail -n 1 >> "$OUT/fitverts.jsonl"
  done
fi

# 3. where it fails: arms crossed before the chest (6 s), the side-on turn, the fast swing,
#    half out of the frame (part_out, 6 s), walking in and out (enter_leave, 8 s), 1.5 -> 3.5 m
#    and back (distance, 8 s), the box in front (one recording each, the whole motion)
if want fails; then
  "$BENCH" "$(rec arms_cross 0 180)" "$(rec turn 2 180)" "$(rec fast_swing 1 48)" \
      "$(rec part_out 0 180)" "$(rec enter_leave 0 240)" "$(rec distance 0 240)" \
      "$(rec occlusion 0 120)" > "$OUT/fails.txt"
  # the distance walk per band of distance (the motion's own distance: 1.5 + 2 smoothstep(u) m)
  "$BENCH" --scores "$OUT/distance_scores.txt" "$(rec distance 0 240)" > "$OUT/distance.txt"
  awk '{ t = $2 / 30.0; u = t < 4 ? t / 4 : (8 - t) / 4; d = 1.5 + 2 * u * u * (3 - 2 * u);
         b = d < 2.0 ? 0 : (d < 2.5 ? 1 : (d < 3.0 ? 2 : 3));
         n[b]++; s[b] += $5; j[b] += $6; bad[b] += ($5 > 15 || $6 > 40); dbt[b] += ($3 != 1) }
       END { split("1.5-2.0 2.0-2.5 2.5-3.0 3.0-3.5", nm, " ");
             for (b = 0; b < 4; b++)
               printf "%s m: %d frames, surface %.1f mm, joints %.1f mm, bad %d, not tracking %d\n",
                      nm[b + 1], n[b], s[b] / n[b], j[b] / n[b], bad[b], dbt[b] }' \
      "$OUT/distance_scores.txt" > "$OUT/distance_bands.txt"
fi

# 4. the temporal prior's weight and the constant-velocity start, on still, fast swing, walk
if want tradeoffs; then
  TRADE_RECS="$(rec still 0) $(rec fast_swing 1) $(rec walk 0)"
  : > "$OUT/tradeoffs.txt"
  for w in 0.0002 0.01 0.05; do
    echo "== --temporal $w" >> "$OUT/tradeoffs.txt"
    "$BENCH" --temporal $w $TRADE_RECS >> "$OUT/tradeoffs.txt"
  done
  for g in 0 0.5 1; do
    echo "== --predict $g" >> "$OUT/tradeoffs.txt"
    "$BENCH" --predict $g $TRADE_RECS >> "$OUT/tradeoffs.txt"
  done
fi

# Charts: error against CPU time, one line per swept setting, points labelled.
col() { # FILE KEY: the key's values, one a line
  sed -n "s/.*\"$2\":\([-0-9.]*\).*/\1/p" "$1"
}
table() { # FILE KEY: "cpu_ms surface_mm value" lines
  col "$1" cpu_ms_median > "$OUT/.a"
  col "$1" surface_mm > "$OUT/.b"
  col "$1" "$2" > "$OUT/.c"
  paste -d' ' "$OUT/.a" "$OUT/.b" "$OUT/.c"
}
if command -v gnuplot >/dev/null && [ -s "$OUT/points.jsonl" ]; then
  table "$OUT/points.jsonl" points > "$OUT/points.dat"
  table "$OUT/iterations.jsonl" iterations > "$OUT/iterations.dat"
  table "$OUT/fitverts.jsonl" fit_verts > "$OUT/fitverts.dat"
  for f in points iterations fitverts; do
    gnuplot <<GP
set terminal png size 800,500 noenhanced
set output "$FIG/bodyfit_$f.png"
set title "tryon-bench-fit: $f (walk, fast_swing, turn; 45 frames each)"
set xlabel "CPU ms per frame (median, thread CPU time)"
set ylabel "mean surface error (mm)"
set grid
set key bottom right
plot "$OUT/$f.dat" using 1:2 with linespoints title "$f", \
     "" using 1:2:3 with labels offset 1,1 notitle
GP
  done
fi
echo "tables and JSON lines in $OUT; charts in $FIG/bodyfit_*.png"

# 5. the published pose's One Euro filter: off, then the defaults, then a few settings, on
#    still, walk, fast swing, arm raise and turn (one shape each)
if want smooth; then
  SMOOTH_RECS="$(rec still 0) $(rec walk 0) $(rec fast_swing 1) $(rec arm_raise 0) $(rec turn 2)"
  : > "$OUT/smooth.txt"
  for args in "--smooth 0" "" "--smooth-beta-rot 8" "--smooth-beta-rot 16" "--smooth 1"; do
    echo "== ${args:-defaults}" >> "$OUT/smooth.txt"
    # shellcheck disable=SC2086 # args are words
    "$BENCH" $args $SMOOTH_RECS >> "$OUT/smooth.txt"
  done
fi

# 5b. the shirt on the fitted body against the shirt on the true body (cloth_vs_truth_mm, a
#     600-vertex shirt, the sim's defaults): standing still on all three shapes, walk, arm raise
if want cloth; then
  "$BENCH" --cloth-vertices 600 "$(rec still 0)" "$(rec still 1)" "$(rec still 2)" \
      "$(rec walk 0)" "$(rec arm_raise 0)" > "$OUT/cloth.txt"
fi

# 6. the demo (walk, 90 frames) three ways: fitted without the filter, fitted, the true body;
#    tryon-sim's per-body statistics in $OUT/sim-NAME.csv, the demo's output in $OUT/demo-NAME.txt,
#    and per run the medians of the sim's work, settle rounds and feature points moved
if want pipeline; then
  med() { # CSV COLUMN: the median of a column of tryon-sim --stats
    tail -n +2 "$1" | cut -d, -f"$2" | sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'
  }
  : > "$OUT/pipeline.txt"
  abs_out=$(cd "$OUT" && pwd)
  for run in fit-off:fit:off fit:fit: truth:truth:; do
    name=${run%%:*}; rest=${run#*:}; body=${rest%%:*}; smooth=${rest#*:}
    TRYON_DEMO_BODY=$body TRYON_DEMO_SMOOTH=$smooth TRYON_DEMO_SIM_STATS="$abs_out/sim-$name.csv" \
        "$FIG/../../scripts/demo.sh" "$B" > "$OUT/demo-$name.txt" 2>&1 || true
    echo "$name: sim ms_total p50 $(med "$OUT/sim-$name.csv" 11), settle rounds p50" \
        "$(med "$OUT/sim-$name.csv" 3), feature points moved p50 $(med "$OUT/sim-$name.csv" 7);" \
        "$(grep -E '^sim ' "$OUT/demo-$name.txt")" >> "$OUT/pipeline.txt"
  done
fi
