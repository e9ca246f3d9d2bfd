//! Periodic steady state of the geared rotor by shooting (RADAU5, Floquet multipliers) and
//! by the n-th order harmonic approach, n = 1..12; reproduces the paper's Fig. 3.
//!
//! Usage: `cargo run --release --bin periodic -- [--params FILE] [--omega1 W] [--t-load T]
//! [--out DIR] [--n-max N] [--json] [--damping] [--sweep W1,W2,..] [--ignore-unknown]`
//!
//! FILE holds `name = value` lines with the FMU's parameter names in SI units (rad for
//! angles), e.g. `mu = 0.1` or `k1.x = 1e9`, and may set the constant inputs `omega1`
//! (rad/s) and `T_load` (N m) the same way; `#` starts a comment. Writes to DIR (default
//! `out/periodic`): `shooting_orbit.csv`, `harmonic_orbit_n4.csv`, `convergence.csv`,
//! `floquet.csv`, `fig3.svg`. With `--json` the last line printed is one JSON object
//! `{"shooting_residual": .., "floquet_max_abs": .., "hb": [{"n": 1, "max_rel_dev": ..}, ..]}`.
//!
//! With `tooth_contact = 2` (elastic, `model.md` §3.5) in FILE the orbit is found on the
//! 14-component elastic state (`periodic::elastic`); it also prints the mesh mode (the
//! Floquet multiplier whose mode shape loads the mesh spring most: frequency, damping ratio)
//! against the closed form (3.19), and the JSON object adds `"mesh_mode": {"freq_hz": ..,
//! "zeta": .., "multiplier_abs": .., "closed_form_hz": ..}` and `"fn_max"`, `"fn_min"`,
//! `"fn_static"` (N).
//!
//! With `--sweep W1,W2,..` (elastic teeth only) it sweeps the drive speed through the listed
//! values in rad/s, in the order given, each point started from its neighbour's orbit
//! (`periodic::elastic::continuation`), and prints one JSON object per point: `{"omega1": ..,
//! "periodic": true|false, "residual": .., "floquet_max_abs": .., "fn_max": .., "fn_min": ..,
//! "fn_static": .., "dynamic_factor": .., "free_flight": .., "periods": .., "cpu_s": ..,
//! "note": ..}`, then one line `{"closed_form_hz": .., "k_mean": .., "m_eq": .., "z1": ..}`
//! (the mesh natural frequency (3.19) and its parts); `sweep.csv` in DIR. gearstudy's
//! `[continuation]` studies call it so (docs/dynamic_factor.md).
//!
//! With `--ignore-unknown`, names in FILE that are no model parameter (FMU settings such as
//! `initialization`) are skipped instead of refused (gearstudy passes a point's values so).
//!
//! With `--damping` it computes the modal damping of the periodic orbit instead
//! (`periodic::modal`, `docs/damping.md`): a table of the modes (name, frequency, damping
//! ratio, the part the friction adds) and `damping.csv`, `damping.json` in DIR; with `--json`
//! the last line printed is that JSON object: `{"omega1": .., "T_load": .., "mesh_period": ..,
//! "shift": .., "floquet_max_abs": .., "modes": [{"mode": 1, "name": .., "freq_hz": ..,
//! "zeta": .., "dzeta": .., "freq0_hz": .., "zeta0": .., "multiplier_abs": .., "branch": ..},
//! ..]}`.

use geared_rotor::periodic::elastic::{self, ContinuationOptions};
use geared_rotor::periodic::harmonic::{harmonic_balance, HarmonicOptions, HarmonicSolution};
use geared_rotor::periodic::modal::{modal_analysis, ModalOptions};
use geared_rotor::periodic::shooting::{shoot, ShootingOptions};
use geared_rotor::periodic::{max_rel_deviation, OrbitPoint, PeriodicSystem};
use geared_rotor::rotor::{param_table, Params, ToothContact};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

struct Args {
    params: Params,
    omega1: f64,
    t_load: f64,
    out: PathBuf,
    n_max: usize,
    json: bool,
    damping: bool,
    sweep: Option<Vec<f64>>,
}

