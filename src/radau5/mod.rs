//! RADAU5 (Hairer & Wanner, `radau5.f` version of 2002) for `M y' = f(t, y)` with index-1,
//! -2 and -3 components, re-implemented in safe Rust for small dense systems
//! (`docs/radau5.md`).
//!
//! Same algorithm, constants, defaults and decisions as the Fortran (§1-§7), so that the
//! work counters match it step for step (all 26 rows of `reference.md` match exactly, see
//! `tests/radau5_parity.rs`); plus the step-based interface co-simulation needs (§8): stop
//! times without restart, dense output, explicit restart, a plain-data [`Snapshot`] with a
//! byte layout, typed [`Error`]s, [`Statistics`], and no heap allocation after
//! construction (fixed-size nalgebra storage, static dispatch on the [`Problem`] type).
//!
//! Modules: [`tableau`] (constants), [`options`] (defaults and validation), [`linalg`]
//! (DECSOL-style LU), `step_size` (`err^0.25` as radau5.f computes it), `stepper`
//! (RADCOR as a state machine, dense output), `step_phases` (one step in the phases of
//! RADCOR: step-size choice, matrices, Newton iteration, error estimate, accept/reject),
//! `state`
//! (everything kept between steps), `snapshot` (copy and bytes), `stats`, `error`.
//!
//! # Where it differs from `RADCOR`, and why
//! None of these changes a decision of an integration over `[t0, t_end]` in one
//! [`Radau5::integrate_to`] call (the parity setting); they concern what the Fortran does
//! not have:
//! - Stop times (§8): the step that reaches a stop time lands on it exactly (`t + h` is
//!   replaced by `t_stop`), like the Fortran's last step. If that shortened step went
//!   through without trouble, the controller's proposal from before the shortening is kept
//!   (scaled by [`Options::resume_after_stop`], default 1; the Gustafsson history is not
//!   overwritten by the tiny step), so tiny
//!   communication steps cost one step each. Between stop intervals of equal length (to
//!   1e-9 and the rounding of t) the LU pair is reused, not between merely similar ones
//!   (the Newton matrix would be wrong by 1 - h_lu/h). A Newton start extrapolated over more than `1/facr`
//!   times the last step (impossible in the Fortran) starts from zero instead.
//! - `f(t, y)` after a step that landed on a stop time is evaluated when the next step
//!   starts (the Fortran never evaluates it after its last step, and does not count it).
//! - A stop time within 4 ulps of t is reached without a step (it could only fail with
//!   "step size too small").
//! - f at the end of an accepted step is evaluated before the step is committed, so a
//!   failing f there shrinks h like a Newton failure.
//! - f returning `Err` or non-finite values, and non-finite Newton increments, count as
//!   Newton failures (h halved). A non-finite f inside the Newton iteration is counted as
//!   the Fortran counts it (the iteration's 3 calls and its solve, then h halved: its
//!   THETA >= 0.99 path from the second iteration on); in the first and the last
//!   iteration, where the Fortran has no convergence test and would carry the NaN into
//!   the error estimate, the attempt is rejected the same way (docs/radau5.md §7).
//!   10 in a row end the step with [`Error::Rhs`] /
//!   [`Error::NonFinite`], 20 unexpected failures in a row with [`Error::NewtonFailure`]
//!   (the Fortran relies on "step size too small", which can not trigger at t = 0).
//!   Singular LU pairs are counted since the last accepted step (the Fortran never resets
//!   `NSING`).
//! - Only forward integration (`t_stop >= t`).
//! - [`Radau5::refresh_f`] re-evaluates the stored f(t, y) with a caller-given problem
//!   (the limit from after a jump of f the caller located), keeping everything else.
//! - [`Radau5::retake`] redoes the last accepted step so that it ends on a given earlier
//!   time (a stop time learned only after the step was taken); it keeps `y` and `f` at the
//!   start of the last step for that.
//! - `fixed_step`: steps of a caller-given constant size with a fixed number of simplified
//!   Newton iterations and a caller-scheduled Jacobian/LU ([`Radau5::fixed_prepare`],
//!   [`Radau5::fixed_step`]): bounded work per step, no error control, non-convergence is
//!   [`Error::FixedStepNewton`].

mod error;
mod fixed_step;
pub mod linalg;
mod linear_systems;
pub mod options;
mod problem;
mod snapshot;
mod snapshot_check;
mod state;
mod stats;
mod step_phases;
mod step_size;
mod stepper;
pub mod tableau;

pub use error::{Error, RhsError, SnapshotError};
pub use fixed_step::MIN_FIXED_ITERATIONS;
pub use options::{Controller, JacobianMode, NewtonStart, Options, Tolerance};
pub use problem::Problem;
pub use snapshot::Snapshot;
pub use stats::Statistics;
pub use stepper::{Radau5, Retake};
