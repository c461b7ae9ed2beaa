#!/usr/bin/env bash
# Runs every libFuzzer harness built in BUILD_DIR (default build-fuzz) for SECONDS_EACH seconds,
# starting from its committed seed corpus (tests/fuzz/corpus/<name>/, never written to: what a
# run finds goes to a scratch corpus). A crash, leak or sanitizer report fails the run and its
# input is kept in BUILD_DIR/fuzz-artifacts/.
#   tests/fuzz/run.sh SECONDS_EACH [BUILD_DIR]
# Build first: CC=clang-14 cmake -S . -B build-fuzz -DTRYON_FUZZ=ON && cmake --build build-fuzz --target fuzz_all
set -uo pipefail
seconds=${1:?usage: tests/fuzz/run.sh SECONDS_EACH [BUILD_DIR]}
build=${2:-build-fuzz}
here=$(cd "$(dirname "$0")" && pwd)
artifacts="$build/fuzz-artifacts"
mkdir -p "$artifacts"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail=0
n=0
for exe in "$build"/tests/fuzz/fuzz_*; do
    [ -x "$exe" ] && [ -f "$exe" ] || continue
    name=$(basename "$exe")
    seeds="$here/corpus/$name"
    if [ ! -d "$seeds" ]; then
        echo "== $name: no seed corpus at $seeds" >&2
        fail=1
        continue
    fi
    mkdir -p "$scratch/$name"
    n=$((n + 1))
    if "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
        -artifact_prefix="$artifacts/$name-" -print_final_stats=1 \
        "$scratch/$name" "$seeds" >"$scratch/$name.log" 2>&1; then
        runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$scratch/$name.log" | grep -o '[0-9]*$')
        echo "== $name: ${runs:-?} inputs in ${seconds} s, no failure"
    else
        echo "== $name: FAILED (input in $artifacts/)" >&2
        tail -n 40 "$scratch/$name.log" >&2
        fail=1
    fi
done
if [ $n -eq 0 ]; then
    echo "no harness in $build/tests/fuzz (build with -DTRYON_FUZZ=ON, target fuzz_all)" >&2
    exit 1
fi
exit $fail
