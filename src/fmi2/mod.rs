//! The FMI 2.0 Co-Simulation C ABI: a thin unsafe shell over a safe instance.

pub mod variables;
