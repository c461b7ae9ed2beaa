#!/usr/bin/env bash
# The bus figures in docs/bus.md: the cost of signing and verifying one 640x480 depth frame.
#   docs/figures/bus_figures.sh BUILD_DIR
set -euo pipefail
B=${1:?usage: docs/figures/bus_figures.sh BUILD_DIR}
for _ in 1 2 3; do "$B/bus/tryon-bus-check" --seal-cost; done
