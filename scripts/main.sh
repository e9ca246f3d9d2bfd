#!/usr/bin/env bash
# Main job: build the .fmu, simulate the default pair through FMPy, write out/
# (results.csv, T1/Fn/TE/orbits PNGs) and print the summary. Extra arguments go
# to scripts/main_job.py (see --help).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
exec "$VPY" scripts/main_job.py "$@"
