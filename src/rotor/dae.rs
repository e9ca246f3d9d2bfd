//! f(t, y), mass matrix, Jacobian, consistent initial values and outputs of the DAE
//! (`model.md` §5-§8).

use super::params::{check_d_phi, check_mu};
use super::{idx, FrictionLaw, Inputs, LastSlot, ModelError, Outputs, Params, ToothContact, NY};
use crate::gear::{
    FrictionSums, IsoMean, Kinematics, Lubricant, Mesh, MeshError, PairGeometry, ParamError,
};
use nalgebra::{SMatrix, SVector, Vector3};
use std::f64::consts::PI;

mod coast;
mod elastic;
mod elastic_jacobian;
mod friction;
mod hidden;
mod memo;
mod stick;

pub use elastic::{ElasticContact, ElasticMesh};
pub use friction::{CREEP_ENTRY, CREEP_SPEED};
pub use stick::{RELEASE_BAND, STICK_RELAXATION};

use friction::Asker;

/// Which part of df/dy an evaluation gives: all of it, or the fast part of the split
/// (`GearedRotor::jacobian_fast`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum JacobianPart {
    Full,
    Fast,
}

/// Start state for [`GearedRotor::initialize_with`] (`model.md` §7).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InitialConditions {
    /// Displacements u1x u1y u1z u2x u2y u2z.
    pub u: [f64; 6],
    /// Their velocities.
    pub u_dot: [f64; 6],
    /// Initial angle of gear 1.
    pub phi1: f64,
}

/// The geared-rotor DAE (`model.md` §5) with its parameters, held inputs and gap offset.
#[derive(Debug, Clone)]
pub struct GearedRotor {
    params: Params,
    geom: PairGeometry,
    inputs: Inputs,
    /// Gap offset g0 (§3.3): g = 0 at the initial state.
    g0: f64,
    /// phi1 at initialisation (reference of xi and TE).
    phi1_0: f64,
    /// diag(M), diag(D), diag(K) of §5 in the order of q.
    mass: [f64; 7],
    damp: [f64; 7],
    stiff: [f64; 7],
    /// Filter corner w_c = 2 pi f_c (§8).
    wc: f64,
    /// Constant part of friction law 3 (ISO/TR 14179-2 mean coefficient).
    iso: IsoMean,
    /// Lubricant and materials of friction law 4.
    lub: Lubricant,
    /// Mesh and friction sums of the last kinematic state (a pure cache, see `memo`).
    memo: memo::KinematicMemo,
    /// A spur contact line of the drive flanks sticks at the pitch line (`model.md` §4.1;
    /// the simulation switches it at located instants). The coast flanks' line has the
    /// same two flags in the mirrored pair.
    stick: bool,
    /// The sense (+1, -1) in which a line just released from sticking slides, 0 if none
    /// (`PitchLine::Released`).
    released: f64,
    /// Whether the stick mode and the release refer to the coast flanks' line (elastic
    /// teeth; `stick_flank_is_coast`).
    stick_coast: bool,
    /// Laws 1 and 3 creep near standstill (`model.md` §4.2; the simulation switches it at
    /// located instants). The mirrored pair of the coast flanks holds the same flag.
    creep: bool,
    /// Physical scale of each state component (`rotor::error_scales`).
    scales: [f64; NY],
    /// The elastic mesh (`tooth_contact = elastic`, `model.md` §3.5); None for rigid teeth.
    elastic: Option<ElasticMesh>,
    /// The coast flanks of the elastic contact (`model.md` §3.6): the mirrored pair. None
    /// for rigid teeth and for the mirrored pair itself.
    coast: Option<coast::CoastFlank>,
    /// No Jacobian for the stepper (it takes forward differences of f): the reference the
    /// tests hold the elastic contact's chain-rule Jacobian against.
    difference_jacobian: bool,
    /// No split Jacobian (`jacobian_fast` declines): every renewal a full one, the
    /// reference the tests hold the split against.
    whole_jacobian: bool,
}

fn mesh_err(t: f64, e: MeshError) -> ModelError {
    match e {
        MeshError::CentreDistanceTooSmall { a, r_sum } => {
            ModelError::CentreDistanceTooSmall { t, a, r_sum }
        }
        MeshError::NonFinite => ModelError::NonFinite {
            t,
            what: "displacement",
        },
    }
}

/// A state vector with the centre displacements u (the rest zero).
fn displaced(u: &[f64; 6]) -> SVector<f64, NY> {
    let mut y = SVector::<f64, NY>::zeros();
    for i in 0..6 {
        y[idx::Q + i] = u[i];
    }
    y
}

#[inline]
pub(super) fn kinematics(y: &SVector<f64, NY>) -> Kinematics {
    let v = idx::V;
    Kinematics {
        v1: Vector3::new(y[v], y[v + 1], y[v + 2]),
        v2: Vector3::new(y[v + 3], y[v + 4], y[v + 5]),
        omega1: y[idx::OMEGA1],
        omega2: y[v + 6],
    }
}

impl GearedRotor {
    /// Validates the parameters and builds the model; inputs start at zero, g0 = 0.
    ///
    /// # Errors
    /// The first violated parameter bound.
    pub fn new(params: Params) -> Result<Self, ParamError> {
        Self::new_flank(params, true)
    }

