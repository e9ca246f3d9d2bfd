//! Long runs of the FMI 3.0 C-ABI fuzzer (the CI run is `tests/fuzz_fmi3.rs`):
//! `cargo run --release --example fuzz_fmi3 -- SEQUENCES BLOBS [SEED]` prints the counts
//! (sequences, calls, statuses, early returns, blobs accepted/refused, the slowest call)
//! and the violations; exits with 1 if there are any.

#[path = "../tests/fuzz_fmi3/driver.rs"]
mod driver;

use geared_rotor::radau5::Snapshot;
use geared_rotor::rotor::NY;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: u64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (sequences, blobs, seed) = (num(1, 100_000), num(2, 20_000), num(3, 0x6765_6172_6533));
    let t0 = std::time::Instant::now();
    let rep = driver::run(seed, sequences, blobs, Snapshot::<NY>::serialized_len());
    println!("seed {seed:#x}, {:.1} s", t0.elapsed().as_secs_f64());
    println!("{rep}");
    if !rep.violations.is_empty() {
        std::process::exit(1);
    }
}
