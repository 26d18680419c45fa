#!/usr/bin/env bash
# The bench's own set-up: what scripts/setup.sh installs, plus gnuplot-nox (the plots; 4 small
# Debian packages, no X) and time (/usr/bin/time, peak memory in bench/scaling.sh). Idempotent.
set -euo pipefail
exec bash "$(dirname "$0")/../scripts/setup.sh" gnuplot-nox time "$@"
