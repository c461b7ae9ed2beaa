#!/usr/bin/env bash
# tryon set-up: installs what is missing (Debian packages), configures, builds, then
#   ./setup.sh          runs the pipeline on a bundled recording (the demo)
#   ./setup.sh test     runs the whole test suite: Release build, then an ASan+UBSan build,
#                       plus the clang-format check
set -euo pipefail
cd "$(dirname "$0")"
mode=${1:-demo}
case "$mode" in demo | test) ;; *)
    echo "usage: ./setup.sh [demo|test]" >&2
    exit 2
    ;;
esac

jobs=$(nproc 2>/dev/null || echo 2)
packages=(build-essential cmake pkg-config git iproute2 procps
    liblcm-dev liblcm-bin libglib2.0-dev libcmocka-dev
    ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
    libfreenect-dev libfreenect-bin libopenni2-dev
    clang-format gnuplot-nox libbullet-dev
    clang-14 libclang-rt-14-dev libsodium-dev
    libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libsdl2-dev libpng-dev
    xvfb xauth ffmpeg libcjson-dev libglx-mesa0 python3
    assimp-testmodels libopencv-dev time valgrind)

as_root() {
    if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi
}

install_missing() {
    local missing=()
    for p in "${packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        echo "== installing: ${missing[*]}"
        as_root apt-get update -qq
        as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
    fi
}

# LCM's default transport is UDP multicast with ttl=0 (it never leaves the host). A machine
# with no default route has no route for multicast either, and lcm_create then fails: route
# the multicast range over loopback. See docs/bus.md.
multicast_route() {
    if ! ip route get 239.255.76.67 >/dev/null 2>&1; then
        echo "== no multicast route: adding 224.0.0.0/4 on loopback (docs/bus.md says why)"
        as_root ip route add 224.0.0.0/4 dev lo
    fi
    # Large depth frames need a large socket buffer; LCM asks for 8 MiB, the kernel caps it.
    local rmem
    rmem=$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)
    if [ "$rmem" -lt 8388608 ]; then
        as_root sysctl -q -w net.core.rmem_max=8388608 2>/dev/null ||
            echo "   (could not raise net.core.rmem_max from $rmem; fine for one pipeline)"
    fi
}

build() { # build DIR [cmake args...]
    local dir=$1
    shift
    cmake -S . -B "$dir" "$@" >"$dir.configure.log" 2>&1 || {
        cat "$dir.configure.log"
        return 1
    }
    cmake --build "$dir" -j"$jobs"
}

format_check() {
    local bad
    bad=$(git ls-files '*.c' '*.h' '*.cl' '*.cpp' | xargs -r clang-format --dry-run -Werror 2>&1 | grep -o '^[^:]*\.[a-z]*:' | sort -u || true)
    if [ -n "$bad" ]; then
        echo "clang-format: these files are not formatted (run clang-format -i):" >&2
        echo "$bad" >&2
        return 1
    fi
    echo "== clang-format: all C sources formatted"
}

install_missing
multicast_route
mkdir -p build
build build -DCMAKE_BUILD_TYPE=Release
./build/bus/tryon-bus-check

if [ "$mode" = test ]; then
    format_check
    echo "== tests, Release build"
    ctest --test-dir build --output-on-failure -j"$jobs" --timeout 300
    echo "== tests, AddressSanitizer + UndefinedBehaviorSanitizer build"
    mkdir -p build-asan
    build build-asan -DCMAKE_BUILD_TYPE=Debug -DTRYON_SANITIZE=ON
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        ctest --test-dir build-asan --output-on-failure -j"$jobs" --timeout 600
    echo "== fuzzing: every libFuzzer harness for 6 s (tests/fuzz/run.sh; docs/building.md)"
    mkdir -p build-fuzz
    CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Debug -DTRYON_FUZZ=ON \
        >build-fuzz.configure.log 2>&1 || {
        cat build-fuzz.configure.log
        exit 1
    }
    cmake --build build-fuzz -j"$jobs" --target fuzz_all
    tests/fuzz/run.sh 6 build-fuzz
    exit 0
fi

exec ./scripts/demo.sh build
