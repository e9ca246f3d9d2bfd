//! The friction law seen from the DAE: which local law and which scalar coefficient a
//! state gets (`docs/friction.md`), the lambda column of the Jacobian for law 4, and the
//! consistent lambda of the load-dependent laws 3 and 4 by a scalar solve.

use super::hidden::HiddenConstraint;
use super::{kinematics, GearedRotor};
use crate::gear::friction::BkLine;
use crate::gear::{EhlLine, Friction, FrictionLaw, FrictionSums, LineLaw, Mesh, PitchLine};
use crate::rotor::{idx, ModelError, NY};
use nalgebra::{SMatrix, SVector};

/// Who asks for the friction of a state: decides what the memo keeps (`memo.rs`) and
/// whether law 2's mean coefficient is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Asker {
    /// f and the Jacobian inside the integrator: many states, each once; the memo is read
    /// but not written (writing would cost on every stage for nothing).
    Integrator,
    /// The consistent lambda of a point: kept, since the outputs and the restarting f ask
    /// for the same state.
    Point,
    /// The outputs of a point: kept, and law 2's load-weighted mean coefficient integrated.
    Outputs,
}

/// Laws 1 and 3 creep (`model.md` §4.2) with this regularising speed (m/s, law 2's default
/// v_reg), and stop creeping where the pair rolls faster than it across a transverse base
/// pitch, `|omega1 + omega2| p_bt` (9.2 rpm of the default pair's pinion).
pub const CREEP_SPEED: f64 = 1e-2;

/// They start to creep where the pair rolls slower than this across a base pitch (m/s): the
/// gap to [`CREEP_SPEED`] keeps the vibration of a pair running near either speed from
/// switching the law back and forth (an unlocated switch at one speed stalled spur pairs
/// running steadily within 1 % of it: 50 000 steps in one doStep).
pub const CREEP_ENTRY: f64 = 0.5 * CREEP_SPEED;

impl GearedRotor {
    /// Whether friction laws 1 and 3 are creeping (`model.md` §4.2): their sharp sliding
    /// direction `v/|v|` is then law 2's `v/sqrt(|v|^2 + CREEP_SPEED^2)`. Where nothing
    /// rolls, the sliding of every contact line is the vibration's and its sign flips from
    /// stage to stage under load: the sharp law stalled the stepper (step limit or Newton
    /// failure), a stuck mesh being outside the model (a line sticks only at the pitch line
    /// of a rolling spur pair, §4.1). The simulation switches the mode at located instants
    /// (rolling speed below [`CREEP_ENTRY`] on, above [`CREEP_SPEED`] off).
    pub fn creeps(&self) -> bool {
        self.creep
    }

    /// Whether the friction law can creep (laws 1 and 3: a sharp sliding direction).
    pub fn creep_possible(&self) -> bool {
        self.params.friction_law.sharp_reversal()
    }

    /// Sets the creep mode on both flanks (ignored where the law cannot creep). Entering
    /// it ends a stick phase or a release (no line sticks while the flanks creep). The
    /// state's lambda is then no longer consistent (rigid teeth).
    pub fn set_creep(&mut self, on: bool) {
        let on = on && self.creep_possible();
        if on {
            self.set_stick(false, 0.0);
            self.clear_release();
        }
        self.creep = on;
        if let Some(c) = self.coast.as_mut() {
            c.mirror_mut().creep = on;
        }
    }

    /// The rolling speed across a transverse base pitch at y, `|omega1 + omega2| p_bt`
    /// (m/s): the scale of the sliding speeds along the contact.
    pub fn rolling_speed(&self, y: &SVector<f64, NY>) -> f64 {
        (y[idx::OMEGA1] + y[idx::V + 6]).abs() * self.geom.p_bt
    }

