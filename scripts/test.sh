#!/usr/bin/env bash
# All tests: the Rust tests (cargo test --release) and the FMPy suite (pytest
# tests/ on target/fmu/GearedRotor.fmu). Runs both, prints both
# summaries, fails if either failed. Extra arguments go to pytest.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
mkdir -p target
status=0

# Build the cdylib (target/release/libgeared_rotor.so, which tests/fmi2_exports.rs
# dlopens) and the .fmu first: `cargo test` alone does not place the cdylib there.
echo "== cargo build --release; cargo run --release --bin package-fmu"
cargo build --release
cargo run --release --quiet --bin package-fmu

echo "== cargo test --release --no-fail-fast"
set +e
cargo test --release --no-fail-fast 2>&1 | tee target/cargo-test.log
cargo_rc=${PIPESTATUS[0]}
set -e
[ "$cargo_rc" -eq 0 ] || status=1

echo "== pytest tests (FMPy on the packaged .fmu)"
set +e
"$VPY" -m pytest tests -ra "$@" 2>&1 | tee target/pytest.log
pytest_rc=${PIPESTATUS[0]}
set -e
[ "$pytest_rc" -eq 0 ] || status=1

echo
echo "== summary"
awk '/^test result:/ { for (i = 1; i <= NF; i++) { if ($(i+1) ~ /^passed;?$/) p += $i; if ($(i+1) ~ /^failed;?$/) f += $i; if ($(i+1) ~ /^ignored;?$/) g += $i } n++ }
     END { printf "cargo test: %d passed, %d failed, %d ignored (%d test binaries)\n", p, f, g, n }' target/cargo-test.log
echo "cargo test exit status: $cargo_rc"
echo "pytest: $(grep -E '(passed|failed|error|skipped|deselected).* in [0-9.]+s' target/pytest.log | tail -1 | tr -d '=' | sed 's/^ *//;s/ *$//')"
echo "pytest exit status: $pytest_rc"
exit "$status"
