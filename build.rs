//! Build script: checks `modelDescription/modelDescription.xml` and generates the variable
//! table, the GUID-filled description and its FMI 3.0 form (`build/fmi3_description.rs`)
//! into OUT_DIR. The rules live in
//! `build/model_description_check.rs` (unit-tested there); a bad description stops the
//! build with a message naming the variable and the rule.

#[path = "build/fmi3_description.rs"]
mod fmi3_description;
#[path = "src/hash.rs"]
mod hash;
#[path = "build/model_description_check.rs"]
mod model_description_check;

use fmi3_description::fmi3_description;
use model_description_check::{process, SOURCE};
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed={SOURCE}");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=build/model_description_check.rs");
    println!("cargo:rerun-if-changed=build/fmi3_description.rs");
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
            let xml3 = match fmi3_description(&xml) {
                Ok(x) => x,
                Err(msg) => panic!("\n\n{SOURCE} cannot be converted to FMI 3.0: {msg}\n\n"),
            };
            std::fs::write(out.join("modelDescription.xml"), xml)
                .expect("write modelDescription.xml");
            std::fs::write(out.join("modelDescription3.xml"), xml3)
                .expect("write modelDescription3.xml");
        }
        Err(msg) => panic!("\n\n{SOURCE} is invalid: {msg}\n\n"),
    }
}
