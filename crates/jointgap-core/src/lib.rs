//! jointgap-core: planar multibody dynamics in Cartesian coordinates with Lagrange
//! multipliers, for mechanisms with ideal and (later) clearance joints.
//!
//! Pipeline: [`model::Model`] (plain data) -> [`system::System`] (checked, indexed) ->
//! [`simulate::simulate`] (assembly, integration, output) -> [`output::SimResult`].
//!
//! The modules are layers, each importing only the ones listed before it, so that a
//! change of one stage (a new contact geometry, a new integration method) cannot reach
//! back into the stages it builds on:
//! [`model`] (the model's plain data) -> [`mechanics`] (the element kinds: bodies, joint
//! rows, drivers, force elements, clearance joints; each built from its model entry and
//! evaluated as a pure function of the state) -> [`system`] (the mechanism compiled from
//! the model: its elements checked, indexed and laid out) -> [`dynamics`] (the equations
//! of motion and their solve) -> [`integrators`] (generic ODE methods, knowing nothing of
//! mechanics) -> [`simulate`] (the run: the equations of motion handed to a method,
//! events, switching, output). [`math`], [`profile`] and [`output`] are plain
//! vocabulary that every stage may use.
#![warn(missing_docs)]
// Index loops mirror the formulas of the methods (stages, rows, coordinates).
#![allow(clippy::needless_range_loop)]

pub mod codegen;
pub mod defaults;
pub mod error;
pub mod math;
pub mod model;
pub mod output;
pub mod profile;
pub mod scalar;

pub mod mechanics;

pub mod system;

pub mod dynamics;

pub mod integrators;

pub mod simulate;

pub use error::Error;
pub use model::Model;
pub use output::{ClearanceData, Impact, JointImpacts, JointWear, RunStats, SimResult, Status};
pub use simulate::{
    simulate, simulate_batch, simulate_with, BatchControl, Method, Monitor, Progress, SimOptions, Stop,
    WearOptions,
};
pub use system::System;
