#!/bin/sh
# Regenerates the committed sample recordings with tryon-synth (docs/recordings.md). Run after a
# change of the body model, the camera or the noise model:  recordings/samples/regenerate.sh BUILD
set -eu
build=$(cd "${1:?usage: regenerate.sh BUILD_DIR}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
synth="$build/recordings/tryon-synth"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$synth" --motion still --shape 0 --frames 3 --noise on --seed 1 --out still_s0
"$synth" --motion fast_swing --shape 1 --frames 8 --noise on --seed 1 --out fast_swing_s1
"$synth" --motion occlusion --shape 2 --frames 4 --noise on --seed 1 --out occlusion_s2
"$synth" --motion arm_raise --shape 0 --frames 4 --noise off --seed 1 --out arm_raise_s0_exact
for d in still_s0 fast_swing_s1 occlusion_s2 arm_raise_s0_exact; do
    # Reproducible archives: sorted names, fixed times and owners, no gzip timestamp.
    tar --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner -cf - "$d" |
        gzip -9n >"$here/$d.tar.gz"
done
