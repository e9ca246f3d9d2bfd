//! Advice for a refused gear pair (`model.md` §2): which single parameter, changed to
//! which limit value, makes the set valid.
//!
//! The limits are computed, not guessed: for each candidate parameter the other data are
//! kept, the parameter is moved in the direction that can help, the first value for
//! which the whole validation of [`PairGeometry::check`] passes is found (integers: step
//! by one; reals: expanding steps, then bisection), and the reported limit is rounded
//! outward and checked again. A candidate that cannot repair the set within its range
//! is left out. The parameter named in the error is the first candidate that works, in
//! an order per rule (the parameter a designer changes first).

use super::geometry::{GearData, PairGeometry, ParamError};

/// Which rule of `model.md` §2 a refused set violates (only the derived rules get advice).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    /// A bound on one parameter alone; its message already states the limit.
    Plain,
    /// `r_a1 > r_b1`.
    TipBelowBase1,
    /// `r_a2 > r_b2`.
    TipBelowBase2,
    /// `inv alpha_wt > 0` (zero-backlash centre distance from x1 + x2).
    WorkingAngle,
    /// `sigma_A >= 0`: the tip of gear 2 passes T1 (interference at gear 1's root).
    Interference1,
    /// `sigma_E <= a_w sin alpha_wt`: the tip of gear 1 passes T2.
    Interference2,
    /// `sigma_A < sigma_E`: the tips do not overlap on the line of action.
    TipsApart,
    /// `eps_alpha + eps_beta > 1`.
    ContactRatio,
}

/// A parameter the advice may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Knob {
    Z1,
    Z2,
    X1,
    X2,
    HaP,
    B,
}

/// Which way a candidate is moved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Dir {
    Up,
    Down,
}

impl Knob {
    fn name(self) -> &'static str {
        match self {
            Knob::Z1 => "z1",
            Knob::Z2 => "z2",
            Knob::X1 => "x1",
            Knob::X2 => "x2",
            Knob::HaP => "h_aP",
            Knob::B => "b",
        }
    }

    fn get(self, d: &GearData) -> f64 {
        match self {
            Knob::Z1 => d.z1 as f64,
            Knob::Z2 => d.z2 as f64,
            Knob::X1 => d.x1,
            Knob::X2 => d.x2,
            Knob::HaP => d.ha_coef,
            Knob::B => d.b,
        }
    }

    fn set(self, d: &GearData, v: f64) -> GearData {
        let mut e = *d;
        match self {
            Knob::Z1 => e.z1 = v as i32,
            Knob::Z2 => e.z2 = v as i32,
            Knob::X1 => e.x1 = v,
            Knob::X2 => e.x2 = v,
            Knob::HaP => e.ha_coef = v,
            Knob::B => e.b = v,
        }
        e
    }

    /// How far the search goes from the current value v in direction dir.
    fn end(self, v: f64, dir: Dir) -> f64 {
        let up = dir == Dir::Up;
        match self {
            Knob::Z1 | Knob::Z2 => {
                if up {
                    400.0
                } else {
                    5.0
                }
            }
            Knob::X1 | Knob::X2 => {
                if up {
                    v + 3.0
                } else {
                    v - 3.0
                }
            }
            Knob::HaP => {
                if up {
                    v.max(1.0) * 3.0
                } else {
                    0.0
                }
            }
            Knob::B => {
                if up {
                    v * 1000.0
                } else {
                    0.0
                }
            }
        }
    }
}

fn valid(d: &GearData) -> bool {
    PairGeometry::check(d).is_ok()
}

