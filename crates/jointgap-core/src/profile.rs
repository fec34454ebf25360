//! Where a run's time goes, stage by stage, when the run is asked to measure it
//! (`SimOptions::profile`): the clock is read only then, so an ordinary run pays one
//! branch per stage.

use std::time::Instant;

use serde::Serialize;

/// Seconds spent per stage; each stage's figure excludes the stages it calls (the
/// evaluations made for a Jacobian or an output sample count as force evaluation and
/// linear solves, not as Jacobian or output time).
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct Profile {
    /// The equations of motion beyond their linear solves: constraint rows, applied
    /// forces (contact laws included) and the accelerations from them; a compiled
    /// evaluation whole [s].
    pub forces: f64,
    /// Schur complement: assembly, factorisation, solve and refinement [s].
    pub linear_solves: f64,
    /// Finite-difference Jacobians, their LU factors and eigenvalues, beyond the
    /// evaluations they make [s].
    pub jacobians: f64,
    /// Output samples: interpolation and channels, beyond their evaluation [s].
    pub output: f64,
    /// Contact-event location and impact peak probes [s].
    pub events: f64,
    /// Projection onto the constraints, beyond its linear solves [s].
    pub projection: f64,
    /// The whole integration [s]; what the stages leave is the integrators' own work.
    pub total: f64,
}

/// A running measurement of one stage: started when profiling, else inert.
#[derive(Debug, Clone, Copy)]
pub struct Lap {
    started: Option<Instant>,
    /// Seconds already booked to inner stages when the lap started.
    inner: f64,
}

impl Profile {
    /// Seconds booked to the stages that others call.
    fn inner(&self) -> f64 {
        self.forces + self.linear_solves
    }
}

/// Starts a lap if `profile` is being measured.
pub fn start(profile: &Option<Profile>) -> Lap {
    match profile {
        Some(p) => Lap { started: Some(Instant::now()), inner: p.inner() },
        None => Lap { started: None, inner: 0.0 },
    }
}

/// Books the lap's time, less what inner stages booked meanwhile, to `stage`.
pub fn stop(profile: &mut Option<Profile>, lap: Lap, stage: fn(&mut Profile) -> &mut f64) {
    if let (Some(p), Some(started)) = (profile.as_mut(), lap.started) {
        let elapsed = started.elapsed().as_secs_f64() - (p.inner() - lap.inner);
        *stage(p) += elapsed;
    }
}
