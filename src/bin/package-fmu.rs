//! Builds `target/fmu/GearedRotor.fmu`: `cargo run --release --bin package-fmu`.
//!
//! Steps:
//! 1. `cargo build --release --lib` (a no-op when the cdylib is fresh), so this one command
//!    is enough on a fresh clone;
//! 2. checks that `target/release/libgeared_rotor.so` carries the GUID of the model
//!    description compiled into this binary (both come from the same build.rs output);
//! 3. writes the zip: `modelDescription.xml` (GUID filled in, byte for byte what build.rs
//!    generated), `binaries/linux64/GearedRotor.so`, `documentation/index.html` (generated
//!    from the variable table) and `documentation/figure.svg` (the gear pair and its line of
//!    action, drawn from the default geometry). Fixed timestamps (1980-01-01) and file order,
//!    so the same sources give the same archive bytes for the same .so.

use geared_rotor::fmi2::variables::{
    Causality, VarType, Variability, Variable, GUID, MODEL_DESCRIPTION_XML, VARIABLES,
};
use geared_rotor::gear::{GearData, PairGeometry};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn fmt_value(v: &Variable) -> String {
    match (v.start, v.ty) {
        (None, _) => String::new(),
        (Some(x), VarType::Integer) => format!("{}", x as i64),
        (Some(x), VarType::Boolean) => (if x != 0.0 { "true" } else { "false" }).into(),
        (Some(x), VarType::Real) => format!("{x}"),
    }
}

fn display(v: &Variable) -> String {
    let x = match v.start {
        Some(x) => x,
        None => return String::new(),
    };
    let (f, u) = match v.display_unit {
        "mm" => (1e3, "mm"),
        "deg" => (180.0 / std::f64::consts::PI, "deg"),
        "rpm" => (30.0 / std::f64::consts::PI, "rpm"),
        "kN" => (1e-3, "kN"),
        _ => return String::new(),
    };
    format!(" ({:.6} {u})", x * f)
}

