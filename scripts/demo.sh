#!/usr/bin/env bash
# The demo that `./setup.sh` ends with: the pipeline on a bundled recording, as far as the
# stages exist today. Each step says what it ran; stages not built yet are named, not faked.
set -euo pipefail
build=${1:-build}
cd "$(dirname "$0")/.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }

echo "== bus: a full-size depth frame over LCM"
"$(bin tryon-bus-check)"

missing=()
for exe in tryon-capture tryon-bodyfit tryon-sim tryon-mirror tryon-profile tryon; do
    [ -n "$(bin "$exe")" ] || missing+=("$exe")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "== not built yet (later issues): ${missing[*]}"
fi
