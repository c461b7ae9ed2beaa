#!/usr/bin/env bash
# tryon-bench-sim keeps its reference caches out of the current directory: in $HOME/.cache/tryon
# by default, in $XDG_CACHE_HOME/tryon or $TRYON_CACHE_DIR when set, in --cache-dir when given.
#   test_bench_cache_dir.sh TRYON_BENCH_SIM_EXE
set -u
bench=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mkdir "$dir/cwd" "$dir/home"
cd "$dir/cwd" || exit 1
run() { env -u TRYON_CACHE_DIR -u XDG_CACHE_HOME HOME="$dir/home" "$@" "$bench" --verts 64 \
    --frames 4 --iterations 2 --ref-iterations 4 --backend c >/dev/null 2>"$dir/err"; }
fail=0
expect() { # WHAT DIR: one cache file in DIR, none here
    if [ -n "$(ls -A)" ] || ! ls "$2"/sim-ref-*.bin >/dev/null 2>&1; then
        echo "FAIL: $1: current dir holds '$(ls -A)', $2 holds '$(ls "$2" 2>&1)'"
        cat "$dir/err"
        fail=1
    fi
    rm -rf ./*
}
run || fail=1
expect default "$dir/home/.cache/tryon"
run XDG_CACHE_HOME="$dir/xdg" || fail=1
expect XDG_CACHE_HOME "$dir/xdg/tryon"
run TRYON_CACHE_DIR="$dir/own/deep" || fail=1
expect TRYON_CACHE_DIR "$dir/own/deep"
[ $fail -eq 0 ] && echo "caches kept out of the current directory"
exit $fail
