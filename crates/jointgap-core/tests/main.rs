//! The engine's integration tests, one module per subject, built as one test program so
//! that the engine's generic code is compiled once for all of them.

mod clearance;
mod common;
mod compiled;
mod drift;
mod element_errors;
mod energy;
mod engine;
mod film;
mod jacobian;
mod joint_kinds;
mod prescribed;
mod radau5;
mod run_checks;
mod schur;
mod singular;
mod spatial_body;
mod spatial_clearance;
mod spatial_engine;
mod spatial_joint_kinds;
mod spatial_mechanisms;
mod stepper_contract;
mod wear;