/// SVG of the default pair in the transverse plane: base, reference and tip circles, the
/// line of action T1-T2 tangent to both base circles, the active part A-E, the pitch point
/// C and the working pressure angle (model.md §2, §3.1).
fn figure(g: &PairGeometry) -> String {
    let s = 3000.0; // px per m (1 mm = 3 px)
    let (w, h) = (560.0, 420.0);
    let (cx1, cy) = (w / 2.0 - g.a_w * s / 2.0, h / 2.0);
    let cx2 = cx1 + g.a_w * s;
    let a = g.alpha_wt;
    // e_w = (cos(-a), sin(-a)) from c1 to T1 (theta = 0); y axis of SVG points down.
    let (ex, ey) = (a.cos(), -(-a).sin());
    let t1 = (cx1 + g.rb1 * s * ex, cy + g.rb1 * s * ey);
    let t2 = (cx2 - g.rb2 * s * ex, cy - g.rb2 * s * ey);
    let dir = (
        (t2.0 - t1.0) / (g.a_w * a.sin() * s),
        (t2.1 - t1.1) / (g.a_w * a.sin() * s),
    );
    let p = |sig: f64| (t1.0 + sig * s * dir.0, t1.1 + sig * s * dir.1);
    let (pa, pe, pc) = (p(g.sigma_a), p(g.sigma_e), p(g.sigma_c));
    let mut o = String::new();
    let _ = writeln!(
        o,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(o, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    for (cx, rb, r, ra, name) in [
        (cx1, g.rb1, g.r1, g.ra1, "1"),
        (cx2, g.rb2, g.r2, g.ra2, "2"),
    ] {
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="none" stroke="#888" stroke-dasharray="4 3"/>"##,
            ra * s
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="none" stroke="#444" stroke-dasharray="1 3"/>"##,
            r * s
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="none" stroke="#1f4e9c" stroke-width="1.5"/>"##,
            rb * s
        );
        let _ = writeln!(
            o,
            r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="3" fill="black"/><text x="{:.2}" y="{:.2}">C{name}</text>"##,
            cx - 8.0,
            cy + 18.0
        );
    }
    let _ = writeln!(
        o,
        r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#c0392b" stroke-width="1.2"/>"##,
        t1.0, t1.1, t2.0, t2.1
    );
    let _ = writeln!(
        o,
        r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#c0392b" stroke-width="4"/>"##,
        pa.0, pa.1, pe.0, pe.1
    );
    let _ = writeln!(
        o,
        r##"<line x1="{cx1:.2}" y1="{cy:.2}" x2="{cx2:.2}" y2="{cy:.2}" stroke="#999"/>"##
    );
    let _ = writeln!(
        o,
        r##"<line x1="{cx1:.2}" y1="{cy:.2}" x2="{:.2}" y2="{:.2}" stroke="#1f4e9c"/>"##,
        t1.0, t1.1
    );
    let _ = writeln!(
        o,
        r##"<line x1="{cx2:.2}" y1="{cy:.2}" x2="{:.2}" y2="{:.2}" stroke="#1f4e9c"/>"##,
        t2.0, t2.1
    );
    for (pt, lab) in [(t1, "T1"), (t2, "T2"), (pa, "A"), (pe, "E"), (pc, "C")] {
        let _ = writeln!(
            o,
            r#"<circle cx="{:.2}" cy="{:.2}" r="2.5"/><text x="{:.2}" y="{:.2}">{lab}</text>"#,
            pt.0,
            pt.1,
            pt.0 + 5.0,
            pt.1 - 5.0
        );
    }
    let _ = writeln!(
        o,
        r#"<text x="10" y="20">Default pair, transverse plane (1 mm = 3 px): base circles (solid), reference (dotted), tip (dashed)</text>"#
    );
    let _ = writeln!(
        o,
        r#"<text x="10" y="{}">Line of action T1-T2 at alpha_wt = {:.3} deg; active contact A-E (thick), pitch point C; a_w = {:.3} mm</text>"#,
        h - 12.0,
        g.alpha_wt.to_degrees(),
        g.a_w * 1e3
    );
    let _ = writeln!(o, "</svg>");
    o
}

fn documentation(g: &PairGeometry) -> String {
    let mut o = String::new();
    let _ = write!(
        o,
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>GearedRotor FMU</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;font-size:90%}}th{{background:#eee}}
code{{background:#f4f4f4}}</style></head><body>
<h1>GearedRotor &mdash; helical gear pair with tooth friction (FMI 2.0 Co-Simulation)</h1>
<p>GUID <code>{guid}</code>.</p>
<h2>What the model is</h2>
<p>Two rigid rotors carry a meshing helical involute gear pair. Each rotor centre translates in x, y, z on
bearing springs and dampers; rotor 1 is driven with the prescribed speed <code>omega1</code> (input), rotor 2 turns
freely against a rotational damper <code>d_phi</code> and the load torque <code>T_load</code> (input). The teeth cannot
penetrate: one scalar constraint whose Lagrange multiplier is the normal contact force <code>Fn</code>. Coulomb friction
acts along all contact lines in the plane of action, integrated in closed form. The result is an index-2
differential-algebraic system (Jehle &amp; Fidlin, PAMM 2015) integrated by RADAU5 (Hairer &amp; Wanner), which
continues across communication points and sub-steps internally.</p>
<p>The input <code>omega1</code> is made continuous inside the model by a critically damped second-order filter with corner
frequency <code>omega1_filter_frequency</code>: <code>omega1'' = w_c^2 (omega1_ref - omega1) - 2 w_c omega1'</code>, <code>w_c = 2 pi f</code>
(like Modelica's <code>Speed(exact=false)</code>), so a held input step gives a bounded torque. Input derivatives set with
<code>fmi2SetRealInputDerivatives</code> (order 1) extrapolate inputs linearly over the communication step; output derivatives
(order 1) come from the collocation polynomial of the last step.</p>
<figure><img src="figure.svg" alt="gear pair and line of action"><figcaption>The default pair in the transverse plane.</figcaption></figure>
<h2>Default pair: calculated parameters</h2>
<table><tr><th>quantity</th><th>value</th></tr>
<tr><td>base radii r_b1, r_b2</td><td>{rb1:.6} mm, {rb2:.6} mm</td></tr>
<tr><td>operating centre distance a_w</td><td>{aw:.6} mm</td></tr>
<tr><td>working pressure angle alpha_wt</td><td>{awt:.6} deg</td></tr>
<tr><td>base helix angle beta_b</td><td>{bb:.6} deg</td></tr>
<tr><td>transverse base pitch p_bt</td><td>{pbt:.6} mm</td></tr>
<tr><td>contact ratios eps_alpha, eps_beta (eps_1, eps_2)</td><td>{ea:.6}, {eb:.6} ({e1:.6}, {e2:.6})</td></tr>
<tr><td>analytic loss factor H_V</td><td>{hv:.6}</td></tr></table>
<h2>Limits of validity</h2>
<ul>
<li>Rigid teeth, perfect involute geometry, single-flank contact: the output <code>contact_lost</code> becomes true when
<code>Fn &lt; 0</code> (the teeth would lift off); results after that are outside the model (logged under <code>logEvents</code>).</li>
<li>Gear data: z1, z2 &ge; 5; m_n &gt; 0; 0 &lt; alpha_n &lt; 45 deg; |beta| &lt; 45 deg; b &gt; 0; no interference
(0 &le; sigma_A &lt; sigma_E &le; a_w sin alpha_wt); eps_alpha + eps_beta &gt; 1; tip radii above the base radii.
Violations are rejected in <code>fmi2ExitInitializationMode</code> with a message naming the parameter and the bound.</li>
<li>Gear axes stay parallel to z (no tilting degrees of freedom); tilting moments are reported, not applied.</li>
<li>Friction: law 1 (Coulomb, constant mu) has no start-up from standstill (the sliding direction is undefined at zero
speed; law 2 regularises it). Laws 3 and 4 are empirical fits, valid in their fitted ranges (see "Friction laws").</li>
<li>The centre distance must stay larger than r_b1 + r_b2; a solver failure returns <code>fmi2Discard</code> with the state at
<code>fmi2LastSuccessfulTime</code>.</li>
<li>Accuracy: RADAU5 with the tolerance of <code>fmi2SetupExperiment</code> (else <code>rtol</code>), absolute tolerances
rtol times physical scales per state (1e-5 m displacements, 1e-2 m/s velocities, 1e3 N contact force, 1 J energies),
internal step at most <code>h_max</code>. While the inputs stay the same, RADAU5 steps across communication points
and the outputs there come from its dense output; when an input or a tunable changes, the step that went past the
communication point is retaken to end on it.</li>
</ul>
<h2>Friction laws (parameter <code>friction_law</code>)</h2>
<p>The friction force per unit length of contact line is <code>-mu_loc q v_T/|v_T|</code> with the line load
<code>q = |Fn| / contact_length</code> and the sliding velocity <code>v_T</code> in the tangent plane. Output
<code>mu_eff</code>: the mean of mu_loc along the lines; <code>mu_mz</code>: the ISO/TR 14179-2 coefficient at the current
load and speed (every law).</p>
<ol>
<li>Coulomb: <code>mu_loc = mu</code> (default).</li>
<li>Regularised Coulomb: <code>v_T/|v_T|</code> replaced by <code>v_T/sqrt(|v_T|^2 + v_reg^2)</code> (<code>v_reg</code> [m/s]); smooth
at the pitch line; tends to law 1 as v_reg^2 ln(1/v_reg).</li>
<li>ISO/TR 14179-2 mean coefficient (Schlenk, as in Niemann/Winter): <code>mu_mz = 0.048 (F_bt/b / (v_SigmaC rho_redC))^0.2
eta_oil^-0.05 Ra^0.25 X_L</code> in N/mm, m/s, mm, mPa s, um (<code>F_bt = Fn cos beta_b</code>; <code>v_SigmaC</code> the sum of the
rolling speeds and <code>rho_redC</code> the equivalent radius of curvature at the pitch point); fitted to FZG tests in the
mixed/EHL regime; v_SigmaC is floored at 0.1 m/s.</li>
<li>Local EHL coefficient along the lines (Xu, Kahraman, Anderson, Maddock, J. Mech. Des. 129, 2007, for a 75W90 oil):
<code>mu = exp(f) P_h^b2 |SR|^b3 V_e^b6 nu0^b7 R^b8</code>, <code>f = b1 + b4 |SR| P_h log10(nu0) + b5 exp(-|SR| P_h log10 nu0)
+ b9 exp(S)</code>, b1..b9 = -8.916465, 1.03303, 1.036077, -0.354068, 2.812084, -0.100601, 0.752755, -0.390958, 0.620305; P_h
[GPa] Hertzian pressure from q and E1, nu1, E2, nu2; SR slide-to-roll ratio; V_e [m/s] entraining speed; nu0 = eta_oil
[mPa s]; R [m] equivalent radius; S = Ra [um]. Fitted for P_h about 0.5-2.5 GPa, SR up to about 1.</li>
</ol>
<p>For laws 3 and 4 the coefficient depends on the contact force, which is then found by a scalar solve.</p>
<h2>Variables</h2>
<table><tr><th>name</th><th>causality</th><th>variability</th><th>type</th><th>unit</th><th>default</th><th>description</th></tr>
"#,
        guid = GUID,
        rb1 = g.rb1 * 1e3,
        rb2 = g.rb2 * 1e3,
        aw = g.a_w * 1e3,
        awt = g.alpha_wt.to_degrees(),
        bb = g.beta_b.to_degrees(),
        pbt = g.p_bt * 1e3,
        ea = g.eps_alpha,
        eb = g.eps_beta,
        e1 = g.eps_1,
        e2 = g.eps_2,
        hv = g.h_v
    );
    for v in VARIABLES.iter() {
        let caus = match v.causality {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculated parameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        };
        let var = match v.variability {
            Variability::Constant => "constant",
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        };
        let _ = writeln!(
            o,
            "<tr><td><code>{}</code></td><td>{caus}</td><td>{var}</td><td>{:?}</td><td>{}</td><td>{}{}</td><td>{}</td></tr>",
            html_escape(v.name),
            v.ty,
            html_escape(v.unit),
            fmt_value(v),
            display(v),
            html_escape(v.description)
        );
    }
    let _ = writeln!(o, "</table>\n<p>Log categories: logStatusError, logStatusWarning, logEvents, logSolver, logAll.</p>\n</body></html>");
    o
}

fn target_dir(manifest: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("target"))
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

fn run() -> Result<PathBuf, String> {
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
    let files: [(&str, Vec<u8>, u32); 4] = [
        (
            "modelDescription.xml",
            MODEL_DESCRIPTION_XML.as_bytes().to_vec(),
            0o644,
        ),
        ("binaries/linux64/GearedRotor.so", so, 0o755),
        (
            "documentation/index.html",
            documentation(&geom).into_bytes(),
            0o644,
        ),
        (
            "documentation/figure.svg",
            figure(&geom).into_bytes(),
            0o644,
        ),
    ];
    let out_dir = target.join("fmu");
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let out = out_dir.join("GearedRotor.fmu");
    let tmp = out_dir.join("GearedRotor.fmu.tmp");
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
        Ok(p) => {
            println!("wrote {} (GUID {GUID})", p.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("package-fmu: {e}");
            ExitCode::FAILURE
        }
    }
}
