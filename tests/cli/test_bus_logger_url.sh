#!/usr/bin/env bash
# The demo's logger listens on the stages' URL: the default one (with its 8 MiB receive buffer)
# when TRYON_LCM_URL is unset, else TRYON_LCM_URL. A stand-in lcm-logger records its arguments.
#   test_bus_logger_url.sh REPO_ROOT TRYON_BUS_CHECK_EXE
set -u
root=$1
check=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
printf '#!/bin/sh\necho "$@" > "%s/args"\n' "$dir" >"$dir/lcm-logger"
chmod +x "$dir/lcm-logger"
fail=0
grep -q 'scripts/bus_logger.sh' "$root/scripts/demo.sh" || {
    echo "FAIL: scripts/demo.sh does not start its logger through scripts/bus_logger.sh"
    fail=1
}
want=$("$check" --print-url)
case "$want" in *recv_buf_size=*) ;; *) echo "FAIL: default URL $want has no recv_buf_size"; fail=1 ;; esac
env -u TRYON_LCM_URL PATH="$dir:$PATH" "$root/scripts/bus_logger.sh" "$check" --quiet x.lcmlog
grep -qF -- "--lcm-url=$want --quiet x.lcmlog" "$dir/args" || {
    echo "FAIL: default: logger got '$(cat "$dir/args")', want --lcm-url=$want"
    fail=1
}
TRYON_LCM_URL='udpm://239.255.9.9:7999?ttl=0' PATH="$dir:$PATH" \
    "$root/scripts/bus_logger.sh" "$check" y.lcmlog
grep -qF -- "--lcm-url=udpm://239.255.9.9:7999?ttl=0 y.lcmlog" "$dir/args" || {
    echo "FAIL: TRYON_LCM_URL: logger got '$(cat "$dir/args")'"
    fail=1
}
[ $fail -eq 0 ] && echo "the logger gets the stages' URL"
exit $fail
