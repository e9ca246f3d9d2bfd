//! The coast flanks and the backlash of the elastic contact (`tooth_contact = elastic`,
//! docs/model.md §3.6): load reversal from the drive to the coast flank through the play,
//! rattle on both flanks with located impacts, the energy balance with both flanks.

use geared_rotor::gear::inv;
use geared_rotor::rotor::{FrictionLaw, Outputs, Params, ToothContact};
use geared_rotor::sim::contact_events::{ContactEvent, Flank};
use geared_rotor::sim::{Initialization, Input, OnViolation, Simulation, SolverSettings};
use std::f64::consts::PI;

const OMEGA1: f64 = 314.159;

fn elastic(p: Params) -> Params {
    Params {
        tooth_contact: ToothContact::Elastic,
        ..p
    }
}

/// A simulation from the static equilibrium that would stop (Discard) at any validity
/// violation: the elastic contact must never raise one.
fn sim(p: Params, rtol: f64, omega1: f64, t_load: f64) -> Simulation {
    let s = SolverSettings { rtol, h_max: 1e-4 };
    let init = Initialization::StaticEquilibrium;
    let mut s = Simulation::with_initialization(p, s, 0.0, omega1, t_load, init).unwrap();
    s.set_on_violation(OnViolation::Discard);
    s
}

/// The energy balance of docs/model.md (3.21) over a run: the largest |supplied - used|
/// since the start, over the largest energy it compares (|E_in| or E_kin, whichever is
/// larger: in a rattle run E_kin ~ 170 J dwarfs the net E_in).
#[derive(Default)]
struct Balance {
    worst: f64,
    scale: f64,
}

impl Balance {
    fn add(&mut self, o: &Outputs, o0: &Outputs) {
        let supplied = o.e_in + (o.w_mesh_stiffness - o0.w_mesh_stiffness);
        let used = o.e_load + (o.e_kin - o0.e_kin) + (o.e_pot - o0.e_pot) + o.e_loss + o.e_damp;
        self.worst = self.worst.max((supplied - used).abs());
        self.scale = self.scale.max(o.e_in.abs()).max(o.e_kin);
    }
    fn relative(&self) -> f64 {
        self.worst / self.scale
    }
}