/// The limit value of `knob` moved in `dir` from `d` at which the set becomes valid, or
/// None when no value in the search range does.
fn limit(d: &GearData, knob: Knob, dir: Dir) -> Option<f64> {
    let v0 = knob.get(d);
    let end = knob.end(v0, dir);
    let s = if dir == Dir::Up { 1.0 } else { -1.0 };
    if matches!(knob, Knob::Z1 | Knob::Z2) {
        // Tooth counts are searched one by one inside the range of `Knob::end` (5..=400):
        // an absurd start (a fuzzed z2 = 1.2e9) starts at the range's edge, else the
        // search tried a billion counts (441 s in fmi2ExitInitializationMode).
        let z_max = knob.end(v0, Dir::Up) + 1.0;
        let start = if dir == Dir::Down { v0.min(z_max) } else { v0 };
        let (mut z, last) = (start as i64, end as i64);
        while (z - last) * (s as i64) < 0 {
            z += s as i64;
            if valid(&knob.set(d, z as f64)) {
                return Some(z as f64);
            }
        }
        return None;
    }
    // expanding steps until a valid value, then bisection between the last invalid one
    let span = (end - v0).abs();
    let mut bad = v0;
    let mut step = span * 1e-4;
    let good = loop {
        let v = v0 + s * step.min(span * (1.0 - 1e-9));
        if valid(&knob.set(d, v)) {
            break v;
        }
        bad = v;
        if step >= span {
            return None;
        }
        step *= 2.0;
    };
    let (mut lo, mut hi) = (bad, good);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if valid(&knob.set(d, mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    // round outward to 4 significant digits and confirm
    let mag = 10f64.powi(hi.abs().max(1e-12).log10().floor() as i32 - 3);
    let r = if dir == Dir::Up {
        (hi / mag).ceil() * mag
    } else {
        (hi / mag).floor() * mag
    };
    Some(if valid(&knob.set(d, r)) { r } else { hi })
}

/// Candidates per rule, in the order in which the first working one is named.
fn candidates(rule: Rule, d: &GearData) -> Vec<(Knob, Dir)> {
    use Dir::{Down, Up};
    use Knob::*;
    match rule {
        Rule::Plain => vec![],
        Rule::TipBelowBase1 => vec![(X1, Up), (HaP, Up)],
        Rule::TipBelowBase2 => vec![(X2, Up), (HaP, Up)],
        Rule::WorkingAngle => vec![(X1, Up), (X2, Up)],
        Rule::Interference1 => vec![
            (Z1, Up),
            (X1, Up),
            (X2, Down),
            (X2, Up),
            (HaP, Down),
            (Z2, Down),
        ],
        Rule::Interference2 => vec![
            (Z2, Up),
            (X2, Up),
            (X1, Down),
            (X1, Up),
            (HaP, Down),
            (Z1, Down),
        ],
        Rule::TipsApart => vec![(HaP, Up), (X1, Up), (X2, Up)],
        Rule::ContactRatio => {
            if d.beta == 0.0 {
                vec![(HaP, Up)]
            } else {
                vec![(B, Up), (HaP, Up)]
            }
        }
    }
}

fn fmt_limit(knob: Knob, dir: Dir, v: f64) -> String {
    let op = if dir == Dir::Up { ">=" } else { "<=" };
    match knob {
        Knob::Z1 | Knob::Z2 => format!("{} {op} {}", knob.name(), v as i64),
        _ => format!("{} {op} {}", knob.name(), significant(v)),
    }
}

/// v with 4 significant digits, without binary noise (0.2002, not 0.20020000000000002).
fn significant(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let decimals = (3 - v.abs().log10().floor() as i32).clamp(0, 17) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The error of a refused set with the advice added: the parameter named is the first
/// candidate that repairs the set; the requirement lists every single-parameter repair
/// with its limit, and the candidates that cannot repair it alone.
pub(crate) fn explain(d: &GearData, rule: Rule, e: ParamError) -> ParamError {
    let cands = candidates(rule, d);
    if cands.is_empty() {
        return e;
    }
    let mut fixes: Vec<(Knob, String)> = Vec::new();
    let mut tried: Vec<Knob> = Vec::new();
    for (knob, dir) in cands {
        if !tried.contains(&knob) {
            tried.push(knob);
        }
        if let Some(v) = limit(d, knob, dir) {
            fixes.push((knob, fmt_limit(knob, dir, v)));
        }
    }
    let helpless: Vec<&str> = tried
        .iter()
        .filter(|k| !fixes.iter().any(|(f, _)| f == *k))
        .map(|k| k.name())
        .collect();
    if fixes.is_empty() {
        return ParamError {
            requirement: format!(
                "{}; no single change of {} repairs it: change several gear parameters",
                e.requirement,
                helpless.join(", ")
            ),
            ..e
        };
    }
    // x1 + x2 is one quantity in inv alpha_wt: keep its name, list the shifts' limits
    let (name, value) = if rule == Rule::WorkingAngle {
        (e.name, e.value)
    } else {
        (fixes[0].0.name(), fixes[0].0.get(d))
    };
    let list: Vec<&str> = fixes.iter().map(|(_, s)| s.as_str()).collect();
    let mut req = format!(
        "{}. With the other parameters as given, any one of these repairs it: {}",
        e.requirement,
        list.join(", ")
    );
    if !helpless.is_empty() {
        req.push_str(&format!(" ({} alone cannot)", helpless.join(", ")));
    }
    let context = match rule {
        Rule::Interference1 | Rule::Interference2 => format!(
            " [z1 = {}, z2 = {}, x1 = {}, x2 = {}, h_aP = {}]",
            d.z1, d.z2, d.x1, d.x2, d.ha_coef
        ),
        _ => String::new(),
    };
    req.push_str(&context);
    ParamError {
        name,
        value,
        requirement: req,
    }
}
