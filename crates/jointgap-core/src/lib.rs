//! jointgap-core: planar multibody dynamics in Cartesian coordinates with Lagrange
//! multipliers, for mechanisms with ideal and (later) clearance joints.
//!
//! Pipeline: [`model::Model`] (plain data) -> [`system::System`] (checked, indexed) ->
//! [`solve::simulate`] (assembly, integration, output) -> [`output::SimResult`].
#![warn(missing_docs)]
// Index loops mirror the formulas of the methods (stages, rows, coordinates).
#![allow(clippy::needless_range_loop)]

pub mod contact;
pub mod defaults;
pub mod drivers;
pub mod error;
pub mod forces;
mod magnitudes;
pub mod math;
pub mod measures;
pub mod model;
pub mod output;
pub mod planar;
pub mod resolved;
pub mod solve;
pub mod system;

pub use model::Model;
pub use output::{ClearanceData, Impact, JointImpacts, RunStats, SimResult, Status};
pub use solve::{
    simulate, simulate_batch, simulate_with, BatchControl, Method, Monitor, Progress, SimOptions, Stop,
};
pub use system::System;

/// Errors that stop a run before it starts. Each message names the offending element;
/// [`Error::parts`] gives the element, the key and the problem apart.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value of a model element is invalid, said in parts.
    #[error("{0}")]
    Element(error::ElementError),
    /// The model is malformed or physically invalid.
    #[error("{0}")]
    Model(String),
    /// The initial configuration cannot satisfy the constraints.
    #[error("{0}")]
    Assembly(String),
    /// The run options are invalid.
    #[error("{0}")]
    Options(String),
}