    /// Whether a start (or a periodic orbit) at the drive speed omega1 creeps: laws 1 and 3
    /// with the pair rolling rigidly slower than [`CREEP_ENTRY`] across a base pitch.
    pub fn creeps_at(&self, omega1: f64) -> bool {
        let g = &self.geom;
        let ratio = f64::from(g.data.z1) / f64::from(g.data.z2);
        self.creep_possible() && omega1.abs() * (1.0 + ratio) * g.p_bt < CREEP_ENTRY
    }

    /// The friction sums of the state y at the normal force `lam` and the scalar
    /// coefficient that multiplies them in [`FrictionSums::resultants`]:
    /// law 1 and 2: mu (the sums carry the regularisation for law 2); law 3: mu_mz of
    /// ISO/TR 14179-2 at |lam| and the speeds; laws 4 and 5: 1 (the sums carry mu(s) at the
    /// line load |lam| / l). For [`Asker::Outputs`] also the regularised law's mean coefficient
    /// (law 2's `mu_len`; not needed in f). No allocation.
    ///
    /// # Errors
    /// [`ModelError::NoContact`] when l = 0.
    pub(crate) fn friction(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        lam: f64,
        asker: Asker,
    ) -> Result<(FrictionSums, f64), ModelError> {
        self.friction_mode(t, y, m, lam, asker, self.stick)
    }

    /// [`GearedRotor::friction`] with the stick mode given (`stick`: the line nearest zero
    /// sliding is left out of the sums and described in `FrictionSums::stuck`, for the
    /// laws and pairs where a line can stick; `model.md` §4.1).
    pub(crate) fn friction_mode(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        lam: f64,
        asker: Asker,
        stick: bool,
    ) -> Result<(FrictionSums, f64), ModelError> {
        self.friction_for_load(t, y, m, asker, stick, |_| lam)
            .map(|(s, mu, _)| (s, mu))
    }

    /// [`GearedRotor::friction_mode`] with the normal force a function of the contact
    /// length l (3.12), `load(l)`, evaluated once with the l the friction evaluation has
    /// anyway (the elastic contact, §3.5: Fn = l max(0, c_l delta + d_l delta')): for
    /// laws 1-3 the sums do not depend on the force and carry l; laws 4 and 5 need the
    /// line load |Fn| / l before the sums, so l comes from one contact summary there.
    /// Returns the sums, their scalar coefficient and the force. No allocation.
    ///
    /// # Errors
    /// [`ModelError::NoContact`] when l = 0 (`load` is then not called; else it is called
    /// once).
    #[inline(never)]
    pub(crate) fn friction_for_load(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        asker: Asker,
        stick: bool,
        mut load: impl FnMut(f64) -> f64,
    ) -> Result<(FrictionSums, f64, f64), ModelError> {
        let pitch = self.pitch_line(y, stick);
        let for_outputs = asker == Asker::Outputs;
        let k = kinematics(y);
        let (phi1, psi0) = (y[idx::PHI1], self.params.psi0);
        let g = &self.geom;
        let law = self.params.friction_law;
        // Laws 4 and 5: the force and the load per unit length |lam| / l of the lines in
        // contact, before the sums.
        let (line, lam) = match law {
            FrictionLaw::LocalEhl | FrictionLaw::BenedictKelley => {
                let l = g.contact_summary(m, phi1, psi0).length;
                if !(l > 0.0) {
                    return Err(ModelError::NoContact { t });
                }
                let lam = load(l);
                let line_load = lam.abs() / l;
                let line = if law == FrictionLaw::LocalEhl {
                    LineLaw::Ehl(EhlLine::new(
                        &self.lub,
                        line_load,
                        k.omega1,
                        k.omega2,
                        m.len_t1t2,
                        g.cos_beta_b,
                        g.sin_beta_b,
                    ))
                } else {
                    let fp = &self.params.friction;
                    LineLaw::BenedictKelley(BkLine::new(
                        line_load,
                        fp.eta_oil,
                        fp.ra,
                        fp.v_reg,
                        k.omega1,
                        k.omega2,
                        m.len_t1t2,
                        g.sin_beta_b,
                    ))
                };
                (line, Some(lam))
            }
            FrictionLaw::RegularisedCoulomb => (
                LineLaw::Regularised {
                    v_reg: self.params.friction.v_reg,
                    with_mean: for_outputs,
                },
                None,
            ),
            // (`set_creep` sets the mode for these two laws only.)
            FrictionLaw::Coulomb | FrictionLaw::IsoMean if self.creep => (
                LineLaw::Regularised {
                    v_reg: CREEP_SPEED,
                    with_mean: false,
                },
                None,
            ),
            FrictionLaw::Coulomb | FrictionLaw::IsoMean => (LineLaw::Coulomb, None),
        };
        // m is the mesh of y, so the sums of laws 1-3 are a function of the memo's key;
        // laws 4 and 5 depend on lambda too (the line load): its bits are the variant.
        let variant = match (law, lam) {
            (_, Some(lam)) => lam.to_bits(),
            (law, None) => {
                let pitch_bits = match pitch {
                    PitchLine::Slide => 0,
                    PitchLine::Stick => 1,
                    PitchLine::Released { sign, .. } => 2 + u64::from(sign > 0.0),
                };
                u64::from(for_outputs && law == FrictionLaw::RegularisedCoulomb)
                    | pitch_bits << 1
                    | u64::from(self.creep) << 4
            }
        };
        let keep = asker != Asker::Integrator;
        let s = self.memo.sums(y, variant, keep, || {
            g.sums_with_stick(m, phi1, psi0, &k, &line, pitch)
        });
        if !(s.contact.length > 0.0) {
            return Err(ModelError::NoContact { t });
        }
        // Laws 1-3: the force from the sums' l; law 3's coefficient at that force.
        let (lam, mu) = match lam {
            Some(lam) => (lam, 1.0),
            None => {
                let lam = load(s.contact.length);
                let mu = match law {
                    FrictionLaw::IsoMean => self.iso.mu(lam, k.omega1, k.omega2),
                    _ => self.params.mu,
                };
                (lam, mu)
            }
        };
        Ok((s, mu, lam))
    }