/// T_load +100 -> -100 N m (ramp 20..25 ms), d_phi small enough that the load wins:
/// drive flank -> free flight -> coast flank, no Discard and no warning; at the end the
/// coast force balances the load and the drive gap is the play (3.24) plus the coast
/// flanks' static approach.
#[test]
fn reversal_moves_through_the_play_to_the_coast_flank() {
    for law in [FrictionLaw::Coulomb, FrictionLaw::LocalEhl] {
        // Law 1 without friction: the torque balance of gear 2 is exact.
        let mu = if law == FrictionLaw::Coulomb {
            0.0
        } else {
            0.05
        };
        let d_phi = 0.05;
        let p = elastic(Params {
            d_phi,
            mu,
            friction_law: law,
            ..Params::default()
        });
        let g = p.validate().unwrap();
        // The energy quadratures are controlled relative to their own size (E_in ~ 500 J
        // here): rtol 1e-7 gives 4.1e-10 / 3.5e-10 of E_in (laws 1 / 4). Before the Newton
        // rate was reset at input changes (stepping.rs), one free-flight step after a new
        // T_load left 3.4e-4 J: 1.4e-6 of E_in at rtol 1e-8, and this test needed 1e-10.
        let mut s = sim(p, 1e-7, OMEGA1, 100.0);
        let o0 = s.outputs();
        let h = 1e-4;
        let (mut states, mut events) = (Vec::new(), Vec::new());
        let mut bal = Balance::default();
        let mut tail = Vec::new();
        for k in 0..600 {
            let t = k as f64 * h;
            let tl = if t < 0.02 {
                100.0
            } else if t < 0.025 {
                100.0 - 200.0 * (t - 0.02) / 0.005
            } else {
                -100.0
            };
            s.set_input(Input::TLoad, tl).unwrap();
            let rep = s.do_step(t, h).unwrap();
            events.extend(rep.contact_events.iter().flatten().copied());
            assert!(rep.violations.iter().all(Option::is_none));
            let o = s.outputs();
            if states.last() != Some(&o.mesh_state) {
                states.push(o.mesh_state);
            }
            bal.add(&o, &o0);
            assert!(o.fn_ >= 0.0 && o.fn_coast >= 0.0);
            assert!(o.mesh_state != 1 || o.fn_coast == 0.0);
            if k >= 500 {
                tail.push(o);
            }
        }
        let n = tail.len() as f64;
        let fc = tail.iter().map(|o| o.fn_coast).sum::<f64>() / n;
        let omega2 = tail.iter().map(|o| o.omega2).sum::<f64>() / n;
        // Gear 2 at constant speed: the coast force's torque carries the reversed load
        // less the damper's torque.
        let fc_static = (100.0 - d_phi * omega2) / (g.rb2 * g.cos_beta_b);
        let o = tail.last().unwrap();
        // The drive gap at the end from the centre positions (independent of the model's
        // mesh code): play j_bn / cos(beta_b) + 2 R (inv alpha - inv alpha_wt) plus the
        // coast flanks' static approach F_c / (k_c cos(beta_b)).
        let dx = g.a_w + o.u2[0] - o.u1[0];
        let dy = o.u2[1] - o.u1[1];
        let alpha = (g.r_sum / dx.hypot(dy)).acos();
        let play = p.gear.j_bn / g.cos_beta_b + 2.0 * g.r_sum * (inv(alpha) - inv(g.alpha_wt));
        let gap_expected = play + o.fn_coast / (o.mesh_stiffness * g.cos_beta_b);
        println!(
            "{law:?}: mesh states {states:?}, events {:?}; mean Fn_coast {fc:.3} N vs static \
             {fc_static:.3} N; drive gap {:.5e} m vs play + approach {gap_expected:.5e} m \
             (play {play:.5e} m); TE {:.4e} -> {:.4e} m; energy balance {:.2e}; {}",
            events
                .iter()
                .map(|e: &ContactEvent| (e.flank, e.onset))
                .collect::<Vec<_>>(),
            o.gap,
            o0.te,
            o.te,
            bal.relative(),
            s.stats()
        );
        assert_eq!(states, vec![1, 0, -1], "{law:?}");
        assert_eq!(
            (
                events[0].flank,
                events[0].onset,
                events[1].flank,
                events[1].onset
            ),
            (Flank::Drive, false, Flank::Coast, true)
        );
        assert_eq!(
            o.impacts as usize,
            events.iter().filter(|e| e.onset).count()
        );
        // Friction (law 4) adds its moment about gear 2's axis.
        let tol = if mu == 0.0 { 1e-3 } else { 0.01 };
        assert!(
            (fc - fc_static).abs() < tol * fc_static,
            "{law:?}: {fc} vs {fc_static}"
        );
        assert!((o.gap - gap_expected).abs() < 1e-3 * play, "{law:?}");
        assert!(bal.relative() < 1e-8, "{law:?}: {:e}", bal.relative());
    }
}

