//! Builds `target/fmu/GearedRotor.fmu` (FMI 2.0) and `target/fmu/GearedRotor-fmi3.fmu`
//! (FMI 3.0): `cargo run --release --bin package-fmu`.
//!
//! Steps:
//! 1. `cargo build --release --lib` (a no-op when the cdylib is fresh), so this one command
//!    is enough on a fresh clone;
//! 2. checks that `target/release/libgeared_rotor.so` carries the GUID of the model
//!    description compiled into this binary (both come from the same build.rs output);
//! 3. writes the zip: `modelDescription.xml` (what build.rs generated, GUID filled in, plus
//!    `generationDateAndTime` = the commit date of the sources, `build_date`),
//!    `binaries/linux64/GearedRotor.so`, and `documentation/`: `index.html` (generated from
//!    the model description, `index_html`), the figures (`figures`), the model, solver and
//!    FMI documents of `docs/` with the sketch and the figures of the load reversal and the
//!    rattle with elastic teeth (`docs/figures/*.png`), `LICENSE.txt`, and the reference run
//!    `GearedRotor_in.csv` / `GearedRotor_ref.csv` of `data/reference_run/`. Fixed
//!    timestamps (1980-01-01) and file order, so the same commit gives the same archive
//!    bytes for the same .so.
//! 4. writes the FMI 3.0 archive the same way: the FMI 3.0 `modelDescription.xml` that
//!    build.rs generated from the same source (`build/fmi3_description.rs`), the same
//!    shared library under the 3.0 platform tuple, `binaries/x86_64-linux/` (it exports the `fmi3*` functions beside the `fmi2*` ones), the same
//!    documentation with an index.html that names FMI 3.0.

mod build_date;
mod description;
mod figures;
mod index_html;

use geared_rotor::fmi2::variables::{GUID, MODEL_DESCRIPTION_XML, MODEL_DESCRIPTION_XML_FMI3};
use geared_rotor::gear::{GearData, PairGeometry};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// Files of the repository shipped in documentation/ (compiled in, so the packager needs
/// nothing at run time but the library it packs).
const MODEL_MD: &str = include_str!("../../../docs/model.md");
const RADAU5_MD: &str = include_str!("../../../docs/radau5.md");
const FMU_MD: &str = include_str!("../../../docs/fmu.md");
const VALIDITY_MD: &str = include_str!("../../../docs/validity.md");
const DRIVETRAIN_MD: &str = include_str!("../../../docs/drivetrain.md");
const FRICTION_MD: &str = include_str!("../../../docs/friction.md");
const SKETCH_SVG: &str = include_str!("../../../docs/figures/geared_rotor.svg");
// The coast flanks with elastic teeth: figures of scripts/coast_figures.py (README "Load
// reversal and rattle (elastic teeth)").
const REVERSAL_PNG: &[u8] = include_bytes!("../../../docs/figures/reversal.png");
const RATTLE_PNG: &[u8] = include_bytes!("../../../docs/figures/rattle.png");
// The dynamic factor study with and without backlash (README "Dynamic factor").
const DYNAMIC_FACTOR_PNG: &[u8] = include_bytes!("../../../docs/figures/dynamic_factor.png");
const LICENSE: &str = include_str!("../../../LICENSE");
const RADAU5_REFERENCE_MD: &str = include_str!("../../../data/radau5/reference.md");
const REF_IN: &str = include_str!("../../../data/reference_run/GearedRotor_in.csv");
const REF_OUT: &str = include_str!("../../../data/reference_run/GearedRotor_ref.csv");

fn target_dir(manifest: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("target"))
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

