//! documentation/index.html of the .fmu: what the model is (sketch), version, licence and
//! generation date, an example result, the default pair, the limits of validity, and the
//! table of every variable read from the model description (start, min, max, unit and
//! display unit). Each variable row is `<tr id="var-NAME">` with cells of class `start`,
//! `min`, `max`, `unit`, `display` (tests/test_documentation.py reads them). The notes of
//! `docs/` that the .fmu ships (model, solver, FMU, validity, drivetrain, friction) are
//! rendered into the same page at packaging time ([`md_html`]); the example result is the
//! steady state of the default pair, simulated here with the crate itself.

use crate::description::{Description, ScalarVariable};
use geared_rotor::gear::{GearData, PairGeometry};
use geared_rotor::rotor::Params;
use geared_rotor::sim::{Initialization, Simulation, SolverSettings};
use std::fmt::Write as _;

#[path = "md_html.rs"]
mod md_html;

/// The notes shipped in documentation/ and rendered into index.html: (file, section id,
/// title, text).
const NOTES: [(&str, &str, &str, &str); 6] = [
    (
        "model.md",
        "note-model",
        "The model (equations)",
        include_str!("../../../docs/model.md"),
    ),
    (
        "friction.md",
        "note-friction",
        "Friction laws",
        include_str!("../../../docs/friction.md"),
    ),
    (
        "fmu.md",
        "note-fmu",
        "FMI behaviour",
        include_str!("../../../docs/fmu.md"),
    ),
    (
        "validity.md",
        "note-validity",
        "Limits of validity",
        include_str!("../../../docs/validity.md"),
    ),
    (
        "radau5.md",
        "note-radau5",
        "The RADAU5 solver",
        include_str!("../../../docs/radau5.md"),
    ),
    (
        "drivetrain.md",
        "note-drivetrain",
        "A drivetrain of two FMUs",
        include_str!("../../../docs/drivetrain.md"),
    ),
];

/// Files of documentation/ a rendered note may link to (besides the notes themselves).
const FILES: [&str; 7] = [
    "figures/geared_rotor.svg",
    "figures/reversal.png",
    "figures/rattle.png",
    "figures/dynamic_factor.png",
    "LICENSE.txt",
    "GearedRotor_in.csv",
    "GearedRotor_ref.csv",
];

/// The notes as HTML sections (collapsed; a link into one opens it).
fn notes_html() -> String {
    let map: Vec<(&str, &str)> = NOTES.iter().map(|(f, id, _, _)| (*f, *id)).collect();
    let mut o = String::new();
    for (file, id, title, text) in NOTES {
        let _ = write!(
            o,
            "<details id=\"{id}\"><summary><b>{title}</b> ({file}, also in this folder as Markdown: \
             <a href=\"{file}\">{file}</a>)</summary>\n<div class=\"note\">\n{}</div></details>\n",
            md_html::to_html(text, id, &map, &FILES)
        );
    }
    o
}

/// The steady state of the default pair as an inline SVG (T1, Fn, TE over four mesh
/// periods, started on the periodic orbit), or a note why not.
fn steady_result() -> String {
    let run = || -> Result<String, String> {
        let omega1 = 314.159;
        let settings = SolverSettings {
            rtol: 1e-8,
            h_max: 1e-4,
        };
        let mut sim = Simulation::with_initialization(
            Params::default(),
            settings,
            0.0,
            omega1,
            0.0,
            Initialization::Periodic,
        )
        .map_err(|e| e.to_string())?;
        let t_m = 2.0 * std::f64::consts::PI / (f64::from(GearData::default().z1) * omega1);
        let n = 4 * 64;
        let h = 4.0 * t_m / n as f64;
        let mut csv = String::from("time,T1,Fn,TE\n");
        for k in 0..=n {
            if k > 0 {
                sim.do_step((k - 1) as f64 * h, h)
                    .map_err(|e| e.to_string())?;
            }
            let o = sim.outputs();
            let _ = writeln!(csv, "{},{},{},{}", k as f64 * h, o.t1, o.fn_, o.te);
        }
        crate::figures::result_plot(&csv)
    };
    match run() {
        Ok(svg) => svg
            .replacen(
                "<svg ",
                r#"<svg style="max-width:100%;height:auto" role="img" "#,
                1,
            )
            .replace(
                "time [ms]",
                "time [ms] on the periodic orbit (4 mesh periods)",
            ),
        Err(e) => format!(
            "<p>(the steady-state example could not be computed: {})</p>",
            escape(&e)
        ),
    }
}

pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `raw` as written in the XML, and for Reals with a display unit also converted:
/// `0.3490658503988659 (20 deg)`.
fn with_display(md: &Description, v: &ScalarVariable, raw: Option<&str>) -> String {
    let Some(raw) = raw else {
        return String::new();
    };
    // the declared 1e-300 stands for "> 0" (FMI bounds are inclusive)
    if raw.parse::<f64>() == Ok(1e-300) {
        return "1e-300 (&gt; 0)".into();
    }
    let mut s = escape(raw);
    if v.base == "Real" {
        if let (Some(u), Some(du), Ok(x)) = (v.ty("unit"), v.ty("displayUnit"), raw.parse::<f64>())
        {
            if let Some(d) = md.display_unit(u, du) {
                let y = d.factor * x + d.offset;
                let _ = write!(s, " ({} {})", short(y), escape(&d.name));
            }
        }
    }
    s
}

/// A number with up to 6 significant digits, no exponent noise for ordinary values.
fn short(y: f64) -> String {
    if y == 0.0 {
        return "0".into();
    }
    let a = y.abs();
    if !(1e-4..1e7).contains(&a) {
        return format!("{y:.5e}");
    }
    let decimals = (5 - a.log10().floor() as i32).clamp(0, 10) as usize;
    let s = format!("{y:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// What the build knows about itself, shown in the header.
pub struct BuildInfo<'a> {
    pub date: Option<&'a str>,
    pub date_source: &'a str,
    pub guid: &'a str,
}

pub fn document(md: &Description, g: &PairGeometry, info: &BuildInfo) -> String {
    let model = |k: &str| md.model.get(k).map(String::as_str).unwrap_or("");
    let exp = |k: &str| {
        md.default_experiment
            .get(k)
            .map(String::as_str)
            .unwrap_or("")
    };
    let date = match info.date {
        Some(d) => format!("{d} ({})", info.date_source),
        None => "not recorded (built outside git without SOURCE_DATE_EPOCH)".into(),
    };
    let n_of = |c: &str| md.vars.iter().filter(|v| v.get("causality") == c).count();
    let mut o = String::new();
    let _ = write!(
        o,
        r##"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{name} FMU</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>body{{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;line-height:1.45}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;font-size:88%;vertical-align:top}}
th{{background:#eee}}code{{background:#f4f4f4;overflow-wrap:anywhere}}figure{{margin:1em 0}}
img{{max-width:100%;height:auto;border:1px solid #ddd}}figcaption{{font-size:90%;color:#333}}
.wide{{overflow-x:auto}}table.vars{{width:100%;table-layout:fixed}}table.vars td{{overflow-wrap:anywhere}}
table.vars th:nth-child(1){{width:9%}}table.vars th:nth-child(2),table.vars th:nth-child(3){{width:7%}}
table.vars th:nth-child(4){{width:6%}}table.vars th:nth-child(5){{width:10%}}
table.vars th:nth-child(6),table.vars th:nth-child(7){{width:8%}}
table.vars th:nth-child(8),table.vars th:nth-child(9){{width:5%}}table.vars th:nth-child(10){{width:35%}}
pre{{background:#f6f6f6;padding:.5em;overflow-x:auto;font-size:88%}}details{{margin:.6em 0;border:1px solid #ddd;padding:.3em .8em}}
summary{{cursor:pointer}}.note table{{margin:.5em 0}}.note img{{max-width:60%}}</style></head><body>
<h1>{name} &mdash; helical gear pair with tooth friction</h1>
<p>FMI {fmi} Co-Simulation FMU, model version <b>{version}</b>, licence <b>{license}</b>
(<a href="LICENSE.txt">LICENSE.txt</a>), generated {date} by {tool}. GUID <code>{guid}</code>.
Platform in this archive: linux64. Author: {author}.</p>
<figure><img src="figures/geared_rotor.svg" alt="sketch of both rotors, bearings, axes, line of action and helix hand">
<figcaption>The model: two rigid rotors on spring-damper bearings in x, y, z; gear 1 is driven at the speed
<code>omega1</code>, gear 2 brakes with <code>d_phi</code> and <code>T_load</code>; the tooth force acts along the
line of action T&#8321;&#8594;T&#8322;; with <code>beta</code> &gt; 0 gear 1 is left-hand, gear 2 right-hand.</figcaption></figure>
<h2>What the model is</h2>
<p>{description}. Each rotor centre translates in x, y and z on linear bearing springs and dampers; rotor 1 turns
with the prescribed speed <code>omega1</code> (input), rotor 2 turns freely against a rotational damper
<code>d_phi</code> and the load torque <code>T_load</code> (input). The rigid teeth cannot penetrate: one constraint
whose Lagrange multiplier is the normal tooth force <code>Fn</code>. Coulomb friction acts along every contact line
in the plane of action and is integrated in closed form. The resulting index-2 differential-algebraic system
(G. Jehle and A. Fidlin, PAMM 2015) is integrated by RADAU5 (Hairer and Wanner), which continues across
communication points and sub-steps internally.</p>
<p>The complete model with numbered equations is in <a href="#note-model">model.md</a> (rendered under
&ldquo;Notes&rdquo; below, and as Markdown in this folder; sections are cited as model.md &sect;N), the solver in
<a href="#note-radau5">radau5.md</a>, the FMI behaviour in <a href="#note-fmu">fmu.md</a>. The input <code>omega1</code> is made continuous by a critically damped second-order
filter (model.md &sect;8), so a held step gives a bounded torque; input derivatives (order 1) are used when the master
sets them; output derivatives (order 1) come from RADAU5's dense output.</p>
<p>Interface: {n_in} inputs, {n_out} outputs, {n_par} parameters, {n_calc} calculated parameters. Default experiment:
{start} to {stop} s, step {step} s (no default tolerance: the parameter rtol applies unless the master passes one to fmi2SetupExperiment).</p>
<h2>Example result</h2>
<figure>{steady}
<figcaption>The steady state of the default pair: 3000 rpm, <code>T_load</code> = 0, loaded by the damper
<code>d_phi</code> = 0.5 N m s/rad (<code>T_damp</code> = d_phi omega2 = 103 N m on gear 2), started on its periodic
orbit (<code>initialization</code> = periodic), four mesh periods (0.74 ms each) computed with this model when the
FMU was packaged. T1 and Fn vary by a few hundredths of a per cent over the mesh period, TE by nanometres: the rigid
teeth and the uniform load along the contact lines leave only the bearing response to the mesh.</figcaption></figure>
<figure><img src="result.svg" alt="T1, Fn and TE of the reference run">
<figcaption>The reference run shipped with this FMU: the default pair from rest at 3000 rpm, <code>T_load</code>
ramped from 0 to 20 N m between 2 and 6 ms (inputs <a href="{model_id}_in.csv">{model_id}_in.csv</a>, outputs every
0.1 ms in <a href="{model_id}_ref.csv">{model_id}_ref.csv</a>, computed at tolerance 1e-10). The decaying oscillation
of about 660 Hz is the vibration of the rotors on their bearings excited by the start from rest; the mesh frequency
(1350 Hz) is above what this output interval shows.</figcaption></figure>
<h2>Elastic teeth: load reversal and rattle</h2>
<p>With <code>tooth_contact</code> = elastic the teeth have drive and coast flanks with the normal backlash
<code>j_bn</code> between them (model.md &sect;3.5, &sect;3.6; outputs <code>mesh_state</code>, <code>Fn_coast</code>,
<code>impacts</code>). Both runs: the default pair at 3000 rpm from the static equilibrium, <code>j_bn</code> = 0.1 mm,
communication step 0.1 ms, tolerance 1e-8, every doStep <code>fmi2OK</code> (the lift-off of rigid teeth is part of this
model: no warning, no Discard).</p>
<figure><img src="figures/reversal.png" alt="T_load, mesh_state, Fn and Fn_coast, TE and drive gap of a load reversal">
<figcaption>Load reversal: <code>T_load</code> +100 &rarr; &minus;100 N m between 20 and 25 ms (<code>d_phi</code> = 0.05
N m s/rad, mu = 0). The drive flanks part at 22.7 ms, gear 2 crosses the play and hits the coast flanks at 24.0 ms
(one rebound: <code>impacts</code> = 2); <code>Fn_coast</code> rings down to the static balance of the reversed load
(2327.7 N against 2327.1 N), the drive gap to the play (111.3 um: <code>j_bn</code>/cos beta_b = 105.6 um, widened by
the bearings' deflection) plus the coast flanks' approach (7.4 um).</figcaption></figure>
<figure><img src="figures/rattle.png" alt="omega1 and omega2, mesh_state, Fn and Fn_coast, impacts in a rattle">
<figcaption>Rattle: no load, <code>d_phi</code> = 0.01 N m s/rad, <code>omega1</code> &plusmn;5 % at 30 Hz set at every
communication point. Gear 2 lags and overtakes gear 1: the teeth hit both flanks, 460 impacts per second, forces up
to 1485 N (drive) and 1568 N (coast), in free flight 53 % of the time.</figcaption></figure>
<figure><img src="figures/dynamic_factor.png" alt="max Fn over its static value against the drive speed, with and without backlash, sweeps up and down">
<figcaption>Dynamic factor: max <code>Fn</code> over its static value against the drive speed, the default pair made spur,
<code>T_load</code> = 100 N m, each point started from its neighbour's periodic orbit (the <code>periodic</code> program's
sweep), up and down. The mesh resonance lies around 6833 rpm, where the mesh frequency z1 n / 60 meets the closed-form
mesh natural frequency sqrt(c_gamma b / m_eq) / 2 pi = 3075 Hz (model.md (3.19)). With the backlash of 0.1 mm it
softens with a jump and hysteresis (up: 2.3 at 6000 rpm, the large orbit from 6500; down: 7.8 at 6500 rpm); without
backlash the two-sided mesh is parametrically unstable there and grows without bound (290 at 6000 rpm, drawn at the
cut of the axis).</figcaption></figure>
<h2>Default pair</h2>
<figure><img src="figure.svg" alt="default pair in the transverse plane">
<figcaption>The default pair in the transverse plane (to scale, bar = 10 mm): base circles solid, reference circles
dotted, tip circles dashed; the line of action T&#8321;T&#8322; touches both base circles at the tangent points
T&#8321;, T&#8322; (points, not the torque output <code>T1</code>); the thick part A&ndash;E is where teeth are in
contact (A: tip of gear 2, E: tip of gear 1); C is the pitch point. Working pressure angle alpha_wt =
{awt:.3} deg, operating centre distance a_w = {aw:.3} mm.</figcaption></figure>
<table><tr><th>calculated parameter</th><th>value</th></tr>
<tr><td>base radii r_b1, r_b2</td><td>{rb1:.6} mm, {rb2:.6} mm</td></tr>
<tr><td>operating centre distance a_w</td><td>{aw:.6} mm</td></tr>
<tr><td>working pressure angle alpha_wt</td><td>{awt:.6} deg</td></tr>
<tr><td>base helix angle beta_b</td><td>{bb:.6} deg</td></tr>
<tr><td>transverse base pitch p_bt</td><td>{pbt:.6} mm</td></tr>
<tr><td>contact ratios eps_alpha, eps_beta (eps_1, eps_2)</td><td>{ea:.6}, {eb:.6} ({e1:.6}, {e2:.6})</td></tr>
<tr><td>analytic loss factor H_V of the model (model.md &sect;9.7; load spread uniformly over the lines)</td><td>{hv:.6}</td></tr>
<tr><td>loss factor H_V_iso of ISO/TR 14179-2 (Ohlendorf; friction.md)</td><td>{hv_iso:.6}</td></tr></table>
<h2>Limits of validity</h2>
<ul>
<li>Rigid teeth with perfect involute flanks; the only compliance is in the bearings.</li>
<li>Single-flank contact: when <code>Fn &lt; 0</code> (the teeth would lift off) or the drive speed is no longer
positive, <code>contact_lost</code> or the message says so and <code>fmi2DoStep</code> returns <code>fmi2Warning</code>
once per episode (<code>on_lift_off</code> = discard: <code>fmi2Discard</code> at the located instant); results after
that are outside the model (<a href="#note-validity">validity.md</a>).</li>
<li>Gear data (model.md &sect;2): z1, z2 &ge; 5; m_n &gt; 0; 0 &lt; alpha_n &lt; 45 deg; |beta| &lt; 45 deg; b &gt; 0;
no interference (0 &le; sigma_A, sigma_E &le; a_w sin alpha_wt); sigma_A &lt; sigma_E; eps_alpha + eps_beta &gt; 1;
tip radii above the base radii. A refused set is reported in <code>fmi2ExitInitializationMode</code> with
<code>fmi2Error</code>, naming the parameter that repairs it alone and its limit (e.g. z1 = 10 with the other
defaults: &ldquo;z1 &gt;= 13, x1 &gt;= 0.2002, h_aP &lt;= 0.7653&rdquo;).</li>
<li>The axes stay parallel to z; tilting moments are reported, not applied.</li>
<li>Friction: law 1 (Coulomb, constant mu) has no start-up from standstill (the sliding direction is undefined at zero
speed; law 2 regularises it). Laws 3 and 4 are empirical fits, valid in their fitted ranges (see &ldquo;Friction
laws&rdquo;).</li>
<li>The centre distance must stay above r_b1 + r_b2; when the solver cannot continue, <code>fmi2DoStep</code> returns
<code>fmi2Discard</code> and the state is the one at <code>fmi2LastSuccessfulTime</code>.</li>
<li>Accuracy: RADAU5 with the tolerance of <code>fmi2SetupExperiment</code> (else <code>rtol</code>), absolute
tolerances rtol times physical scales per state, internal step at most <code>h_max</code>.</li>
</ul>
<h2>Friction laws (parameter <code>friction_law</code>)</h2>
<p>The friction force per unit length of contact line is <code>-mu_loc q v_T/|v_T|</code> with the line load
<code>q = |Fn| / contact_length</code> and the sliding velocity <code>v_T</code> in the tangent plane. Output
<code>mu_eff</code>: the mean of mu_loc along the lines; <code>mu_mz</code>: the ISO/TR 14179-2 coefficient at the
current load and speed. Formulas, sources, units and ranges: <a href="#note-friction">friction.md</a>.</p>
<ol>
<li>Coulomb: <code>mu_loc = mu</code> (default).</li>
<li>Regularised Coulomb: <code>v_T/|v_T|</code> replaced by <code>v_T/sqrt(|v_T|^2 + v_reg^2)</code>
(<code>v_reg</code> [m/s]).</li>
<li>Mean coefficient of ISO/TR 14179-2 (Schlenk's formula): <code>mu_mz</code> from the transverse load per face width,
the sum speed and the equivalent radius of curvature at the pitch point, <code>eta_oil</code>, <code>Ra</code> and
<code>X_L</code>. Checked against a published worked example (the FZG C40 gear: mu_mz 0.0256, H_V 0.1986;
friction.md). The loss of a run uses the model's loss factor <code>H_V</code>; the standard's loss is
<code>mu_mz H_V_iso P_in</code> with Ohlendorf's <code>H_V_iso</code> (equal for spur pairs, 16-19 % lower for
helical ones). Outside the fitted range (v_t &ge; 1 m/s, F_bt/b &ge; 150 N/mm) a warning is logged.</li>
<li>Local EHL coefficient along the lines (Xu, Kahraman, Anderson, Maddock 2007, fitted for a 75W90 gear oil) from the
local Hertzian pressure, slide-to-roll ratio, entraining speed, radius of curvature, <code>eta_oil</code> and
<code>Ra</code>; <code>E1</code>, <code>nu1</code>, <code>E2</code>, <code>nu2</code> give the Hertzian pressure.</li>
<li>Benedict &amp; Kelley's coefficient (1961) along the lines from the line load, the local sliding and sum speeds,
<code>eta_oil</code> and <code>Ra</code>; below the sliding speed <code>v_reg</code> the force falls off linearly
(the formula diverges at the pitch line; friction.md).</li>
</ol>
<p>For laws 3 to 5 the coefficient depends on the contact force, which is then found by a scalar solve. Law 4
integrates mu_loc along every line (about 4-5 times the cost of law 1 per right-hand side); its loss against speed
follows a published use of the same formula on the Petry-Johnson spur test gear (413 N m, 2000-10000 rpm: within the
bands derived from that publication's tables to 3 %; friction.md).</p>
<h2>Variables</h2>
<p>Values in SI units as in modelDescription.xml; in brackets the same value in the display unit.
min and max are the declared bounds (inclusive); 1e-300 stands for &ldquo;greater than 0&rdquo;.</p>
<div class="wide"><table class="vars"><tr><th>name</th><th>causality</th><th>variability</th><th>type</th><th>start</th><th>min</th><th>max</th><th>unit</th><th>display unit</th><th>description</th></tr>
"##,
        name = escape(model("modelName")),
        fmi = escape(model("fmiVersion")),
        version = escape(model("version")),
        license = escape(model("license")),
        tool = escape(model("generationTool")),
        author = escape(model("author")),
        description = escape(model("description")),
        date = escape(&date),
        guid = escape(info.guid),
        model_id = "GearedRotor",
        n_in = n_of("input"),
        n_out = n_of("output"),
        n_par = n_of("parameter"),
        n_calc = n_of("calculatedParameter"),
        start = escape(exp("startTime")),
        stop = escape(exp("stopTime")),
        step = escape(exp("stepSize")),
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
        hv = g.h_v,
        hv_iso = geared_rotor::gear::friction::iso_mean::ohlendorf_h_v(
            f64::from(g.data.z1),
            f64::from(g.data.z2),
            g.cos_beta_b,
            g.eps_1,
            g.eps_2
        ),
        steady = steady_result()
    );
    for v in &md.vars {
        let mut ty = v.base.clone();
        if v.base == "Enumeration" {
            if let Some(t) = v.ty("declaredType").and_then(|n| md.types.get(n)) {
                let items: Vec<String> = t
                    .items
                    .iter()
                    .map(|(val, n, _)| format!("{val} = {}", escape(n)))
                    .collect();
                ty = format!("Enumeration ({})", items.join(", "));
            }
        }
        let _ = writeln!(
            o,
            r#"<tr id="var-{name}"><td><code>{name}</code></td><td>{caus}</td><td>{var}</td><td>{ty}</td><td class="start">{start}</td><td class="min">{min}</td><td class="max">{max}</td><td class="unit">{unit}</td><td class="display">{disp}</td><td>{desc}</td></tr>"#,
            name = escape(v.get("name")),
            caus = escape(v.get("causality")),
            var = escape(v.get("variability")),
            ty = ty,
            start = with_display(md, v, v.ty("start")),
            min = with_display(md, v, v.ty("min")),
            max = with_display(md, v, v.ty("max")),
            unit = escape(v.ty("unit").unwrap_or("")),
            disp = escape(v.ty("displayUnit").unwrap_or("")),
            desc = escape(v.get("description")),
        );
    }
    let _ = writeln!(
        o,
        "</table></div>\n<p>Log categories: logStatusError, logStatusWarning, logEvents, logSolver, logAll.</p>\n\
         <h2 id=\"notes\">Notes</h2>\n<p>The notes of this folder, rendered (click a title to open it).</p>\n{}\n</body></html>",
        notes_html()
    );
    o
}