/// Rattle: no load torque, a small damper (d_phi 0.01), omega1 +-5 % at 30 Hz: the teeth
/// fly through the play and hit both flanks; every onset is a located event, the impact
/// count is the number of onsets, and the energy balance holds (laws 1 and 4).
#[test]
fn rattle_hits_both_flanks_with_located_impacts() {
    for law in [FrictionLaw::Coulomb, FrictionLaw::LocalEhl] {
        let p = elastic(Params {
            d_phi: 0.01,
            friction_law: law,
            ..Params::default()
        });
        let omega1 = |t: f64| OMEGA1 * (1.0 + 0.05 * (2.0 * PI * 30.0 * t).sin());
        let mut s = sim(p, 1e-10, OMEGA1, 0.0);
        let o0 = s.outputs();
        let h = 1e-4;
        let mut bal = Balance::default();
        let mut events = Vec::new();
        let mut seen = [false; 3];
        let cpu = std::time::Instant::now();
        let n = 1000;
        for k in 0..n {
            let t = k as f64 * h;
            s.set_input(Input::Omega1, omega1(t)).unwrap();
            let rep = s.do_step(t, h).unwrap();
            events.extend(rep.contact_events.iter().flatten().copied());
            assert_eq!(rep.contact_events_dropped, 0);
            let o = s.outputs();
            seen[(o.mesh_state + 1) as usize] = true;
            assert!(o.fn_ >= 0.0 && o.fn_coast >= 0.0);
            bal.add(&o, &o0);
        }
        let cpu = cpu.elapsed().as_secs_f64();
        let o = s.outputs();
        let onsets: Vec<&ContactEvent> = events.iter().filter(|e| e.onset).collect();
        let coast = onsets.iter().filter(|e| e.flank == Flank::Coast).count();
        let drive = onsets.len() - coast;
        println!(
            "{law:?} rattle 0.1 s: {} impacts ({drive} drive, {coast} coast), {:.0} per \
             second; energy balance {:.2e} of {:.1} J; CPU {cpu:.2} s at rtol 1e-10; {}",
            o.impacts,
            onsets.len() as f64 / (n as f64 * h),
            bal.relative(),
            bal.scale,
            s.stats()
        );
        assert!(
            seen.iter().all(|&x| x),
            "{law:?}: mesh states seen {seen:?}"
        );
        assert!(
            drive > 0 && coast > 0,
            "{law:?}: {drive} drive, {coast} coast"
        );
        assert_eq!(o.impacts as usize, onsets.len());
        assert!(bal.relative() < 1e-8, "{law:?}: {:e}", bal.relative());
        // Every onset located to 1e-10 s: a second run stepped to 1e-10 s before and after
        // the first onsets sees the force function negative before and positive after.
        for e in onsets.iter().take(4) {
            let k = usize::from(e.flank == Flank::Coast);
            let mut sides = [0.0; 2];
            for (j, dt) in [-1e-10, 1e-10].into_iter().enumerate() {
                let mut r = sim(p, 1e-10, OMEGA1, 0.0);
                let te = e.t + dt;
                let mut t = 0.0;
                while t < te - 1e-15 {
                    let step = h.min(te - t);
                    r.set_input(Input::Omega1, omega1((t / h).round() * h))
                        .unwrap();
                    r.do_step(t, step).unwrap();
                    t += step;
                }
                sides[j] = r.model().flank_event_functions(r.time(), r.y()).unwrap()[k];
            }
            println!(
                "onset {e:?}: force function {:.3e} / {:.3e} m",
                sides[0], sides[1]
            );
            assert!(sides[0] <= 0.0 && sides[1] > 0.0, "{e:?}: {sides:?}");
        }
    }
}

/// Reversal in the real-time mode (h_fixed = 1e-5 s): the fixed steps cross the onset
/// (no retake: the work per doStep stays bounded), the crossing is still located on the
/// step's polynomial and counted; the coast onset lies within one fixed step of the
/// adaptive run's and the end state agrees.
#[test]
fn real_time_mode_crosses_and_reports_the_coast_onset() {
    let p = elastic(Params {
        d_phi: 0.05,
        mu: 0.0,
        ..Params::default()
    });
    let h_fixed = 1e-5;
    let run = |fixed: bool| {
        let mut s = sim(p, 1e-8, OMEGA1, 100.0);
        if fixed {
            s.set_h_fixed(h_fixed).unwrap();
        }
        let mut events = Vec::new();
        let h = 1e-4;
        for k in 0..400 {
            let t = k as f64 * h;
            let tl = if t < 0.02 {
                100.0
            } else {
                (100.0 - 200.0 * (t - 0.02) / 0.005).max(-100.0)
            };
            s.set_input(Input::TLoad, tl).unwrap();
            let rep = s.do_step(t, h).unwrap();
            events.extend(rep.contact_events.iter().flatten().copied());
        }
        (events, s.outputs())
    };
    let (ea, oa) = run(false);
    let (ef, of) = run(true);
    let onset = |e: &[ContactEvent]| {
        e.iter()
            .find(|e| e.flank == Flank::Coast && e.onset)
            .map(|e| e.t)
            .unwrap()
    };
    let (ta, tf) = (onset(&ea), onset(&ef));
    println!(
        "coast onset adaptive {ta:.9} s, real-time {tf:.9} s ({:.2} fixed steps); impacts \
         {} / {}; Fn_coast at 40 ms {:.2} / {:.2} N",
        (tf - ta) / h_fixed,
        oa.impacts,
        of.impacts,
        oa.fn_coast,
        of.fn_coast
    );
    assert!((tf - ta).abs() < h_fixed);
    assert!(of.impacts >= 1 && of.mesh_state == -1);
    assert!((of.fn_coast - oa.fn_coast).abs() < 0.02 * oa.fn_coast);
}