/// Sets the parameter `name` (any of the FMU's model parameters, `rotor::param_table`).
fn set_param(p: &mut Params, name: &str, v: f64) -> Result<(), String> {
    let q = param_table::by_name(name).ok_or_else(|| {
        let names: Vec<&str> = param_table::all().map(|q| q.name()).collect();
        format!("unknown parameter '{name}' (known: {})", names.join(", "))
    })?;
    q.set(p, v).map_err(|e| e.to_string())
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        params: Params::default(),
        omega1: 314.159,
        t_load: 0.0,
        out: PathBuf::from("out/periodic"),
        n_max: 12,
        json: false,
        damping: false,
        sweep: None,
    };
    let ignore_unknown = std::env::args().any(|a| a == "--ignore-unknown");
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = |what: &str| it.next().ok_or_else(|| format!("{arg} needs {what}"));
        match arg.as_str() {
            "--json" => a.json = true,
            "--damping" => a.damping = true,
            "--ignore-unknown" => {}
            "--out" => a.out = PathBuf::from(value("a directory")?),
            "--omega1" => {
                a.omega1 = value("a speed in rad/s")?
                    .parse()
                    .map_err(|e| format!("--omega1: {e}"))?
            }
            "--t-load" => {
                a.t_load = value("a load torque in N m")?
                    .parse()
                    .map_err(|e| format!("--t-load: {e}"))?
            }
            "--sweep" => {
                let list = value("drive speeds in rad/s, e.g. 100,200,300")?;
                let speeds = list
                    .split(',')
                    .map(|w| w.trim().parse::<f64>())
                    .collect::<Result<Vec<f64>, _>>()
                    .map_err(|e| format!("--sweep {list}: {e}; give speeds in rad/s separated by commas"))?;
                if speeds.is_empty() || !speeds.iter().all(|w| *w > 0.0 && w.is_finite()) {
                    return Err(format!(
                        "--sweep {list}: every speed must be positive and finite (rad/s)"
                    ));
                }
                a.sweep = Some(speeds);
            }
            "--n-max" => {
                a.n_max = value("an order")?
                    .parse()
                    .map_err(|e| format!("--n-max: {e}"))?
            }
            "--params" => {
                let path = value("a file")?;
                let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
                for (no, line) in text.lines().enumerate() {
                    let line = line.split('#').next().unwrap_or("").trim();
                    if line.is_empty() {
                        continue;
                    }
                    let (k, v) = line
                        .split_once('=')
                        .ok_or_else(|| format!("{path}:{}: expected 'name = value'", no + 1))?;
                    let v: f64 = v
                        .trim()
                        .parse()
                        .map_err(|e| format!("{path}:{}: {e}", no + 1))?;
                    match k.trim() {
                        "omega1" => a.omega1 = v,
                        "T_load" => a.t_load = v,
                        // The FMU's Enumeration (fixed), not a Real of the parameter table.
                        "tooth_contact" => {
                            a.params.tooth_contact = ToothContact::from_code(v as i32)
                                .filter(|_| v.fract() == 0.0)
                                .ok_or_else(|| {
                                    format!(
                                        "{path}:{}: tooth_contact = {v}: give 1 (rigid) or 2 (elastic)",
                                        no + 1
                                    )
                                })?
                        }
                        name if ignore_unknown && param_table::by_name(name).is_none() => {}
                        name => set_param(&mut a.params, name, v)
                            .map_err(|e| format!("{path}:{}: {e}", no + 1))?,
                    }
                }
            }
            "-h" | "--help" => {
                return Err(
                    "usage: periodic [--params FILE] [--omega1 W] [--t-load T] [--out DIR] [--n-max N] [--json] [--damping] [--sweep W1,W2,..] [--ignore-unknown]"
                        .into(),
                )
            }
            other => return Err(format!("unknown argument '{other}' (try --help)")),
        }
    }
    Ok(a)
}

fn orbit_csv(points: &[OrbitPoint]) -> String {
    let mut s = String::from("t,u1x,u1y,u1z,u2x,u2y,u2z,xi,lambda\n");
    for p in points {
        let _ = writeln!(
            s,
            "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
            p.t, p.u[0], p.u[1], p.u[2], p.u[3], p.u[4], p.u[5], p.xi, p.lambda
        );
    }
    s
}

