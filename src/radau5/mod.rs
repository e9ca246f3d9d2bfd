//! RADAU5 (Hairer & Wanner, `radau5.f` version of 2002) for `M y' = f(t, y)` with index-1,
//! -2 and -3 components, re-implemented in safe Rust for small dense systems
//! (`../shared/spec/radau5.md`).
//!
//! Same algorithm, constants, defaults and decisions as the Fortran (§1-§7), so that the
//! work counters match it step for step; plus the step-based interface co-simulation needs
//! (§8): stop times without restart, dense output, explicit restart, a plain-data
//! [`Snapshot`] with a byte layout, typed [`Error`]s, [`Statistics`], and no heap
//! allocation after construction (fixed-size nalgebra storage, static dispatch).
//!
//! Modules: [`tableau`] (constants), [`options`] (defaults and validation), [`linalg`]
//! (DECSOL-style LU), `stepper` (RADCOR as a state machine, dense output), `state`
//! (everything kept between steps), `snapshot` (copy and bytes), `stats`, `error`.

pub mod linalg;
pub mod options;
mod problem;
mod snapshot;
mod state;
mod stats;
mod stepper;
pub mod tableau;
mod error;
#[doc(hidden)]
pub mod test_problems;

pub use error::{Error, RhsError, SnapshotError};
pub use options::{Controller, JacobianMode, NewtonStart, Options, Tolerance};
pub use problem::Problem;
pub use snapshot::Snapshot;
pub use stats::Statistics;
pub use stepper::Radau5;