    /// [`GearedRotor::new`]; `with_coast`: an elastic model gets its coast flanks (false
    /// for the mirrored pair that carries them, `coast`).
    fn new_flank(params: Params, with_coast: bool) -> Result<Self, ParamError> {
        let geom = params.validate()?;
        let (r1, r2) = (params.rotor1, params.rotor2);
        let fp = params.friction;
        let mass = [r1.m, r1.m, r1.m, r2.m, r2.m, r2.m, r2.j];
        let elastic = match params.tooth_contact {
            ToothContact::Rigid => None,
            ToothContact::Elastic => Some(ElasticMesh::new(&geom, &mass, params.zeta_mesh).ok_or(
                ParamError {
                    name: "tooth_contact",
                    value: 2.0,
                    requirement: "an undeflected mesh for the elastic contact".into(),
                },
            )?),
        };
        let coast = match (&elastic, with_coast) {
            (Some(_), true) => Some(coast::CoastFlank::new(&params).ok_or(ParamError {
                name: "j_bn",
                value: params.gear.j_bn,
                requirement: "a coast flank the mirrored pair can evaluate".into(),
            })?),
            _ => None,
        };
        let iso = IsoMean::new(
            params.gear.b,
            geom.rb1,
            geom.rb2,
            geom.alpha_wt,
            geom.cos_beta_b,
            fp.eta_oil,
            fp.ra,
            fp.x_l,
        );
        Ok(Self {
            params,
            geom,
            inputs: Inputs::default(),
            g0: 0.0,
            phi1_0: 0.0,
            mass,
            damp: [
                r1.d[0],
                r1.d[1],
                r1.d[2],
                r2.d[0],
                r2.d[1],
                r2.d[2],
                params.d_phi,
            ],
            stiff: [r1.k[0], r1.k[1], r1.k[2], r2.k[0], r2.k[1], r2.k[2], 0.0],
            wc: 2.0 * PI * params.omega1_filter_hz,
            iso,
            lub: fp.lubricant(),
            memo: memo::KinematicMemo::default(),
            stick: false,
            released: 0.0,
            stick_coast: false,
            creep: false,
            scales: super::DEFAULT_PAIR_SCALES,
            elastic,
            coast,
            difference_jacobian: false,
            whole_jacobian: false,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The pair geometry (§2).
    pub fn geometry(&self) -> &PairGeometry {
        &self.geom
    }

    /// The physical scale of each state component, from which the absolute tolerances
    /// follow (`atol_i = rtol scale_i`; `rotor::error_scales`).
    pub fn scales(&self) -> &[f64; NY] {
        &self.scales
    }

    /// The coefficient of friction where the parameter `mu` is it (laws 1 and 2); None for
    /// the laws whose coefficient follows from the load, speed and oil (3 and 4), which
    /// ignore `mu`.
    pub fn coulomb_mu(&self) -> Option<f64> {
        (!self.params.friction_law.load_dependent()).then_some(self.params.mu)
    }

    /// Changes mu (tunable). The lambda held in a state is then no longer consistent:
    /// recompute it with [`GearedRotor::consistent_lambda`] before restarting the solver.
    ///
    /// # Errors
    /// mu negative or not finite.
    pub fn set_mu(&mut self, mu: f64) -> Result<(), ParamError> {
        check_mu(mu)?;
        self.params.mu = mu;
        if let Some(c) = self.coast.as_mut() {
            c.set_mu(mu)?;
        }
        if !self.stick_possible() {
            // No friction left to hold a line (law 1 with mu = 0): no stick, no release.
            self.set_stick(false, 0.0);
        }
        Ok(())
    }

    /// Changes the rotational damper d_phi (tunable); as for [`GearedRotor::set_mu`],
    /// re-project lambda with [`GearedRotor::consistent_lambda`] before a restart.
    ///
    /// # Errors
    /// d_phi negative or not finite.
    pub fn set_d_phi(&mut self, d: f64) -> Result<(), ParamError> {
        check_d_phi(d)?;
        self.params.d_phi = d;
        self.damp[6] = d;
        // The mirrored pair holds a stuck coast line against the damper too (§4.1).
        if let Some(c) = self.coast.as_mut() {
            c.mirror_mut().set_d_phi(d)?;
        }
        Ok(())
    }

    /// Fixes the error scales (`rotor::error_scales`) for a start at t0 with the inputs
    /// held now; the initialisation does this (`GearedRotor::initialize_with`).
    pub fn set_scales_for_start(&mut self, t0: f64) {
        self.scales = super::error_scales(self, t0);
    }

    /// Sets the held inputs.
    pub fn set_inputs(&mut self, inputs: Inputs) {
        self.inputs = inputs;
    }

    /// The held inputs.
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    /// Gap offset g0 (§3.3), set by the initialisation.
    pub fn gap_offset(&self) -> f64 {
        self.g0
    }

    /// The references fixed at initialisation, `(g0, phi1(0))`: model state outside y that
    /// an FMU state snapshot must carry (the gap diagnostic and phi2/TE outputs use them).
    pub fn references(&self) -> (f64, f64) {
        (self.g0, self.phi1_0)
    }

    /// Restores the references of [`GearedRotor::references`] (e.g. after deserialising an
    /// FMU state into a fresh instance).
    pub fn set_references(&mut self, g0: f64, phi1_0: f64) {
        self.g0 = g0;
        self.phi1_0 = phi1_0;
    }

    /// Mesh of the displaced state y.
    ///
    /// # Errors
    /// Centre distance too small or non-finite displacements.
    pub fn mesh(&self, t: f64, y: &SVector<f64, NY>) -> Result<Mesh, ModelError> {
        self.mesh_memo(t, y, true)
    }

    /// [`GearedRotor::mesh`] for the integrator's f and Jacobian: reads the memo, does
    /// not write it (see [`Asker::Integrator`]).
    fn mesh_for_f(&self, t: f64, y: &SVector<f64, NY>) -> Result<Mesh, ModelError> {
        self.mesh_memo(t, y, false)
    }

    /// The mesh of y from the memo, or evaluated (and kept in it when `keep`).
    fn mesh_memo(&self, t: f64, y: &SVector<f64, NY>, keep: bool) -> Result<Mesh, ModelError> {
        self.memo.mesh(y, keep, || {
            let u1 = Vector3::new(y[0], y[1], y[2]);
            let u2 = Vector3::new(y[3], y[4], y[5]);
            self.geom.mesh(&u1, &u2).map_err(|e| mesh_err(t, e))
        })
    }

    /// Right-hand side f(t, y) of `M_ext y' = f` (`model.md` §5, §8, energy states of model.md §6).
    /// No heap allocation.
    ///
    /// # Errors
    /// Centre distance too small, no contact, or a non-finite result.
    pub fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), ModelError> {
        self.eval_rhs(t, y, f)
    }

    fn eval_rhs(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), ModelError> {
        let g = &self.geom;
        let m = self.mesh_for_f(t, y)?;
        // Elastic contact (§3.5): the normal force from the approach of the flanks; the
        // last slot of y is the work stored in the mesh spring, not a multiplier.
        // One contact length per f: the friction evaluation's (`elastic_friction`).
        let (elastic, lam, mut fr, stuck) = if self.elastic.is_some() {
            let (c, fr, stuck) = self.elastic_friction(t, y, &m)?;
            (Some(c), c.fn_, fr, stuck)
        } else {
            let lam = y[idx::LAMBDA];
            let (sums, mu) = self.friction(t, y, &m, lam, Asker::Integrator)?;
            let fr = self.friction_resultants(t, y, &m, &sums, mu, &[0.0; 7]);
            (None, lam, fr, None)
        };
        let grow = g.constraint_row(&m);
        let v = idx::V;
        let omega1 = y[idx::OMEGA1];
        let omega1_dot = y[idx::OMEGA1_DOT];
        let omega2 = y[v + 6];
        let t_load = self.inputs.t_load_at(t);
        // The coast flanks (§3.6): their normal force and friction, zero while apart.
        // While the drive flanks carry the load they are apart (`coast_surely_apart`).
        let coast = if elastic.is_some_and(|c| !self.coast_surely_apart(&c, &m)) {
            // A stuck coast line is held against the drive flanks' forces too.
            let drive = if self.coast_sticks() {
                coast::contact_generalised(lam, &grow, &fr)
            } else {
                [0.0; 7]
            };
            self.coast_terms(t, y, &m, &drive)?
        } else {
            coast::CoastTerms::default()
        };
        // A stuck drive line (elastic teeth, §4.1): its force holds it against all others.
        if let Some(st) = &stuck {
            self.add_stick_force(t, y, &m, st, lam, &coast.q, &mut fr);
        }
        let mut qf = fr.generalised();
        if elastic.is_some() {
            for (a, b) in qf.iter_mut().zip(coast.q.iter()) {
                *a += b;
            }
        }
        let mut p_damp = 0.0;
        let mut gv = 0.0;
        for i in 0..6 {
            f[i] = y[v + i];
        }
        // xi' = r_b2 omega2 - r_b1 omega1 (idx::Q doc).
        f[6] = g.rb2 * omega2 - g.rb1 * omega1;
        for i in 0..7 {
            let vi = y[v + i];
            f[v + i] = -self.damp[i] * vi - self.stiff[i] * y[i] + lam * grow[i] + qf[i];
            p_damp += self.damp[i] * vi * vi;
            gv += grow[i] * vi;
        }
        f[v + 6] -= t_load;
        // Drive filter (§8): critically damped, phi1' = omega1.
        let wc = self.wc;
        f[idx::PHI1] = omega1;
        f[idx::OMEGA1] = omega1_dot;
        f[idx::OMEGA1_DOT] = wc * wc * (self.inputs.omega1_at(t) - omega1) - 2.0 * wc * omega1_dot;
        // Energy accumulators (§6, §9.6).
        let t1 =
            lam * g.rb1 * g.cos_beta_b - fr.m1.z + self.params.rotor1.j * omega1_dot + coast.t1;
        f[idx::E_IN] = t1 * omega1;
        f[idx::E_LOSS] = fr.p_loss + coast.p_loss;
        f[idx::E_LOAD] = t_load * omega2;
        f[idx::E_DAMP] = p_damp;
        if let Some(c) = &elastic {
            f[idx::E_MESH_DAMP] = c.p_damp + coast.contact.p_damp;
            f[idx::LAMBDA] = c.p_spring + coast.contact.p_spring;
        } else {
            f[idx::E_MESH_DAMP] = 0.0;
            // Velocity-level constraint (§3.3).
            f[idx::LAMBDA] = gv - g.rb1 * g.cos_beta_b * omega1;
        }
        // On the contiguous slice: nalgebra's element iterator is a strided loop (about
        // 5x slower here).
        if !f.as_slice().iter().all(|x| x.is_finite()) {
            return Err(ModelError::NonFinite { t, what: "f" });
        }
        Ok(())
    }

    /// Whether the coast flanks are apart for certain, without evaluating their approach
    /// (one tan less per f while the drive flanks carry the load): by (3.24) and (3.28)
    /// the coast gap is `g_c = play(alpha) - g` with `play(alpha) = j_t + 2 R (inv alpha -
    /// inv alpha_wt)`, so drive flanks that overlap (`delta = -cos(beta_b) g > 0`) at a
    /// working angle `alpha >= alpha_wt` (centres not closer than a_w) leave the coast
    /// flanks apart by more than the play j_t. Taken only with a play of at least 1 nm,
    /// far above the rounding of either gap, so that it decides as `coast_terms` would.
    fn coast_surely_apart(&self, c: &ElasticContact, m: &crate::gear::Mesh) -> bool {
        c.delta > 0.0 && m.alpha >= self.geom.alpha_wt && self.geom.play() >= 1e-9
    }

    /// `M_ext = diag(I7, M, 1 (phi1), 1, 1 (filter), 1, 1, 1, 1 (energies), 0 (lambda))`.
    pub fn mass(&self) -> SMatrix<f64, NY, NY> {
        let mut m = SMatrix::<f64, NY, NY>::identity();
        for i in 0..7 {
            m[(idx::V + i, idx::V + i)] = self.mass[i];
        }
        // The multiplier is algebraic: a zero row.
        if self.contact().has_multiplier() {
            m[(idx::LAMBDA, idx::LAMBDA)] = 0.0;
        }
        m
    }

    /// Jacobian df/dy. The linear parts, the constraint row G(q) and its q-derivative and
    /// the lambda column are analytic; the derivatives of the friction resultants with
    /// respect to q, v, phi1 and omega1 are one-sided differences of the friction
    /// evaluation alone (15 evaluations, cheaper than 22 full f). In the elastic contact
    /// the same at lambda := Fn(y) with the chain rule through Fn (`elastic_jacobian`).
    /// Returns false (caller falls back to finite differences of f) when the state cannot
    /// be evaluated.
    pub fn jacobian(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> bool {
        // In the stick mode the stick force (4.13) depends on every state component; the
        // stepper's forward differences of f are taken there (stick phases are short).
        if self.stick || self.difference_jacobian {
            return false;
        }
        if self.elastic.is_none() {
            return self
                .eval_jacobian(t, y, jac, &mut [0.0; NY], JacobianPart::Full)
                .is_ok();
        }
        self.elastic_jacobian_part(t, y, jac, JacobianPart::Full)
    }

    /// The elastic contact's J or its fast part (§3.5): the chain rule through Fn(y), for
    /// the drive flanks; false (the stepper's differences of f) while the coast flanks touch
    /// (§3.6), where the state cannot be evaluated, and for rigid teeth.
    fn elastic_jacobian_part(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
        part: JacobianPart,
    ) -> bool {
        let Some(e) = &self.elastic else {
            return false;
        };
        !self.coast_touches(t, y) && self.eval_elastic_jacobian(e, t, y, jac, part).is_ok()
    }

    /// The fast part F of the split Jacobian `J = S + F` (radau5 `Problem::jacobian_fast`,
    /// `model.md` §3.5 "Cost"): with elastic teeth, J without the friction columns'
    /// differences and without the contact length's gradient dl/dy (in dFn/dy and in the
    /// rates of the spring's work and the mesh damping's energy, two quadrature rows).
    /// What it keeps follows the mesh stiffness `c_l l(t)` and the force Fn, which change
    /// within a mesh period; what it leaves to S (friction ~ mu Fn, `q dl/dy`) changes the
    /// Newton matrix little (the stepper renews S when the contraction says so). It costs
    /// about 2.5 f against 14-19 f for J. False where [`GearedRotor::jacobian`] declines
    /// (stick mode, coast flanks touching, test switches), and for
    /// rigid teeth: their J has no such stiffness (the constraint row is exact in every J),
    /// and they keep radau5.f's full renewals and so their results.
    pub fn jacobian_fast(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> bool {
        !(self.stick || self.difference_jacobian || self.whole_jacobian)
            && self.elastic_jacobian_part(t, y, jac, JacobianPart::Fast)
    }

    /// Test switch: `true` makes [`GearedRotor::jacobian`] decline, so that the stepper
    /// takes forward differences of f (the reference for the analytic Jacobian).
    #[doc(hidden)]
    pub fn set_difference_jacobian(&mut self, on: bool) {
        self.difference_jacobian = on;
    }

    /// Test switch: `true` makes [`GearedRotor::jacobian_fast`] decline, so that every
    /// renewal of J is a full one (the reference for the split Jacobian).
    #[doc(hidden)]
    pub fn set_whole_jacobian(&mut self, on: bool) {
        self.whole_jacobian = on;
    }

    /// The rigid model's Jacobian at y's own lambda (for the elastic contact: at lambda :=
    /// Fn(y), `elastic_jacobian`). `dl` receives the one-sided differences of the contact
    /// length l (3.12) that the friction columns evaluate anyway (positions and phi1; 0
    /// elsewhere). [`JacobianPart::Fast`] leaves out the friction columns (and so `dl`).
    fn eval_jacobian(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
        dl: &mut [f64; NY],
        part: JacobianPart,
    ) -> Result<(), ModelError> {
        let g = &self.geom;
        let (v, lam_i) = (idx::V, idx::LAMBDA);
        let m = self.mesh_for_f(t, y)?;
        let lam = y[lam_i];
        let (sums, mu) = self.friction(t, y, &m, lam, Asker::Integrator)?;
        let fr = sums.resultants(mu, lam);
        let grow = g.constraint_row(&m);
        let (cb, rb1, rb2) = (g.cos_beta_b, g.rb1, g.rb2);
        let omega1 = y[idx::OMEGA1];
        let omega1_dot = y[idx::OMEGA1_DOT];
        let t_load = self.inputs.t_load_at(t);
        let j1 = self.params.rotor1.j;
        // A memset (nalgebra's `fill` is a strided loop: ~80 % of this function's time).
        jac.as_mut_slice().fill(0.0);
        // q' = v, xi' = r_b2 omega2 - r_b1 omega1.
        for i in 0..6 {
            jac[(i, v + i)] = 1.0;
        }
        jac[(6, v + 6)] = rb2;
        jac[(6, idx::OMEGA1)] = -rb1;
        // Linear force parts and lambda G^T.
        for i in 0..7 {
            jac[(v + i, v + i)] = -self.damp[i];
            jac[(v + i, i)] = -self.stiff[i];
            jac[(v + i, lam_i)] = grow[i];
            jac[(lam_i, v + i)] = grow[i];
        }
        // dG/dq: G_xy(u2) = cos beta_b t(psi) = -G_xy(u1), psi = theta - alpha(a),
        // dt/dpsi = -e_w, dpsi/dd = (-sin th, cos th)/a - R/(a^2 sin alpha) (cos th, sin th).
        let d = m.c2 - m.c1;
        let (cth, sth) = (d.x / m.a, d.y / m.a);
        let k_al = g.r_sum / (m.a * m.a * m.alpha.sin());
        let dpsi = [-sth / m.a - k_al * cth, cth / m.a - k_al * sth];
        let ew = [m.e_w.x, m.e_w.y];
        let dv = [y[v + 3] - y[v], y[v + 4] - y[v + 1]];
        let ew_dv = ew[0] * dv[0] + ew[1] * dv[1];
        for (jj, &dp) in dpsi.iter().enumerate() {
            // column u2_j (and -column for u1_j): dn_xy/du2_j = -cb e_w dpsi_j.
            for comp in 0..2 {
                let dn = -cb * ew[comp] * dp;
                // rows of u1 (G = -n) and u2 (G = +n)
                jac[(v + comp, 3 + jj)] += -lam * dn;
                jac[(v + comp, jj)] += lam * dn;
                jac[(v + 3 + comp, 3 + jj)] += lam * dn;
                jac[(v + 3 + comp, jj)] += -lam * dn;
            }
            let dgv = -cb * ew_dv * dp;
            jac[(lam_i, 3 + jj)] += dgv;
            jac[(lam_i, jj)] -= dgv;
        }
        jac[(lam_i, idx::OMEGA1)] = -rb1 * cb;
        // Drive filter.
        let wc = self.wc;
        jac[(idx::PHI1, idx::OMEGA1)] = 1.0;
        jac[(idx::OMEGA1, idx::OMEGA1_DOT)] = 1.0;
        jac[(idx::OMEGA1_DOT, idx::OMEGA1)] = -wc * wc;
        jac[(idx::OMEGA1_DOT, idx::OMEGA1_DOT)] = -2.0 * wc;
        // Energies, linear parts: E_in' = (lambda r_b1 cb - M1_z + J1 omega1') omega1.
        let t1 = lam * rb1 * cb - fr.m1.z + j1 * omega1_dot;
        jac[(idx::E_IN, lam_i)] = rb1 * cb * omega1;
        jac[(idx::E_IN, idx::OMEGA1_DOT)] = j1 * omega1;
        jac[(idx::E_IN, idx::OMEGA1)] = t1;
        for i in 0..7 {
            jac[(idx::E_DAMP, v + i)] = 2.0 * self.damp[i] * y[v + i];
        }
        jac[(idx::E_LOAD, v + 6)] = t_load;
        // Friction: exactly linear in |lambda|.
        let sgn = if lam > 0.0 {
            1.0
        } else if lam < 0.0 {
            -1.0
        } else {
            0.0
        };
        let l = sums.contact.length;
        if self.params.friction_law.local_load_dependent() {
            self.friction_lambda_column(t, y, &m, &fr, jac)?;
        } else {
            // d p / d|lambda|; law 3: p = mu_mz |lambda| / l with mu_mz ~ |lambda|^0.2.
            let pu = if self.params.friction_law == FrictionLaw::IsoMean {
                1.2 * mu / l
            } else {
                mu / l
            };
            let gu = sums.generalised_unit();
            for i in 0..7 {
                jac[(v + i, lam_i)] += sgn * pu * gu[i];
            }
            jac[(idx::E_IN, lam_i)] += -sgn * pu * sums.moment1.z * omega1;
            jac[(idx::E_LOSS, lam_i)] = sgn * pu * sums.w;
        }
        if part == JacobianPart::Fast {
            return Ok(());
        }
        // Friction derivatives by one-sided differences of the friction evaluation only.
        let base = fr.generalised();
        let cols: [usize; 15] = [
            0,
            1,
            2,
            3,
            4,
            5,
            v,
            v + 1,
            v + 2,
            v + 3,
            v + 4,
            v + 5,
            v + 6,
            idx::PHI1,
            idx::OMEGA1,
        ];
        let mut yp = *y;
        for &j in cols.iter() {
            let yj = y[j];
            // Steps on the scale over which the friction terms vary: positions on the
            // gear size, the phase on the mesh period, speeds on their own size.
            let scale = if j < 6 {
                g.a_w
            } else if j == idx::PHI1 {
                g.phi1_period
            } else {
                yj.abs().max(1.0)
            };
            let h = f64::EPSILON.sqrt() * scale;
            yp[j] = yj + h;
            let h = yp[j] - yj;
            let mp = if j < 6 { self.mesh_for_f(t, &yp)? } else { m };
            let (sp, mup) = self.friction(t, &yp, &mp, lam, Asker::Integrator)?;
            let frp = sp.resultants(mup, lam);
            let pert = frp.generalised();
            for i in 0..7 {
                jac[(v + i, j)] += (pert[i] - base[i]) / h;
            }
            jac[(idx::E_IN, j)] += -(frp.m1.z - fr.m1.z) / h * omega1;
            jac[(idx::E_LOSS, j)] += (frp.p_loss - fr.p_loss) / h;
            dl[j] = (sp.contact.length - l) / h;
            yp[j] = yj;
        }
        Ok(())
    }

    /// lambda from the hidden constraint in closed form (`model.md` §7).
    ///
    /// Differentiating `G(q) v - r_b1 cos beta_b omega1 = 0` with
    /// `M v' = F + lambda G^T + |lambda| Phi` (F: damping, springs, load; Phi: friction per unit |lambda|, fixed
    /// for fixed kinematics) gives `lambda A + |lambda| B = r` with `A = G M^-1 G^T`,
    /// `B = G M^-1 Phi`, `r = r_b1 cos beta_b omega1' - G' v - G M^-1 F`. Solving under
    /// each sign assumption and keeping the consistent one needs no iteration.
    ///
    /// A root is taken only where its denominator `A + B` (λ >= 0) or `A - B` (λ < 0) is
    /// positive, so at most one assumption is ever consistent (λ >= 0 needs r >= 0, λ < 0
    /// needs r < 0). None is when `|B| >= A` and r has the sign whose denominator is not
    /// positive: Painlevé's paradox of friction, far outside the paper's range (for the
    /// default pair in rigid rotation |B| reaches A only at μ = 45, the smallest A/|B/μ|
    /// over a mesh period).
    ///
    /// # Errors
    /// Mesh/contact errors; [`ModelError::InconsistentLambda`] when no assumption is
    /// consistent (see above; r = 0 gives λ = 0).
    pub fn consistent_lambda(&self, t: f64, y: &SVector<f64, NY>) -> Result<f64, ModelError> {
        let m = self.mesh(t, y)?;
        if !self.contact().has_multiplier() {
            // The normal force is a function of the state (§3.5).
            return Ok(self.elastic_contact(y, &m).fn_);
        }
        self.consistent_lambda_mode(t, y, &m, self.stick)
    }

    /// [`GearedRotor::consistent_lambda`] in the given stick mode (`model.md` §4.1).
    pub(crate) fn consistent_lambda_mode(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        stick: bool,
    ) -> Result<f64, ModelError> {
        if self.params.friction_law.load_dependent() {
            // The scalar solve evaluates the friction itself (from y's own lambda).
            return self
                .consistent_lambda_solve(t, y, m, None, stick)
                .map(|(l, _)| l);
        }
        let (sums, _) = self.friction_mode(t, y, m, y[idx::LAMBDA], Asker::Point, stick)?;
        self.consistent_lambda_with(t, y, m, &sums)
    }

    /// [`GearedRotor::consistent_lambda`] for laws 1 and 2 (friction linear in |lambda|),
    /// in closed form from the mesh and the friction sums of y already evaluated (they do
    /// not depend on lambda). Laws 3 and 4 take [`GearedRotor::consistent_lambda_solve`].
    ///
    /// # Errors
    /// [`ModelError::InconsistentLambda`] as for [`GearedRotor::consistent_lambda`].
    pub(crate) fn consistent_lambda_with(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        sums: &FrictionSums,
    ) -> Result<f64, ModelError> {
        let pu = self.params.mu / sums.contact.length;
        let gu = sums.generalised_unit();
        let hidden::HiddenConstraint { gp, a, r } =
            self.hidden_constraint(t, y, m, sums.stuck.as_ref());
        let mut b = 0.0;
        for i in 0..7 {
            b += gp[i] * pu * gu[i] / self.mass[i];
        }
        let lp = r / (a + b);
        let ln = r / (a - b);
        let pos_ok = a + b > 0.0 && lp >= 0.0;
        let neg_ok = a - b > 0.0 && ln < 0.0;
        match (pos_ok, neg_ok) {
            (true, false) => Ok(lp),
            (false, true) => Ok(ln),
            _ => {
                if r == 0.0 {
                    Ok(0.0)
                } else {
                    Err(ModelError::InconsistentLambda {
                        t,
                        lambda_pos: lp,
                        lambda_neg: ln,
                    })
                }
            }
        }
    }

    /// Consistent initial state for zero displacements and velocities (`model.md` §7).
    ///
    /// # Errors
    /// See [`GearedRotor::initialize_with`].
    pub fn initialize(&mut self, t0: f64) -> Result<SVector<f64, NY>, ModelError> {
        self.initialize_with(t0, &InitialConditions::default())
    }

    /// Consistent initial state at t0 for given displacements, velocities and phi1
    /// (`model.md` §7, §8): sets g0 so that g(t0) = 0 (then xi = 0) and phi1(0), and
    /// returns [`GearedRotor::consistent_state`].
    ///
    /// # Errors
    /// Mesh/contact errors or an inconsistent lambda.
    pub fn initialize_with(
        &mut self,
        t0: f64,
        ic: &InitialConditions,
    ) -> Result<SVector<f64, NY>, ModelError> {
        if !ic
            .u
            .iter()
            .chain(&ic.u_dot)
            .chain([&ic.phi1])
            .all(|x| x.is_finite())
        {
            return Err(ModelError::NonFinite {
                t: t0,
                what: "initial state",
            });
        }
        let m = self.mesh(t0, &displaced(&ic.u))?;
        self.g0 = -self.geom.gap_raw(&m, 0.0);
        self.phi1_0 = ic.phi1;
        self.set_scales_for_start(t0);
        self.consistent_state(t0, ic)
    }

    /// The consistent state at t for the centre displacements, velocities and phi1 of `ic`
    /// (`model.md` §3.3, §7, §8): the filter at rest at omega1_ref(t), xi from the
    /// position-level constraint g = 0 with the model's gap offset g0, omega2 from the
    /// velocity-level constraint (5.2), energies 0, the last slot as the contact starts it
    /// (`Contact::start_value`: lambda from the hidden constraint, or the springs' energy).
    /// The one place that builds a state from (u, u'): the initial state, the periodic
    /// solutions and the static equilibrium start use it.
    ///
    /// # Errors
    /// Mesh/contact errors or an inconsistent lambda.
    pub fn consistent_state(
        &self,
        t: f64,
        ic: &InitialConditions,
    ) -> Result<SVector<f64, NY>, ModelError> {
        let g = &self.geom;
        let mut y = displaced(&ic.u);
        for i in 0..6 {
            y[idx::V + i] = ic.u_dot[i];
        }
        let omega1 = self.inputs.omega1_at(t);
        y[idx::PHI1] = ic.phi1;
        y[idx::OMEGA1] = omega1;
        y[idx::OMEGA1_DOT] = 0.0;
        if !y.iter().all(|x| x.is_finite()) {
            return Err(ModelError::NonFinite {
                t,
                what: "initial state",
            });
        }
        let m = self.mesh(t, &y)?;
        // Rigid: g = 0. Elastic (§3.5): the static approach for the nominal load,
        // g = -delta_0 / cos(beta_b) with delta_0 = lambda_nom / (c_l l).
        let lam_nom = self.nominal_lambda(t);
        let delta0 = self.static_approach(t, &m, ic.phi1, lam_nom)?;
        y[idx::Q + 6] = -self.g0 - g.gap_raw(&m, 0.0) - delta0 / g.cos_beta_b;
        if self.coast.is_some() && lam_nom < 0.0 {
            // A reversed nominal load (§3.6): the coast flanks carry it, at their static
            // approach; the drive gap is then the play (3.24) plus that approach.
            let delta_c = self.coast_static_approach(t, &y, -lam_nom)?;
            y[idx::Q + 6] += g.play_at(m.alpha) + delta_c / g.cos_beta_b;
        }
        let grow = g.constraint_row(&m);
        let gv: f64 = grow.iter().zip(ic.u_dot.iter()).map(|(a, b)| a * b).sum();
        y[idx::V + 6] = (g.rb1 * g.cos_beta_b * omega1 - gv) / grow[6];
        y[idx::LAMBDA] = self.contact().start_value(t, &y, &m)?;
        Ok(y)
    }

    /// Rigid-rotation kinematic state at t: no displacement, the filter at rest, omega2 =
    /// omega1 r_b1 / r_b2 (the constraint at rest), energies 0, lambda consistent; xi = 0
    /// when g0 is that of the undeflected state. Does not change g0.
    ///
    /// # Errors
    /// Mesh/contact errors or an inconsistent lambda.
    pub fn rigid_rotation_state(&self, t: f64, phi1: f64) -> Result<SVector<f64, NY>, ModelError> {
        self.consistent_state(
            t,
            &InitialConditions {
                phi1,
                ..InitialConditions::default()
            },
        )
    }

    /// The nominal normal force at the inputs of t: what the damper and the load torque on
    /// gear 2 take in rigid rotation at the drive speed, without friction (model.md §7),
    /// `lambda = (d_phi omega2 + T_load) / (r_b2 cos beta_b)` with `omega2 = omega1 r_b1 /
    /// r_b2`, in N. The one source of the load scale of the static equilibrium and of the
    /// periodic solutions.
    pub fn nominal_lambda(&self, t: f64) -> f64 {
        let g = &self.geom;
        let omega2 = self.inputs.omega1_at(t) * g.rb1 / g.rb2;
        (self.params.d_phi * omega2 + self.inputs.t_load_at(t)) / (g.rb2 * g.cos_beta_b)
    }

    /// Friction law 3 outside the operating range Schlenk's formula was fitted in, at the
    /// inputs of t (pitch-line speed `omega1 r_w1`, load per face width `F_bt/b` from the
    /// nominal normal force, [`GearedRotor::nominal_lambda`]): one phrase per violated
    /// bound (docs/friction.md, law 3), empty inside or for the other laws.
    pub fn law3_outside_fitted_range(&self, t: f64) -> Vec<String> {
        if self.params.friction_law != FrictionLaw::IsoMean {
            return Vec::new();
        }
        let g = &self.geom;
        let v_t = (self.inputs.omega1_at(t) * g.rb1 / g.alpha_wt.cos()).abs();
        // F_bt = lambda cos(beta_b) (transverse, in the plane of action), per mm of face.
        let load = self.nominal_lambda(t) * g.cos_beta_b / (self.params.gear.b * 1e3);
        crate::gear::friction::iso_mean::outside_fitted_range(v_t, load)
    }

    /// Frictionless static equilibrium for the inputs at t (`model.md` §7, §9.5): constant
    /// omega1, omega2 = omega1 r_b1 / r_b2, `lambda = (d_phi omega2 + T_load)/(r_b2 cos beta_b)`
    /// and `K u = lambda G_u^T(u)` solved by fixed-point iteration (G depends on u only
    /// through the small rotation of the line of action, so it contracts fast).
    /// Returns the initial conditions (u, u' = 0) and lambda. A start near the periodic orbit.
    ///
    /// # Errors
    /// A zero stiffness on an axis the normal force loads, or no convergence.
    pub fn static_equilibrium(
        &self,
        t: f64,
        phi1: f64,
    ) -> Result<(InitialConditions, f64), ModelError> {
        let g = &self.geom;
        let lam = self.nominal_lambda(t);
        let mut u = [0.0f64; 6];
        for _ in 0..50 {
            let u1 = Vector3::new(u[0], u[1], u[2]);
            let u2 = Vector3::new(u[3], u[4], u[5]);
            let m = g.mesh(&u1, &u2).map_err(|e| mesh_err(t, e))?;
            // A reversed load with coast flanks (§3.6): the coast force |lam| along its own
            // row (its radial part is the opposite of the drive row's).
            let (grow, f) = match (lam < 0.0).then(|| self.coast_row(t, &u)).transpose()? {
                Some(Some(row)) => (row, -lam),
                _ => (g.constraint_row(&m), lam),
            };
            let mut change: f64 = 0.0;
            for i in 0..6 {
                let load = f * grow[i];
                let ui = if self.stiff[i] > 0.0 {
                    load / self.stiff[i]
                } else if load == 0.0 {
                    0.0
                } else {
                    return Err(ModelError::NoStaticEquilibrium {
                        reason: "zero bearing stiffness on a loaded axis",
                    });
                };
                change = change.max((ui - u[i]).abs());
                u[i] = ui;
            }
            if change <= 1e-15 * g.a_w {
                return Ok((
                    InitialConditions {
                        u,
                        u_dot: [0.0; 6],
                        phi1,
                    },
                    lam,
                ));
            }
        }
        Err(ModelError::NoStaticEquilibrium {
            reason: "fixed-point iteration did not converge",
        })
    }

    /// Every output of `model.md` §6 from the state and the inputs at t. When the mesh
    /// cannot be evaluated the contact quantities are NaN.
    pub fn outputs(&self, t: f64, y: &SVector<f64, NY>) -> Outputs {
        // Without a multiplier the force is the state's: nothing to make consistent.
        if !self.contact().has_multiplier() {
            return self.outputs_consistent(t, y);
        }
        self.outputs_with(t, y, self.point_friction(t, y))
    }

    /// The mesh of y and its friction at y's own lambda, as the outputs ask for them.
    fn point_friction(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
    ) -> Result<(Mesh, FrictionSums, f64), ModelError> {
        self.mesh(t, y).and_then(|m| {
            self.friction(t, y, &m, y[idx::LAMBDA], Asker::Outputs)
                .map(|(s, mu)| (m, s, mu))
        })
    }

    /// Outputs with lambda replaced by the value of the hidden constraint where it can be
    /// decided ([`GearedRotor::consistent_lambda`]; else the lambda of y), evaluating the
    /// mesh and the friction sums once for both (they do not depend on lambda).
    pub fn outputs_consistent(&self, t: f64, y: &SVector<f64, NY>) -> Outputs {
        if self.contact().last_slot() == LastSlot::StoredSpringWork {
            // The normal force follows from y's positions and velocities (§3.5).
            let mut z = *y;
            if let Ok(m) = self.mesh(t, y) {
                z[idx::LAMBDA] = self.elastic_contact(y, &m).fn_;
            }
            let res = match self.point_friction(t, &z) {
                // No drive line active and no force (free flight of a large vibration):
                // the outputs without drive friction, not NaN.
                Err(ModelError::NoContact { .. }) if z[idx::LAMBDA] == 0.0 => {
                    self.mesh(t, y).map(|m| (m, FrictionSums::default(), 0.0))
                }
                r => r,
            };
            let mut o = self.outputs_with(t, &z, res);
            self.add_coast_outputs(t, y, &mut o);
            // The stiffness variation's work: spring energy minus the work stored.
            o.w_mesh_stiffness = o.e_mesh_spring - y[idx::LAMBDA];
            return o;
        }
        if self.params.friction_law.load_dependent() {
            return self.outputs_consistent_load_dependent(t, y);
        }
        let res = self.point_friction(t, y);
        let mut z = *y;
        if let Ok((m, sums, _)) = &res {
            if let Ok(l) = self.consistent_lambda_with(t, y, m, sums) {
                if l.is_finite() {
                    z[idx::LAMBDA] = l;
                }
            }
        }
        self.outputs_with(t, &z, res)
    }

    /// [`GearedRotor::outputs_consistent`] for laws 3 and 4, where the friction follows
    /// lambda: the scalar solve starts from y's own lambda with the friction evaluated
    /// there and returns the friction at its root, which the outputs then use.
    fn outputs_consistent_load_dependent(&self, t: f64, y: &SVector<f64, NY>) -> Outputs {
        let res = self.point_friction(t, y);
        let mut z = *y;
        let res = res.map(|(m, sums, mu)| {
            match self.consistent_lambda_solve(t, y, &m, Some((sums, mu)), self.stick) {
                Ok((l, (s, mu_l))) if l.is_finite() => {
                    z[idx::LAMBDA] = l;
                    (m, s, mu_l)
                }
                _ => (m, sums, mu),
            }
        });
        self.outputs_with(t, &z, res)
    }

    fn outputs_with(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        res: Result<(Mesh, FrictionSums, f64), ModelError>,
    ) -> Outputs {
        self.outputs_with_other(t, y, res, None)
    }

    /// [`GearedRotor::outputs_with`] where a stuck line is held against the generalised
    /// forces `other` of the other flanks and the load (the coast side, whose mirrored
    /// pair does not hold the inputs); None: the model's own coast flanks.
    pub(crate) fn outputs_with_other(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        res: Result<(Mesh, FrictionSums, f64), ModelError>,
        other: Option<&[f64; 7]>,
    ) -> Outputs {
        let g = &self.geom;
        let v = idx::V;
        let mut o = Outputs::default();
        let omega1 = y[idx::OMEGA1];
        let omega1_dot = y[idx::OMEGA1_DOT];
        let omega2 = y[v + 6];
        let lam = y[idx::LAMBDA];
        o.omega1 = omega1;
        o.omega1_dot = omega1_dot;
        o.phi1 = y[idx::PHI1];
        o.omega2 = omega2;
        o.te = y[6];
        o.phi2 = (y[6] + g.rb1 * (y[idx::PHI1] - self.phi1_0)) / g.rb2;
        o.fn_ = lam;
        o.contact_lost = lam < 0.0;
        o.stick = self.stick();
        o.e_in = y[idx::E_IN];
        o.e_loss = y[idx::E_LOSS];
        // The dampers' and the mesh damping's (elastic teeth; 0 with rigid ones).
        o.e_damp = y[idx::E_DAMP] + y[idx::E_MESH_DAMP];
        o.e_mesh_damp = y[idx::E_MESH_DAMP];
        o.e_load = y[idx::E_LOAD];
        let mut e_kin = 0.5 * self.params.rotor1.j * omega1 * omega1;
        let mut e_pot = 0.0;
        let mut p_damp = 0.0;
        for i in 0..7 {
            e_kin += 0.5 * self.mass[i] * y[v + i] * y[v + i];
            e_pot += 0.5 * self.stiff[i] * y[i] * y[i];
            p_damp += self.damp[i] * y[v + i] * y[v + i];
        }
        o.e_kin = e_kin;
        o.e_pot = e_pot;
        o.p_damp = p_damp;
        o.t_damp = self.params.d_phi * omega2;
        o.p_damp_phi = o.t_damp * omega2;
        for i in 0..3 {
            o.u1[i] = y[i];
            o.u2[i] = y[3 + i];
            o.v1[i] = y[v + i];
            o.v2[i] = y[v + 3 + i];
            o.f_bearing1[i] = self.stiff[i] * y[i] + self.damp[i] * y[v + i];
            o.f_bearing2[i] = self.stiff[3 + i] * y[3 + i] + self.damp[3 + i] * y[v + 3 + i];
        }
        let (m, sums, mu) = match res {
            Ok(x) => x,
            Err(_) => {
                let nan = f64::NAN;
                o.t1 = nan;
                o.p_in = nan;
                o.p_loss = nan;
                o.mu_eff = nan;
                o.mu_mz = nan;
                o.gap = nan;
                o.contact_length = if matches!(res, Err(ModelError::NoContact { .. })) {
                    0.0
                } else {
                    nan
                };
                let n3 = [nan; 3];
                o.f_friction1 = n3;
                o.f_friction2 = n3;
                o.m_friction1 = n3;
                o.m_friction2 = n3;
                o.f_contact1 = n3;
                o.f_contact2 = n3;
                o.m_contact1 = n3;
                o.m_contact2 = n3;
                return o;
            }
        };
        // A stuck line is held against the other flanks' forces too (elastic teeth: the
        // given ones, or the model's own coast flanks).
        let other = match (other, sums.stuck.is_some() && self.elastic.is_some()) {
            (Some(q), _) => *q,
            (None, true) => self
                .coast_terms(t, y, &m, &[0.0; 7])
                .map_or([f64::NAN; 7], |c| c.q),
            (None, false) => [0.0; 7],
        };
        let fr = self.friction_resultants(t, y, &m, &sums, mu, &other);
        if self.elastic.is_some() {
            let c = self.elastic_contact(y, &m);
            o.mesh_deflection = c.delta;
            // The stiffness of the flanks in contact: 0 in free flight (§3.6).
            o.mesh_stiffness = if c.in_contact { c.stiffness } else { 0.0 };
            o.mesh_state = i32::from(c.in_contact);
            o.e_mesh_spring = c.energy;
            o.e_pot += c.energy;
        } else {
            o.mesh_state = 1;
        }
        let l = sums.contact.length;
        // (l = 0 only for the elastic contact in free flight: no line, no coefficient.)
        o.mu_eff = if l > 0.0 {
            self.mean_coefficient(&sums, mu)
        } else {
            f64::NAN
        };
        o.mu_mz = self.iso.mu(lam, omega1, omega2);
        o.t1 = lam * g.rb1 * g.cos_beta_b - fr.m1.z + self.params.rotor1.j * omega1_dot;
        o.p_in = o.t1 * omega1;
        o.p_loss = fr.p_loss;
        o.gap = g.gap_raw(&m, y[6]) + self.g0;
        o.contact_length = sums.contact.length;
        o.pairs_in_contact = sums.contact.pairs;
        // Normal load lambda / l per unit length along every line: force +-lambda n,
        // moments (lambda / l) int (P - c_j) ds x n.
        let q = if l > 0.0 { lam / l } else { 0.0 };
        let fn2 = lam * m.n;
        let mn1 = -q * sums.arm1.cross(&m.n);
        let mn2 = q * sums.arm2.cross(&m.n);
        let arr = |x: Vector3<f64>| [x.x, x.y, x.z];
        o.f_friction1 = arr(fr.f1);
        o.f_friction2 = arr(fr.f2);
        o.m_friction1 = arr(fr.m1);
        o.m_friction2 = arr(fr.m2);
        o.f_contact1 = arr(fr.f1 - fn2);
        o.f_contact2 = arr(fr.f2 + fn2);
        o.m_contact1 = arr(fr.m1 + mn1);
        o.m_contact2 = arr(fr.m2 + mn2);
        o
    }
}
