# Sourced by the pipeline's figure scripts (pipeline_figures.sh, restart_figures.sh) after `cd` to
# the repository root with $build set: bin NAME finds an executable of the build; walk_recording
# makes (once) and names the 150-frame walk recording they run `tryon run` on; the environment a
# session on two cores wants (docs/pipeline.md, "Threads").
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
walk_recording() {
    local rec="$build/recordings/figures_walk_150_6000"
    if [ ! -f "$rec/INDEX.txt" ]; then
        "$(bin tryon-synth)" --out "$rec" --motion walk --frames 150 --vertices 6000 >/dev/null
    fi
    echo "$rec"
}
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