/// A snapshot taken in coast contact after impacts continues bit-identically, impact
/// count included (FMU state layout 7).
#[test]
fn snapshot_keeps_the_impact_count() {
    let p = elastic(Params {
        d_phi: 0.01,
        ..Params::default()
    });
    let mut s = sim(p, 1e-6, OMEGA1, 0.0);
    let h = 1e-4;
    let omega1 = |t: f64| OMEGA1 * (1.0 + 0.05 * (2.0 * PI * 30.0 * t).sin());
    let mut k = 0;
    while s.impacts() < 3 {
        let t = k as f64 * h;
        s.set_input(Input::Omega1, omega1(t)).unwrap();
        s.do_step(t, h).unwrap();
        k += 1;
        assert!(k < 1000);
    }
    // Through the serialised bytes, as fmi2SerializeFMUstate writes them.
    let mut w = geared_rotor::bytes::Writer::default();
    s.state().write(&mut w);
    let mut rd = geared_rotor::bytes::Reader::new(&w.buf);
    let snap = geared_rotor::sim::SimState::read(&mut rd).unwrap();
    rd.finish().unwrap();
    let mut r = Simulation::from_state(&snap).unwrap();
    assert_eq!(r.impacts(), s.impacts());
    for j in k..k + 200 {
        let t = j as f64 * h;
        for x in [&mut s, &mut r] {
            x.set_input(Input::Omega1, omega1(t)).unwrap();
            x.do_step(t, h).unwrap();
        }
        let (a, b) = (s.outputs(), r.outputs());
        assert_eq!(a.impacts, b.impacts);
        assert_eq!(a.fn_coast.to_bits(), b.fn_coast.to_bits());
        assert_eq!(a.fn_.to_bits(), b.fn_.to_bits());
    }
    println!(
        "restored at {} impacts; {} after 200 more steps",
        3,
        s.impacts()
    );
    assert!(s.impacts() > 3);
}

/// Free flight far from the nominal centre distance: with the centres pulled 2.5 mm apart a
/// spur pair's contact ratio falls below 1, so at some phases no drive line is active; the
/// flanks are apart there (no force), and f and the outputs are still defined (the friction
/// needs no contact line without a force).
#[test]
fn free_flight_needs_no_active_contact_line() {
    use geared_rotor::gear::GearData;
    use geared_rotor::rotor::{idx, GearedRotor, Inputs, NY};
    use nalgebra::SVector;
    let p = elastic(Params {
        gear: GearData {
            beta: 0.0,
            ..GearData::default()
        },
        ..Params::default()
    });
    let mut m = GearedRotor::new(p).unwrap();
    m.set_inputs(Inputs {
        omega1: OMEGA1,
        ..Inputs::default()
    });
    let y0 = m.initialize(0.0).unwrap();
    let g = *m.geometry();
    let mut found = 0;
    for i in 0..200 {
        let mut y = y0;
        y[3] = 2.5e-3;
        y[idx::PHI1] = g.phi1_period * i as f64 / 200.0;
        let e = m.elastic_contact_at(0.0, &y).unwrap();
        if e.length > 0.0 {
            continue;
        }
        found += 1;
        assert!(e.delta < 0.0 && e.fn_ == 0.0);
        let mut f = SVector::<f64, NY>::zeros();
        m.rhs(0.0, &y, &mut f).unwrap();
        let o = m.outputs(0.0, &y);
        assert!(o.t1.is_finite() && o.p_loss == 0.0 && o.contact_length == 0.0);
        assert!(o.f_contact2.iter().all(|x| x.is_finite()));
    }
    println!("{found} of 200 phases without an active drive line");
    assert!(found > 0);
}

