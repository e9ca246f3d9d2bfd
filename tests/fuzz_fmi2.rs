//! CI run of the C-ABI fuzzer (`tests/fuzz_fmi2/driver.rs`; docs/fmu.md "Robustness"):
//! seeded random call sequences against a shadow FMI 2.0 state machine and mutated state
//! blobs. Fails on any violation: a caught panic (fmi2Fatal), a call over 2 s, an OK or
//! Warning where FMI 2.0 requires an error, a non-finite value behind OK or Warning.
//! Longer runs: `cargo run --release --example fuzz_fmi2 -- SEQUENCES BLOBS [SEED]`.

#[path = "fuzz_fmi2/driver.rs"]
mod driver;

use geared_rotor::radau5::Snapshot;
use geared_rotor::rotor::NY;

/// CI size: 4-8 s on the shared 2-core VM (figures in docs/fmu.md "Fuzzer").
const SEQUENCES: u64 = 20_000;
const BLOBS: u64 = 5_000;

#[test]
fn fuzz_the_c_abi_short_run() {
    let rep = driver::run(
        0x6765_6172_6564,
        SEQUENCES,
        BLOBS,
        Snapshot::<NY>::serialized_len(),
    );
    println!("{rep}");
    assert!(rep.violations.is_empty(), "{rep}");
    // The run exercised what it claims to: every status but Fatal/Pending, required errors,
    // accepted and refused blobs.
    assert!(
        rep.statuses[0] > 0 && rep.statuses[2] > 0 && rep.statuses[3] > 0,
        "{rep}"
    );
    assert!(rep.required_errors > 0 && rep.blobs_refused > 0, "{rep}");
}