fn run() -> Result<(PathBuf, PathBuf), String> {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(&cargo)
        .args(["build", "--release", "--lib"])
        .current_dir(&manifest)
        .status()
        .map_err(|e| format!("cannot run {cargo} build: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build --release --lib failed ({status})"));
    }
    let target = target_dir(&manifest);
    let so_path = target.join("release").join("libgeared_rotor.so");
    let so =
        std::fs::read(&so_path).map_err(|e| format!("cannot read {}: {e}", so_path.display()))?;
    if !contains(&so, GUID.as_bytes()) {
        return Err(format!(
            "{} does not contain GUID {GUID}: the library and this packager come from different sources; rerun",
            so_path.display()
        ));
    }
    let geom =
        PairGeometry::new(&GearData::default()).map_err(|e| format!("default geometry: {e}"))?;
    let epoch = build_date::source_epoch(&manifest);
    let date = epoch.map(|(t, _)| build_date::iso8601_utc(t));
    let xml = build_date::with_generation_date(MODEL_DESCRIPTION_XML, date.as_deref());
    let md = description::parse(&xml).map_err(|e| format!("model description: {e}"))?;
    let info = index_html::BuildInfo {
        date: date.as_deref(),
        date_source: epoch.map(|(_, s)| s).unwrap_or(""),
        guid: GUID,
    };
    let xml3 = build_date::with_generation_date(MODEL_DESCRIPTION_XML_FMI3, date.as_deref());
    // The FMI 3.0 index.html: the same document, naming the version of its archive.
    let mut md3 = md.clone();
    md3.model.insert("fmiVersion".into(), "3.0".into());
    let text = |s: &str| s.as_bytes().to_vec();
    let mut files: Vec<(&str, Vec<u8>, u32)> = vec![
        ("modelDescription.xml", xml.clone().into_bytes(), 0o644),
        ("binaries/linux64/GearedRotor.so", so, 0o755),
        (
            "documentation/index.html",
            index_html::document(&md, &geom, &info).into_bytes(),
            0o644,
        ),
        (
            "documentation/figure.svg",
            figures::transverse(&geom).into_bytes(),
            0o644,
        ),
        (
            "documentation/result.svg",
            figures::result_plot(REF_OUT)?.into_bytes(),
            0o644,
        ),
        (
            "documentation/figures/geared_rotor.svg",
            text(SKETCH_SVG),
            0o644,
        ),
        (
            "documentation/figures/reversal.png",
            REVERSAL_PNG.to_vec(),
            0o644,
        ),
        (
            "documentation/figures/rattle.png",
            RATTLE_PNG.to_vec(),
            0o644,
        ),
        (
            "documentation/figures/dynamic_factor.png",
            DYNAMIC_FACTOR_PNG.to_vec(),
            0o644,
        ),
        ("documentation/model.md", text(MODEL_MD), 0o644),
        ("documentation/radau5.md", text(RADAU5_MD), 0o644),
        ("documentation/fmu.md", text(FMU_MD), 0o644),
        ("documentation/validity.md", text(VALIDITY_MD), 0o644),
        ("documentation/drivetrain.md", text(DRIVETRAIN_MD), 0o644),
        ("documentation/friction.md", text(FRICTION_MD), 0o644),
        // radau5.md cites the Fortran figures it is compared with
        (
            "documentation/reference.md",
            text(RADAU5_REFERENCE_MD),
            0o644,
        ),
        ("documentation/LICENSE.txt", text(LICENSE), 0o644),
        ("documentation/GearedRotor_in.csv", text(REF_IN), 0o644),
        ("documentation/GearedRotor_ref.csv", text(REF_OUT), 0o644),
    ];
    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let out = write_fmu(&out_dir, "GearedRotor.fmu", &files)?;
    files[0].1 = xml3.into_bytes();
    // FMI 3.0 names the platform by its tuple (section 2.5.1.2).
    files[1].0 = "binaries/x86_64-linux/GearedRotor.so";
    files[2].1 = index_html::document(&md3, &geom, &info).into_bytes();
    let out3 = write_fmu(&out_dir, "GearedRotor-fmi3.fmu", &files)?;
    Ok((out, out3))
}

/// Writes `files` into the archive `out_dir/name` (through a temporary file, renamed when
/// complete), with fixed timestamps and in the given order.
fn write_fmu(
    out_dir: &Path,
    name: &str,
    files: &[(&str, Vec<u8>, u32)],
) -> Result<PathBuf, String> {
    let out = out_dir.join(name);
    let tmp = out_dir.join(format!("{name}.tmp"));
    let file =
        std::fs::File::create(&tmp).map_err(|e| format!("cannot create {}: {e}", tmp.display()))?;
    let mut zip = ZipWriter::new(file);
    for (name, bytes, mode) in files.iter() {
        let opts = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .last_modified_time(DateTime::default())
            .unix_permissions(*mode);
        zip.start_file(*name, opts)
            .map_err(|e| format!("zip {name}: {e}"))?;
        zip.write_all(bytes)
            .map_err(|e| format!("zip {name}: {e}"))?;
    }
    zip.finish().map_err(|e| format!("zip: {e}"))?;
    std::fs::rename(&tmp, &out)
        .map_err(|e| format!("cannot move {} to {}: {e}", tmp.display(), out.display()))?;
    Ok(out)
}

fn main() -> ExitCode {
    match run() {
        Ok((p, p3)) => {
            println!("wrote {} (GUID {GUID})", p.display());
            println!(
                "wrote {} (FMI 3.0, instantiationToken {GUID})",
                p3.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("package-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
