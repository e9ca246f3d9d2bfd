//! CI run of the FMI 3.0 C-ABI fuzzer (`tests/fuzz_fmi3/driver.rs`, the mirror of
//! `tests/fuzz_fmi2.rs` at the same size): seeded random call sequences against a shadow
//! FMI 3.0 state machine and mutated state blobs (FMI 2.0 blobs among them). Fails on any
//! violation: a caught panic (fmi3Fatal), a call over 2 s, an OK or Warning where FMI 3.0
//! requires an error, a non-finite value behind OK or Warning, inconsistent out-arguments
//! of fmi3DoStep. Longer runs: `cargo run --release --example fuzz_fmi3 -- SEQUENCES BLOBS [SEED]`.

#[path = "fuzz_fmi3/driver.rs"]
mod driver;

use geared_rotor::radau5::Snapshot;
use geared_rotor::rotor::NY;

/// The size of the FMI 2.0 CI run (tests/fuzz_fmi2.rs).
const SEQUENCES: u64 = 20_000;
const BLOBS: u64 = 5_000;

#[test]
fn fuzz_the_fmi3_c_abi_short_run() {
    let rep = driver::run(
        0x6765_6172_6533,
        SEQUENCES,
        BLOBS,
        Snapshot::<NY>::serialized_len(),
    );
    println!("{rep}");
    assert!(rep.violations.is_empty(), "{rep}");
    // The run exercised what it claims to: OK, Discard and Error statuses, required
    // errors, early returns, accepted and refused blobs.
    assert!(
        rep.statuses[0] > 0 && rep.statuses[2] > 0 && rep.statuses[3] > 0,
        "{rep}"
    );
    assert!(rep.early_returns > 0, "{rep}");
    assert!(
        rep.required_errors > 0 && rep.blobs_refused > 0 && rep.blobs_accepted > 0,
        "{rep}"
    );
}