/// Fig. 3 of the paper as SVG: orbits of both centres in the x-y plane in um, one panel per
/// gear, RADAU5 (shooting) as lines, the harmonic approach as dots; red gear 1, blue gear 2.
fn fig3_svg(orbit: &[OrbitPoint], dots: &[OrbitPoint], n: usize) -> String {
    let (w, h, pad) = (900.0, 460.0, 60.0);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (j, colour) in [(0usize, "#d62728"), (1usize, "#1f77b4")] {
        let x0 = pad + j as f64 * (w / 2.0);
        let pw = w / 2.0 - 1.5 * pad;
        let ph = h - 2.0 * pad;
        let xs = orbit.iter().chain(dots).map(|p| p.u[3 * j] * 1e6);
        let ys = orbit.iter().chain(dots).map(|p| p.u[3 * j + 1] * 1e6);
        let (xmin, xmax) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let (ymin, ymax) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let span = (xmax - xmin).max(ymax - ymin).max(1e-12) * 1.1;
        let (cx, cy) = ((xmin + xmax) / 2.0, (ymin + ymax) / 2.0);
        let px = |x: f64| x0 + pw / 2.0 + (x * 1e6 - cx) / span * pw.min(ph);
        let py = |y: f64| pad + ph / 2.0 - (y * 1e6 - cy) / span * pw.min(ph);
        let _ = writeln!(
            s,
            "<rect x=\"{x0}\" y=\"{pad}\" width=\"{pw}\" height=\"{ph}\" fill=\"none\" stroke=\"#999\"/>"
        );
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">gear {}: u{}y over u{}x [um], x {:.3}..{:.3}, y {:.3}..{:.3}</text>",
            x0 + pw / 2.0,
            pad - 12.0,
            j + 1,
            j + 1,
            j + 1,
            xmin,
            xmax,
            ymin,
            ymax
        );
        let mut path = String::new();
        for (i, p) in orbit.iter().chain(orbit.first()).enumerate() {
            let _ = write!(
                path,
                "{}{:.2},{:.2} ",
                if i == 0 { "M" } else { "L" },
                px(p.u[3 * j]),
                py(p.u[3 * j + 1])
            );
        }
        let _ = writeln!(
            s,
            "<path d=\"{path}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\"/>"
        );
        for p in dots {
            let _ = writeln!(
                s,
                "<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"3\" fill=\"{colour}\"/>",
                px(p.u[3 * j]),
                py(p.u[3 * j + 1])
            );
        }
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">Periodic orbit: solid line RADAU5 (shooting), dots harmonic approach n = {n}; red gear 1, blue gear 2</text>",
        w / 2.0,
        h - 20.0
    );
    s.push_str("</svg>\n");
    s
}