/// A start with a reversed load (T_load -500 N m) from the static equilibrium: the coast
/// flanks carry it from t = 0 - the bearings are deflected along the coast force's line
/// (accelerations of the centres zero at the start), the stored spring work is the coast
/// spring's energy (W_mesh_stiffness 0), and the coast force stays near its static value
/// (within the ripple of the time-varying stiffness, as a loaded drive flank does).
#[test]
fn reversed_load_starts_static_on_the_coast_flanks() {
    use geared_rotor::rotor::{idx, NY};
    use nalgebra::SVector;
    let (t_load, d_phi) = (-500.0, 0.05);
    let p = elastic(Params {
        d_phi,
        mu: 0.0,
        ..Params::default()
    });
    let g = p.validate().unwrap();
    let mut s = sim(p, 1e-8, OMEGA1, t_load);
    let o0 = s.outputs();
    let mut f = SVector::<f64, NY>::zeros();
    let mut m = s.model().clone();
    m.rhs(0.0, s.y(), &mut f).unwrap();
    let acc = (0..6).map(|i| f[idx::V + i].abs()).fold(0.0, f64::max);
    let omega2 = OMEGA1 * g.rb1 / g.rb2;
    let fc_static = (-t_load - d_phi * omega2) / (g.rb2 * g.cos_beta_b);
    println!(
        "reversed start: mesh_state {}, Fn_coast {:.2} N (static {fc_static:.2} N), largest \
         force on a bearing coordinate {acc:.3e} N, W_mesh_stiffness {:.3e} J",
        o0.mesh_state, o0.fn_coast, o0.w_mesh_stiffness
    );
    assert_eq!(o0.mesh_state, -1);
    assert!((o0.fn_coast - fc_static).abs() < 1e-9 * fc_static);
    assert!(acc < 1e-6 * fc_static, "{acc}");
    assert!(o0.w_mesh_stiffness.abs() < 1e-12);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for k in 0..50 {
        s.do_step(k as f64 * 1e-4, 1e-4).unwrap();
        let o = s.outputs();
        assert_eq!(o.mesh_state, -1);
        lo = lo.min(o.fn_coast);
        hi = hi.max(o.fn_coast);
    }
    println!("Fn_coast over 5 ms: {lo:.1} .. {hi:.1} N");
    assert!(hi - lo < 0.06 * fc_static, "{lo} {hi}");
}

/// A tuned mu reaches the coast flanks: f in coast contact after set_mu(0.2) on a model
/// built with mu 0.02 equals f of a model built with 0.2 (laws 1 and 2).
#[test]
fn tuned_mu_reaches_the_coast_flanks() {
    use geared_rotor::rotor::{GearedRotor, Inputs, NY};
    use nalgebra::SVector;
    for law in [FrictionLaw::Coulomb, FrictionLaw::RegularisedCoulomb] {
        let build = |mu: f64| {
            let p = elastic(Params {
                mu,
                friction_law: law,
                ..Params::default()
            });
            let mut m = GearedRotor::new(p).unwrap();
            m.set_inputs(Inputs {
                omega1: OMEGA1,
                t_load: -300.0,
                ..Inputs::default()
            });
            m
        };
        let mut a = build(0.02);
        let mut b = build(0.2);
        let y = b.initialize(0.0).unwrap();
        let _ = a.initialize(0.0).unwrap();
        a.set_mu(0.2).unwrap();
        assert!(b.coast_contact_at(0.0, &y).unwrap().fn_ > 0.0);
        let (mut fa, mut fb) = (SVector::<f64, NY>::zeros(), SVector::<f64, NY>::zeros());
        a.rhs(0.0, &y, &mut fa).unwrap();
        b.rhs(0.0, &y, &mut fb).unwrap();
        assert_eq!(fa, fb, "{law:?}");
    }
}

