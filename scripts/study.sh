#!/usr/bin/env bash
# The example study: efficiency of the default pair over drive speed x load torque for two
# friction coefficients (examples/studies/efficiency_map.toml, 60 points), on a Dask
# LocalCluster with one worker per core; rows in out/study/rows/, maps in out/study/*.png.
# Builds the .fmu first if it is missing. A rerun skips the points already done. Extra
# arguments go to `gearstudy sweep` (e.g. --scheduler tcp://HOST:8786, --workers 4,
# --overwrite after rebuilding the .fmu). See docs/studies.md.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
if [ ! -f target/fmu/GearedRotor.fmu ]; then
    echo "== cargo run --release --bin package-fmu"
    cargo run --release --quiet --bin package-fmu
fi
"$REPO/.venv/bin/gearstudy" sweep examples/studies/efficiency_map.toml --out out/study "$@"
"$REPO/.venv/bin/gearstudy" plot out/study
"$REPO/.venv/bin/gearstudy" table out/study efficiency