    /// Load-weighted mean coefficient `1/l int mu_loc ds` of sums from
    /// [`GearedRotor::friction`] (asked by [`Asker::Outputs`]) and their scalar coefficient.
    pub(super) fn mean_coefficient(&self, sums: &FrictionSums, mu: f64) -> f64 {
        match self.params.friction_law {
            FrictionLaw::Coulomb | FrictionLaw::IsoMean => mu,
            _ => mu * sums.mu_len / sums.contact.length,
        }
    }

    /// Law 4: d(friction terms of f)/d(lambda) by a one-sided difference of the friction
    /// evaluation (mu(s) depends on the line load through the Hertzian pressure), added
    /// to the lambda column (rows of v, E_in, E_loss).
    pub(super) fn friction_lambda_column(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        fr: &Friction,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> Result<(), ModelError> {
        let (v, lam_i) = (idx::V, idx::LAMBDA);
        let lam = y[lam_i];
        let lp = lam + f64::EPSILON.sqrt() * lam.abs().max(1.0);
        let h = lp - lam;
        let (sp, mup) = self.friction(t, y, m, lp, Asker::Integrator)?;
        let frp = sp.resultants(mup, lp);
        let base = fr.generalised();
        let pert = frp.generalised();
        for i in 0..7 {
            jac[(v + i, lam_i)] += (pert[i] - base[i]) / h;
        }
        jac[(idx::E_IN, lam_i)] += -(frp.m1.z - fr.m1.z) / h * y[idx::OMEGA1];
        jac[(idx::E_LOSS, lam_i)] = (frp.p_loss - fr.p_loss) / h;
        Ok(())
    }

    /// Consistent lambda for the load-dependent laws 3 and 4: the hidden
    /// constraint reads `h(lambda) = lambda A + G M^-1 Q_f(lambda) - r = 0` with A, r as
    /// in [`GearedRotor::consistent_lambda`]; Q_f uses |lambda| itself, so any root is
    /// consistent (no sign assumption). Secant iteration until the step is below 2 eps |lambda|
    /// (the residual is then at round-off). It starts from the lambda of y when that has
    /// the sign of r (at a communication point the integrator's lambda is already within
    /// ~rtol of the root: typically 3 friction evaluations instead of 4-6 from the
    /// frictionless `r / A`), else from `r / A`; the second point is the
    /// friction-linearised correction of the first. `at_y`: the friction of y at its own
    /// lambda when the caller has it (the first evaluation is then free).
    ///
    /// Returns lambda and the friction evaluated at it (the last iterate, within about
    /// 2 eps |lambda| of the root), so that outputs at the consistent state need no further
    /// evaluation.
    ///
    /// # Errors
    /// Mesh/contact errors; [`ModelError::InconsistentLambda`] when the iteration does
    /// not converge (friction so strong that h is not monotone, Painlevé-type).
    pub(super) fn consistent_lambda_solve(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        at_y: Option<(FrictionSums, f64)>,
        stick: bool,
    ) -> Result<(f64, (FrictionSums, f64)), ModelError> {
        let stuck = match &at_y {
            _ if !(stick && self.stick_possible()) => None,
            Some((s, _)) => s.stuck,
            None => {
                self.friction_mode(t, y, m, y[idx::LAMBDA], Asker::Point, stick)?
                    .0
                    .stuck
            }
        };
        let HiddenConstraint { gp, a, r } = self.hidden_constraint(t, y, m, stuck.as_ref());
        // h(lambda), its friction part phi(lambda) = G M^-1 Q_f(lambda), and the friction
        // evaluated for it.
        type Eval = (f64, f64, (FrictionSums, f64));
        let residual = |lam: f64, fr: (FrictionSums, f64)| -> Eval {
            let q = fr.0.resultants(fr.1, lam);
            let q = q.generalised();
            let mut phi = 0.0;
            for i in 0..7 {
                phi += gp[i] * q[i] / self.mass[i];
            }
            (lam * a + phi - r, phi, fr)
        };
        let h = |lam: f64| -> Result<Eval, ModelError> {
            Ok(residual(
                lam,
                self.friction_mode(t, y, m, lam, Asker::Point, stick)?,
            ))
        };
        let lam_y = y[idx::LAMBDA];
        if r == 0.0 {
            return Ok((0.0, self.friction_mode(t, y, m, 0.0, Asker::Point, stick)?));
        }
        let from_y = lam_y.is_finite() && lam_y * r > 0.0;
        let mut l0 = if from_y { lam_y } else { r / a };
        let (mut h0, phi0, first) = match at_y {
            Some(fr) if from_y => residual(l0, fr),
            _ => h(l0)?,
        };
        if h0 == 0.0 {
            return Ok((l0, first));
        }
        // Friction as an effective slope phi(l0)/l0 (phi from the evaluation, not from
        // h0 + r - l0 A, which cancels when l0 is far from the root).
        let mut l1 = r / (a + phi0 / l0);
        for _ in 0..60 {
            if !l1.is_finite() {
                // the effective slope cancels A: friction this strong is not resolved here
                break;
            }
            let (h1, _, e1) = h(l1)?;
            if h1 == 0.0 {
                return Ok((l1, e1));
            }
            let slope = (h1 - h0) / (l1 - l0);
            if !(slope.is_finite() && slope != 0.0) {
                // h flat to round-off between two iterates that already agree.
                if (l1 - l0).abs() <= 1e-12 * l1.abs() {
                    return Ok((l1, e1));
                }
                break;
            }
            let l2 = l1 - h1 / slope;
            if !l2.is_finite() {
                break;
            }
            if (l2 - l1).abs() <= 2.0 * f64::EPSILON * l2.abs() {
                // l1 is within about 2 eps |l1| of the root, and its friction is at hand.
                return Ok((l1, e1));
            }
            (l0, h0) = (l1, h1);
            l1 = l2;
        }
        Err(ModelError::InconsistentLambda {
            t,
            lambda_pos: l1,
            lambda_neg: l0,
        })
    }
}