/// The impacts do not depend on the communication step: load steps +100 -> -100 -> +100 ->
/// -100 N m at 20, 30 and 40 ms, run with H from 0.1 to 10 ms (look-ahead past the
/// communication points, retakes to them): the same impact count, and where a doStep lists
/// them all (at most 8 per interval: H <= 1 ms) the same onsets and separations at the same
/// instants to 1e-8 s (the trajectories of different step sequences differ by the
/// integration error of rtol 1e-8: 1.2e-9 s here).
#[test]
fn impacts_do_not_depend_on_the_communication_step() {
    let p = elastic(Params {
        d_phi: 0.05,
        ..Params::default()
    });
    let load = |t: f64| match t {
        t if t < 0.02 => 100.0,
        t if t < 0.03 => -100.0,
        t if t < 0.04 => 100.0,
        _ => -100.0,
    };
    let mut runs = Vec::new();
    for h in [1e-4, 2.5e-4, 1e-3, 5e-3, 1e-2] {
        let mut s = sim(p, 1e-8, OMEGA1, 100.0);
        let n = (0.06f64 / h).round() as usize;
        let (mut events, mut dropped) = (Vec::new(), 0);
        for k in 0..n {
            let t = k as f64 * h;
            s.set_input(Input::TLoad, load(t + 1e-12)).unwrap();
            let rep = s.do_step(t, h).unwrap();
            dropped += rep.contact_events_dropped;
            events.extend(rep.contact_events.iter().flatten().copied());
        }
        println!(
            "H {h}: {} events listed, {dropped} more counted, impacts {}",
            events.len(),
            s.impacts()
        );
        if dropped == 0 {
            assert_eq!(
                s.impacts() as usize,
                events.iter().filter(|e| e.onset).count()
            );
        }
        runs.push((s.impacts(), dropped, events));
    }
    assert!(
        runs.iter().all(|r| r.0 == runs[0].0),
        "impact counts differ"
    );
    let listed: Vec<_> = runs.iter().filter(|r| r.1 == 0).map(|r| &r.2).collect();
    assert!(listed.len() >= 3);
    for r in &listed[1..] {
        assert_eq!(r.len(), listed[0].len());
        for (a, b) in r.iter().zip(listed[0]) {
            assert_eq!((a.flank, a.onset), (b.flank, b.onset));
            assert!((a.t - b.t).abs() < 1e-8, "{a:?} vs {b:?}");
        }
    }
}