/// JSON string literal (the mode names are plain ASCII, quotes and backslashes escaped).
fn json_str(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

fn run_damping(a: &Args) -> Result<(), String> {
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let t0 = std::time::Instant::now();
    let r = modal_analysis(a.params, a.omega1, a.t_load, &ModalOptions::default())
        .map_err(|e| e.to_string())?;
    let rho_max = r
        .modes
        .iter()
        .map(|m| m.multiplier.norm())
        .fold(0.0, f64::max);
    println!(
        "modal damping of the periodic orbit: omega1 = {} rad/s, T_load = {} N m, mu = {}, law {}, T_m = {:.6e} s, {:.2} s",
        a.omega1,
        a.t_load,
        a.params.mu,
        a.params.friction_law.code(),
        r.period,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "largest exponent shift from the friction-free reference: {:.2e} of pi/T_m (branches unambiguous below 1)",
        r.shift
    );
    if r.shift > 0.5 {
        eprintln!(
            "periodic: warning: an exponent moved {:.2} of pi/T_m from its friction-free value; the frequencies (branches) may be off by multiples of the mesh frequency",
            r.shift
        );
    }
    println!(
        "{:>4}  {:<34} {:>10} {:>10} {:>11} {:>11} {:>10} {:>6}",
        "mode", "name", "f [Hz]", "zeta", "dzeta", "f(mu=0)", "|rho|", "k"
    );
    let mut csv = String::from(
        "mode,name,freq_hz,zeta,dzeta,freq0_hz,zeta0,re_s,im_s,multiplier_abs,branch\n",
    );
    let mut json = Vec::new();
    for (i, m) in r.modes.iter().enumerate() {
        println!(
            "{:>4}  {:<34} {:>10.3} {:>10.6} {:>11.3e} {:>11.3} {:>10.6} {:>6}",
            i + 1,
            m.name,
            m.freq_hz,
            m.zeta,
            m.dzeta(),
            m.freq0_hz,
            m.multiplier.norm(),
            m.branch
        );
        let _ = writeln!(
            csv,
            "{},{},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{}",
            i + 1,
            m.name,
            m.freq_hz,
            m.zeta,
            m.dzeta(),
            m.freq0_hz,
            m.zeta0,
            m.s.re,
            m.s.im,
            m.multiplier.norm(),
            m.branch
        );
        json.push(format!(
            "{{\"mode\": {}, \"name\": {}, \"freq_hz\": {:.12e}, \"zeta\": {:.12e}, \"dzeta\": {:.12e}, \"freq0_hz\": {:.12e}, \"zeta0\": {:.12e}, \"multiplier_abs\": {:.12e}, \"branch\": {}}}",
            i + 1,
            json_str(&m.name),
            m.freq_hz,
            m.zeta,
            m.dzeta(),
            m.freq0_hz,
            m.zeta0,
            m.multiplier.norm(),
            m.branch
        ));
    }
    let json = format!(
        "{{\"omega1\": {:.12e}, \"T_load\": {:.12e}, \"mesh_period\": {:.12e}, \"shift\": {:.6e}, \"floquet_max_abs\": {:.12e}, \"modes\": [{}]}}",
        a.omega1,
        a.t_load,
        r.period,
        r.shift,
        rho_max,
        json.join(", ")
    );
    for (name, text) in [("damping.csv", &csv), ("damping.json", &json)] {
        let p = a.out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    if a.json {
        println!("{json}");
    }
    Ok(())
}

/// The shooting result of either contact model, as the report uses it.
struct Shot {
    residual: f64,
    iterations: usize,
    history: Vec<f64>,
    steps_per_period: u64,
    floquet: Vec<nalgebra::Complex<f64>>,
    orbit: Vec<OrbitPoint>,
    /// Elastic teeth: the mesh mode, the closed-form omega_m (3.19) and the static force.
    elastic: Option<(Option<elastic::MeshMode>, f64, f64)>,
}

fn shoot_any(sys: &mut PeriodicSystem) -> Result<Shot, String> {
    if sys.is_elastic() {
        let z0 = sys.elastic_start().map_err(|e| e.to_string())?;
        let sh = elastic::shoot_elastic(sys, &z0, &elastic::default_options())
            .map_err(|e| e.to_string())?;
        let mm = elastic::mesh_mode(sys, &sh.z, &sh.monodromy).map_err(|e| e.to_string())?;
        let wm = elastic::closed_form_mesh_mode(sys).map_or(f64::NAN, |(w, _)| w);
        return Ok(Shot {
            residual: sh.residual,
            iterations: sh.iterations,
            history: sh.residual_history,
            steps_per_period: sh.steps_per_period,
            floquet: sh.floquet,
            orbit: sh.orbit,
            elastic: Some((mm, wm, sys.model().nominal_lambda(0.0))),
        });
    }
    let (z0, _) = sys.static_equilibrium().map_err(|e| e.to_string())?;
    let sh = shoot(sys, &z0, &ShootingOptions::default()).map_err(|e| e.to_string())?;
    Ok(Shot {
        residual: sh.residual,
        iterations: sh.iterations,
        history: sh.residual_history,
        steps_per_period: sh.steps_per_period,
        floquet: sh.floquet,
        orbit: sh.orbit,
        elastic: None,
    })
}

fn run_sweep(a: &Args, speeds: &[f64]) -> Result<(), String> {
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let sys = PeriodicSystem::new(a.params, speeds[0], a.t_load).map_err(|e| e.to_string())?;
    let Some((wm, _)) = elastic::closed_form_mesh_mode(&sys) else {
        return Err(
            "--sweep: tooth_contact = 2 (elastic) is required (the dynamic factor needs the \
             elastic contact; with rigid teeth the normal force has no mesh resonance); set \
             tooth_contact = 2 in the --params file"
                .into(),
        );
    };
    let mesh = sys.model().elastic_mesh().copied();
    let mut csv = String::from(
        "omega1,periodic,residual,floquet_max_abs,fn_max,fn_min,fn_static,dynamic_factor,free_flight,periods,cpu_s,note\n",
    );
    let mut t0 = std::time::Instant::now();
    let mut lines = Vec::new();
    elastic::continuation(
        a.params,
        a.t_load,
        speeds,
        &ContinuationOptions::default(),
        |p| {
            let cpu = t0.elapsed().as_secs_f64();
            t0 = std::time::Instant::now();
            let _ = writeln!(
                csv,
                "{:.12e},{},{:.3e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{},{:.4},{}",
                p.omega1,
                p.periodic,
                p.residual,
                p.floquet_max_abs,
                p.fn_max,
                p.fn_min,
                p.fn_static,
                p.dynamic_factor(),
                p.free_flight,
                p.periods,
                cpu,
                json_str(&p.note)
            );
            let num = |x: f64| {
                if x.is_finite() {
                    format!("{x:.12e}")
                } else {
                    "null".into()
                }
            };
            let line = format!(
                "{{\"omega1\": {}, \"periodic\": {}, \"residual\": {}, \"floquet_max_abs\": {}, \"fn_max\": {}, \"fn_min\": {}, \"fn_static\": {}, \"dynamic_factor\": {}, \"free_flight\": {}, \"periods\": {}, \"cpu_s\": {:.4}, \"note\": {}}}",
                num(p.omega1),
                p.periodic,
                num(p.residual),
                num(p.floquet_max_abs),
                num(p.fn_max),
                num(p.fn_min),
                num(p.fn_static),
                num(p.dynamic_factor()),
                num(p.free_flight),
                p.periods,
                cpu,
                json_str(&p.note)
            );
            if a.json {
                println!("{line}");
            } else {
                println!(
                    "omega1 = {:10.3} rad/s ({:8.1} rpm): max Fn / F_static = {:.4}, free flight {:5.1} % of the period, {}",
                    p.omega1,
                    p.omega1 * 30.0 / std::f64::consts::PI,
                    p.dynamic_factor(),
                    100.0 * p.free_flight,
                    if p.periodic { "periodic orbit".to_string() } else { format!("simulated ({})", p.note) }
                );
            }
            lines.push(line);
        },
    )
    .map_err(|e| e.to_string())?;
    let p = a.out.join("sweep.csv");
    std::fs::write(&p, &csv).map_err(|e| format!("{}: {e}", p.display()))?;
    let summary = format!(
        "{{\"closed_form_hz\": {:.12e}, \"k_mean\": {:.12e}, \"m_eq\": {:.12e}, \"z1\": {}}}",
        wm / (2.0 * std::f64::consts::PI),
        mesh.map_or(f64::NAN, |m| m.k_mean),
        mesh.map_or(f64::NAN, |m| m.m_eq),
        a.params.gear.z1
    );
    println!("{summary}");
    Ok(())
}

fn run(a: &Args) -> Result<(), String> {
    if a.damping {
        return run_damping(a);
    }
    if let Some(speeds) = &a.sweep {
        return run_sweep(a, speeds);
    }
    let mut sys = PeriodicSystem::new(a.params, a.omega1, a.t_load).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let write = |name: &str, text: &str| {
        let p = a.out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    let t0 = std::time::Instant::now();
    let sh = shoot_any(&mut sys)?;
    println!(
        "shooting: T_m = {:.6e} s, residual {:.3e} after {} Newton iterations (history {:?}), {} RADAU5 steps per period, {:.2} s",
        sys.period(),
        sh.residual,
        sh.iterations,
        sh.history.iter().map(|r| format!("{r:.1e}")).collect::<Vec<_>>(),
        sh.steps_per_period,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "Floquet multipliers (|.|): {}",
        sh.floquet
            .iter()
            .map(|c| format!("{:.4}", c.norm()))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let mut json_elastic = String::new();
    if let Some((mm, wm, fn_static)) = sh.elastic {
        let (hi, lo) = sh
            .orbit
            .iter()
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(h, l), p| {
                (h.max(p.lambda), l.min(p.lambda))
            });
        let f_cf = wm / (2.0 * std::f64::consts::PI);
        println!(
            "elastic contact: Fn {lo:.3} .. {hi:.3} N (static {fn_static:.3} N, max / static {:.5}); closed-form mesh natural frequency (3.19) {f_cf:.3} Hz",
            hi / fn_static
        );
        if let Some(m) = mm {
            println!(
                "mesh mode (largest mesh-spring share {:.3}): multiplier {:.6} (|.| {:.6}), f = {:.3} Hz, zeta = {:.5}",
                m.mesh_share,
                m.multiplier,
                m.multiplier.norm(),
                m.freq_hz,
                m.zeta
            );
            json_elastic = format!(
                ", \"mesh_mode\": {{\"freq_hz\": {:.9e}, \"zeta\": {:.9e}, \"multiplier_abs\": {:.9e}, \"closed_form_hz\": {:.9e}}}",
                m.freq_hz,
                m.zeta,
                m.multiplier.norm(),
                f_cf
            );
        }
        json_elastic.push_str(&format!(
            ", \"fn_max\": {hi:.9e}, \"fn_min\": {lo:.9e}, \"fn_static\": {fn_static:.9e}"
        ));
    }
    write("shooting_orbit.csv", &orbit_csv(&sh.orbit))?;
    let mut fl = String::from("re,im,abs\n");
    for c in &sh.floquet {
        let _ = writeln!(fl, "{:.12e},{:.12e},{:.12e}", c.re, c.im, c.norm());
    }
    write("floquet.csv", &fl)?;

    let hopts = HarmonicOptions::default();
    let mut table = String::from("n,max_rel_dev,residual,newton_iterations\n");
    let mut json_hb = Vec::new();
    let mut prev: Option<HarmonicSolution> = None;
    let mut n4: Option<HarmonicSolution> = None;
    println!("harmonic approach vs shooting (max deviation of the centre positions / orbit size):");
    for n in 1..=a.n_max {
        let hb = harmonic_balance(&sys, n, prev.as_ref(), &hopts)
            .map_err(|e| format!("n = {n}: {e}"))?;
        let pts: Vec<OrbitPoint> = sh.orbit.iter().map(|p| hb.point(p.t)).collect();
        let dev = max_rel_deviation(&pts, &sh.orbit);
        println!(
            "  n = {n:2}: {dev:.3e}  (residual {:.1e}, {} iterations)",
            hb.residual, hb.iterations
        );
        let _ = writeln!(table, "{n},{dev:.6e},{:.3e},{}", hb.residual, hb.iterations);
        json_hb.push(format!("{{\"n\": {n}, \"max_rel_dev\": {dev:.6e}}}"));
        if n == 4 {
            n4 = Some(hb.clone());
        }
        prev = Some(hb);
    }
    write("convergence.csv", &table)?;
    if let Some(hb) = &n4 {
        let dots = hb.orbit(48);
        write("harmonic_orbit_n4.csv", &orbit_csv(&dots))?;
        write("fig3.svg", &fig3_svg(&sh.orbit, &dots, 4))?;
        println!("Fig. 3: {}", a.out.join("fig3.svg").display());
    }
    if a.json {
        println!(
            "{{\"shooting_residual\": {:.6e}, \"floquet_max_abs\": {:.6e}, \"hb\": [{}]{json_elastic}}}",
            sh.residual,
            sh.floquet.first().map_or(0.0, |c| c.norm()),
            json_hb.join(", ")
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match parse_args().and_then(|a| run(&a)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("periodic: {e}");
            ExitCode::FAILURE
        }
    }
}
