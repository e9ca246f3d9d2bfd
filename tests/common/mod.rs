//! Helpers shared by the integration test binaries (each binary compiles this module with
//! `mod common;` and uses only part of it, hence the `dead_code` allowance). The FMI 2.0
//! instance driver and logger are in [`fmi2`].
#![allow(dead_code)]

pub mod alloc;
pub mod fmi2;
pub mod gear;
pub mod quad;
pub mod radau5;
pub mod radau5_problems;
pub mod rng;
pub mod rotor;
pub mod stick;
