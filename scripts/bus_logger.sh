#!/usr/bin/env bash
# lcm-logger on the very URL the stages use ($TRYON_LCM_URL or the default, which carries the
# large receive buffer a 640x480 depth stream needs): without it the logger listens with the
# kernel's default buffer and loses frames the stages receive.
#   scripts/bus_logger.sh TRYON_BUS_CHECK_EXE [lcm-logger options...] LOGFILE
set -euo pipefail
check=$1
shift
url=$("$check" --print-url)
exec lcm-logger --lcm-url="$url" "$@"
