#!/usr/bin/env bash
# The bus refuses other machines. netns mode: tryon-sim runs in a network namespace whose default
# route leads to a second namespace (a "LAN" made of a veth pair, never the machine's
# interfaces); a peer there sends wire-valid BODY datagrams unicast to the stage's address and to
# the multicast group. Unsigned ones and one signed with another key are counted as refused and
# never reach the sim; one signed with the bus key gets through (so the path itself works).
# Needs root (ip netns): without it the test is skipped (exit 77), not passed.
# loopback mode (no root): the same datagrams unicast to 127.0.0.1, and the key file's checks
# (made 0600; refused when others can read it or when it is short).
#   test_bus_netns.sh netns|loopback TRYON_SIM BUS_UDP_SEND TRYON_BUS_CHECK
set -u
mode=$1
sim=$2
send=$3
check=$4
a=tryonA$$
b=tryonB$$
if [ "$mode" = netns ] && ! ip netns add "$a" 2>/dev/null; then
    echo "SKIP: cannot create network namespaces (needs root: ip netns add)"
    exit 77
fi
dir=$(mktemp -d)
fail=0
cleanup() {
    [ -n "${pid:-}" ] && kill "$pid" 2>/dev/null
    ip netns del "$a" 2>/dev/null
    ip netns del "$b" 2>/dev/null
    rm -rf "$dir"
}
trap cleanup EXIT
port=$((20000 + $$ % 20000))
group=239.255.76.67
prefix=NS$$_
export TRYON_BUS_KEY_FILE="$dir/bus.key" TRYON_CHANNEL_PREFIX=$prefix OMP_WAIT_POLICY=passive
url="udpm://$group:$port?ttl=0&recv_buf_size=8388608"
if [ "$mode" = loopback ]; then
    "$check" --seal-cost >/dev/null || { echo "FAIL: no key made"; fail=1; }
    [ "$(stat -c %a "$dir/bus.key")" = 600 ] || { echo "FAIL: key not mode 600"; fail=1; }
    cp "$dir/bus.key" "$dir/open.key" && chmod 644 "$dir/open.key"
    TRYON_BUS_KEY_FILE="$dir/open.key" "$check" --seal-cost 2>"$dir/err" &&
        { echo "FAIL: a key others can read was used"; fail=1; }
    grep -q "chmod 600" "$dir/err" || { echo "FAIL: no fix named: $(cat "$dir/err")"; fail=1; }
    printf short >"$dir/short.key" && chmod 600 "$dir/short.key"
    TRYON_BUS_KEY_FILE="$dir/short.key" "$check" --seal-cost 2>/dev/null &&
        { echo "FAIL: a short key was used"; fail=1; }
    TRYON_LCM_URL=$url "$sim" --backend c --verts 400 --queue all >"$dir/sim.log" 2>&1 &
    pid=$!
    for _ in $(seq 100); do grep -q "waiting for" "$dir/sim.log" && break; sleep 0.1; done
    "$send" 127.0.0.1 "$port" "${prefix}BODY" 5 plain
    "$send" 127.0.0.1 "$port" "${prefix}BODY" 6 plain
    TRYON_BUS_KEY_FILE="$dir/other.key" "$send" 127.0.0.1 "$port" "${prefix}BODY" 8 sign
    sleep 0.5
    "$send" 127.0.0.1 "$port" "${prefix}BODY" 7 sign
else
    set -e
    ip netns add "$b"
    ip link add "va$$" type veth peer name "vb$$"
    ip link set "va$$" netns "$a"
    ip link set "vb$$" netns "$b"
    ip -n "$a" addr add 10.199.0.1/24 dev "va$$"
    ip -n "$b" addr add 10.199.0.2/24 dev "vb$$"
    for ns in "$a" "$b"; do ip -n "$ns" link set lo up; done
    ip -n "$a" link set "va$$" up
    ip -n "$b" link set "vb$$" up
    ip -n "$a" route add default via 10.199.0.2 # the group is joined on this "LAN" interface
    ip -n "$b" route add 224.0.0.0/4 dev "vb$$"
    set +e
    ip netns exec "$a" env TRYON_LCM_URL="$url" \
        "$sim" --backend c --verts 400 --queue all >"$dir/sim.log" 2>&1 &
    pid=$!
    for _ in $(seq 100); do grep -q "waiting for" "$dir/sim.log" && break; sleep 0.1; done
    in_b() { ip netns exec "$b" "$@"; }
    in_b "$send" 10.199.0.1 "$port" "${prefix}BODY" 5 plain # unicast to the stage's address
    in_b "$send" "$group" "$port" "${prefix}BODY" 6 plain   # to the group
    TRYON_BUS_KEY_FILE="$dir/other.key" in_b "$send" "$group" "$port" "${prefix}BODY" 8 sign
    sleep 0.5
    in_b "$send" "$group" "$port" "${prefix}BODY" 7 sign # the control: the right key
fi
sleep 1.5
kill -TERM "$pid"
wait "$pid"
pid=
log=$(cat "$dir/sim.log")
echo "$log"
echo "$log" | grep -q "3 BODY messages dropped" || { echo "FAIL: 3 refused BODY expected"; fail=1; }
[ "$(echo "$log" | grep -c "not signed with this host's bus key")" -eq 3 ] ||
    { echo "FAIL: 3 refusals for the key expected"; fail=1; }
echo "$log" | grep -qE "body [568]\b" && { echo "FAIL: a refused body reached the sim"; fail=1; }
echo "$log" | grep -qE "body 7\b|1 frames simulated" ||
    { echo "FAIL: the signed body did not arrive: the test proves nothing"; fail=1; }
[ $fail -eq 0 ] && echo "other machines' messages refused, the signed one delivered"
exit $fail