/// Outside the elastic model: a spur pair without backlash, brought onto its large orbit
/// at 6500 rpm and slowed to 6000 rpm after 50 ms, is parametrically unstable (docs/
/// dynamic_factor.md) and its vibration grows until the flanks overlap by more than m_n / 20;
/// that is reported once as a tooth overload at a located instant, and with `discard` the
/// step stops at that instant, where the overlap is the limit. The loaded and reversal runs
/// above never report one.
#[test]
fn tooth_overload_is_reported_where_the_model_leaves_its_validity() {
    use geared_rotor::gear::GearData;
    use geared_rotor::sim::{SimError, ViolationKind};
    let p = elastic(Params {
        d_phi: 0.0,
        mu: 0.0,
        gear: GearData {
            beta: 0.0,
            j_bn: 0.0,
            ..GearData::default()
        },
        ..Params::default()
    });
    let rpm = |n: f64| n * PI / 30.0;
    let limit = 0.05 * p.gear.m_n;
    let h = 1e-4;
    let speed = |k: usize| if k < 500 { rpm(6500.0) } else { rpm(6000.0) };
    // Warn: the run goes on, one report.
    let mut s = sim(p, 1e-8, rpm(6500.0), 100.0);
    s.set_on_violation(OnViolation::Warn);
    let mut seen = Vec::new();
    let mut end = 3000;
    for k in 0..3000 {
        s.set_input(Input::Omega1, speed(k)).unwrap();
        let rep = s.do_step(k as f64 * h, h).unwrap();
        seen.extend(rep.violations.iter().flatten().copied());
        if seen.len() == 1 && end == 3000 {
            end = k + 100;
        }
        if k >= end {
            break;
        }
    }
    assert_eq!(seen.len(), 1, "{seen:?}");
    let v = seen[0];
    assert_eq!(v.kind, ViolationKind::ToothOverload);
    println!("{v}");
    // Discard: the FMU time stops at the located instant, where the overlap is the limit.
    let mut s = sim(p, 1e-8, rpm(6500.0), 100.0);
    let mut stopped = None;
    for k in 0..3000 {
        s.set_input(Input::Omega1, speed(k)).unwrap();
        match s.do_step(k as f64 * h, h) {
            Ok(_) => {}
            Err(SimError::Validity(v)) => {
                stopped = Some(v);
                break;
            }
            Err(e) => panic!("{e:?}"),
        }
    }
    let v = stopped.expect("a Discard");
    let o = s.outputs();
    // The overlap of the drive flanks (delta) or of the coast flanks (-delta less the
    // play, j_bn = 0 here; the centres hardly move against the overlap).
    let overlap = o.mesh_deflection.abs();
    println!(
        "stopped at t = {:.9} s (warn run: {:.9} s); |delta| there {overlap:.6e} m, limit {limit:.1e} m",
        s.time(),
        seen[0].t
    );
    assert_eq!(s.time(), v.t);
    assert!((v.t - seen[0].t).abs() < 1e-9);
    assert!((overlap - limit).abs() < 0.02 * limit, "{overlap}");
}

/// E_mesh_damp (the mesh damping's energy, its own quadrature) is the part of E_damp the
/// dampers do not take: E_damp - E_mesh_damp equals the integral of the dampers' power
/// P_damp (bearings and d_phi), integrated here by the trapezoidal rule on 10 us samples
/// of the output, and the energy balance holds with E_damp; E_mesh_damp never falls (its
/// power is >= 0) and is 0 with rigid teeth.
#[test]
fn mesh_damping_energy_is_the_rest_of_e_damp() {
    for (contact, omega1_amp) in [(ToothContact::Elastic, 0.05), (ToothContact::Rigid, 0.0)] {
        let p = Params {
            tooth_contact: contact,
            d_phi: 0.01,
            ..Params::default()
        };
        let t_load = if contact == ToothContact::Rigid {
            50.0
        } else {
            0.0
        };
        let mut s = sim(p, 1e-10, OMEGA1, t_load);
        let h = 1e-5;
        let o0 = s.outputs();
        let mut o_prev = o0;
        let mut integral = 0.0;
        let mut worst = 0.0f64;
        // With the balance (3.21), which holds only if E_mesh_damp takes exactly the mesh
        // damping's dissipation, this pins E_mesh_damp (the first check alone reads only
        // the dampers' slot).
        let mut bal = Balance::default();
        for k in 0..3000 {
            let t = k as f64 * h;
            let w = OMEGA1 * (1.0 + omega1_amp * (2.0 * PI * 30.0 * t).sin());
            s.set_input(Input::Omega1, w).unwrap();
            s.do_step(t, h).unwrap();
            let o = s.outputs();
            integral += 0.5 * h * (o.p_damp + o_prev.p_damp);
            assert!(
                o.e_mesh_damp >= o_prev.e_mesh_damp - 1e-9 * o.e_damp.max(1e-3),
                "{} -> {}",
                o_prev.e_mesh_damp,
                o.e_mesh_damp
            );
            worst = worst.max((o.e_damp - o.e_mesh_damp - integral).abs() / integral.max(1e-9));
            bal.add(&o, &o0);
            o_prev = o;
        }
        println!(
            "{contact:?}: 30 ms, E_damp {:.6e} J, E_mesh_damp {:.6e} J, integral of P_damp \
             {integral:.6e} J; worst |E_damp - E_mesh_damp - int P_damp| / int {worst:.2e}",
            o_prev.e_damp, o_prev.e_mesh_damp
        );
        assert!(worst < 2e-4, "{contact:?}: {worst:e}");
        println!("energy balance {:.2e}", bal.relative());
        assert!(bal.relative() < 1e-8, "{contact:?}: {:e}", bal.relative());
        if contact == ToothContact::Rigid {
            assert_eq!(o_prev.e_mesh_damp, 0.0);
        } else {
            assert!(o_prev.e_mesh_damp > 1e-3);
        }
    }
}

