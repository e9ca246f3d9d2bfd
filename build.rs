//! Build script: checks `modelDescription/modelDescription.xml` and generates the variable
//! table and the GUID-filled description into OUT_DIR. The rules live in
//! `build/model_description_check.rs` (unit-tested there); a bad description stops the
//! build with a message naming the variable and the rule.

#[path = "src/hash.rs"]
mod hash;
#[path = "build/model_description_check.rs"]
mod model_description_check;

use model_description_check::{process, SOURCE};
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed={SOURCE}");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=build/model_description_check.rs");
    println!("cargo:rerun-if-changed=src/hash.rs");
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR"));
    let text = match std::fs::read_to_string(manifest.join(SOURCE)) {
        Ok(t) => t,
        Err(e) => panic!("cannot read {SOURCE}: {e}"),
    };
    // Silence the checker's internal unwinding; the message is reported below.
    std::panic::set_hook(Box::new(|_| {}));
    let result = process(&text);
    let _ = std::panic::take_hook();
    match result {
        Ok((table, xml)) => {
            std::fs::write(out.join("variables_gen.rs"), table).expect("write variables_gen.rs");
            std::fs::write(out.join("modelDescription.xml"), xml)
                .expect("write modelDescription.xml");
        }
        Err(msg) => panic!("\n\n{SOURCE} is invalid: {msg}\n\n"),
    }
}
