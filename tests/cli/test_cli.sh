#!/usr/bin/env bash
# Every tool answers --help with its usage on stdout (exit 0) and refuses an unknown option
# (exit 2, a message naming it), creating no file either way.
#   test_cli.sh TOOL...
set -u
fail=0
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir" || exit 1
for exe in "$@"; do
    name=$(basename "$exe")
    timeout 20 "$exe" --help >out.txt 2>err.txt
    rc=$?
    if [ $rc -ne 0 ] || ! grep -qi "usage" out.txt; then
        echo "FAIL: $name --help: exit $rc, stdout: $(head -c 200 out.txt)"
        fail=1
    fi
    timeout 20 "$exe" --bogus >out.txt 2>err.txt
    rc=$?
    if [ $rc -ne 2 ] || ! grep -q -- "--bogus" err.txt; then
        echo "FAIL: $name --bogus: exit $rc, stderr: $(head -c 200 err.txt)"
        fail=1
    fi
    rm -f out.txt err.txt
    if [ -n "$(ls -A)" ]; then
        echo "FAIL: $name created: $(ls -A)"
        rm -rf ./* ./.[!.]* 2>/dev/null
        fail=1
    fi
done
[ $fail -eq 0 ] && echo "all $# tools answer --help and refuse --bogus"
exit $fail