/// Real-time mode with elastic teeth from rest under load (the closed-loop bench's `rt`
/// case): the mesh mode's start transient needs more than the 3 fixed Newton iterations in
/// the first steps; the one retry of a failed step (new Jacobian, 7 iterations) carries it
/// at h_fixed = 2.5e-5 and 5e-5 s, and the run stays close to the adaptive one.
#[test]
fn real_time_mode_starts_the_elastic_contact_from_rest() {
    let p = elastic(Params::default());
    for h_fixed in [2.5e-5, 5e-5] {
        let run = |fixed: bool| {
            let s = SolverSettings {
                rtol: 1e-6,
                h_max: 1e-4,
            };
            let mut s =
                Simulation::with_initialization(p, s, 0.0, OMEGA1, 50.0, Initialization::Rest)
                    .unwrap();
            if fixed {
                s.set_h_fixed(h_fixed).unwrap();
            }
            let h = 1e-4;
            for k in 0..200 {
                let t = k as f64 * h;
                let w = OMEGA1 * (1.0 + 0.01 * (2.0 * PI * 30.0 * t).sin());
                s.set_input(Input::Omega1, w).unwrap();
                s.do_step(t, h).unwrap();
            }
            s.outputs()
        };
        let (a, f) = (run(false), run(true));
        println!(
            "h_fixed {h_fixed:e}: T1 {:.4} / {:.4} N m, Fn {:.2} / {:.2} N at 20 ms",
            f.t1, a.t1, f.fn_, a.fn_
        );
        assert!((f.fn_ - a.fn_).abs() < 0.02 * a.fn_);
    }
}

/// An overload that holds at the start state (static equilibrium under 6000 N m: a
/// deflection of some 6e-4 m, six times the limit) is reported by the first doStep, once,
/// at the start time; with `discard` that doStep returns the violation at t = 0.
#[test]
fn overload_at_the_start_state_is_reported_by_the_first_do_step() {
    use geared_rotor::sim::{SimError, ViolationKind};
    let p = elastic(Params::default());
    let w = 1000.0 * PI / 30.0;
    let mut s = sim(p, 1e-6, w, 6000.0);
    s.set_on_violation(OnViolation::Warn);
    let mut seen = Vec::new();
    for k in 0..20 {
        let rep = s.do_step(k as f64 * 1e-4, 1e-4).unwrap();
        seen.extend(rep.violations.iter().flatten().copied());
    }
    println!("{seen:?}");
    assert_eq!(seen.len(), 1);
    assert_eq!(
        (seen[0].kind, seen[0].t),
        (ViolationKind::ToothOverload, 0.0)
    );
    assert!(seen[0].value > 5.0 * 0.05 * p.gear.m_n);
    let mut s = sim(p, 1e-6, w, 6000.0);
    match s.do_step(0.0, 1e-4) {
        Err(SimError::Validity(v)) => {
            assert_eq!((v.kind, v.t), (ViolationKind::ToothOverload, 0.0))
        }
        r => panic!("{r:?}"),
    }
}
