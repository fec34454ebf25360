//! Run options: end time, output sampling, tolerances and method.

use serde::{Deserialize, Serialize};

/// Integration method.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Explicit Dormand-Prince 5(4) while it is efficient, the implicit SDIRK4 when the
    /// problem turns stiff (detected from repeated step-size limitation).
    #[default]
    Auto,
    /// Explicit embedded Runge-Kutta, Dormand-Prince 5(4) with 4th-order dense output.
    Dopri5,
    /// L-stable singly diagonally implicit Runge-Kutta of order 4 with embedded order 3
    /// (Hairer and Wanner, Solving ODEs II, Table IV.6.5), for stiff contact and friction.
    Sdirk4,
    /// L-stable 3-stage Radau IIA collocation method of order 5 with embedded order 3
    /// (Hairer and Wanner, Solving ODEs II, section IV.8, the method of RADAU5), for stiff
    /// contact and friction at tight tolerances.
    Radau5,
}

impl Method {
    /// The method's name in options and reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::Dopri5 => "dopri5",
            Method::Sdirk4 => "sdirk4",
            Method::Radau5 => "radau5",
        }
    }
}

fn default_compiled() -> bool {
    true
}
fn default_exact_jacobian() -> bool {
    true
}
fn default_rtol() -> f64 {
    1e-8
}
fn default_atol() -> f64 {
    1e-11
}
/// The default step budget: [`MIN_STEP_BUDGET`] steps, or [`STEPS_PER_SECOND`] per
/// simulated second when that is more.
pub fn default_step_budget(t_end: f64) -> usize {
    let scaled = STEPS_PER_SECOND * t_end;
    if scaled.is_finite() && scaled > MIN_STEP_BUDGET as f64 {
        scaled.ceil() as usize
    } else {
        MIN_STEP_BUDGET
    }
}

/// The smallest default step budget: 1e7 steps.
pub const MIN_STEP_BUDGET: usize = 10_000_000;
/// Steps per simulated second of the default budget of a long run: 1e6, fifteen times
/// what the two-clearance slider-crank takes at the default tolerances (66 000 per
/// second; a fixed 1e7 stopped its 180 s run at 151 s), so that a long run is not
/// stopped for its length while a run stuck at tiny steps still is.
pub const STEPS_PER_SECOND: f64 = 1e6;
fn default_decimate() -> usize {
    1
}

/// Options of one run. Times in s, rates in Hz.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimOptions {
    /// End time [s], > 0. Runs start at t = 0.
    pub t_end: f64,
    /// Output sampling rate [Hz]; `None` records every accepted step.
    #[serde(default)]
    pub rate: Option<f64>,
    /// Record every accepted step in addition to the sampled output.
    #[serde(default)]
    pub every_step: bool,
    /// Relative tolerance of the local error test (default 1e-8).
    #[serde(default = "default_rtol")]
    pub rtol: f64,
    /// Absolute tolerance of the local error test, in state units m, rad, m/s, rad/s
    /// (default 1e-11).
    #[serde(default = "default_atol")]
    pub atol: f64,
    /// Integration method (default `auto`).
    #[serde(default)]
    pub method: Method,
    /// Largest step [s]; by default unbounded.
    #[serde(default)]
    pub max_step: Option<f64>,
    /// Step budget (accepted and rejected steps); the run stops with a reason when it is
    /// spent. `None`: [`default_step_budget`], 1e7 or 1e6 per simulated second, whichever
    /// is more.
    #[serde(default)]
    pub max_steps: Option<usize>,
    /// Channels to record (exact names or `element.*`); all by default.
    #[serde(default)]
    pub channels: Option<Vec<String>>,
    /// Evaluate the channels at every accepted step for their peaks
    /// (`SimResult::peaks`) without keeping those steps: an impact's spike can be
    /// narrower than the sampling interval, and a long run cannot keep every step.
    #[serde(default)]
    pub step_peaks: bool,
    /// Keep every `decimate`-th output record (default 1: all), e.g. of `every_step` output.
    #[serde(default = "default_decimate")]
    pub decimate: usize,
    /// Keep the energy accounts: the work of drivers and applied loads and the energy
    /// dissipated, as channels, and the energy balance (about three more evaluations of
    /// the equations of motion per step and per sample).
    #[serde(default)]
    pub energy: bool,
    /// Measure the time spent per stage (forces, linear solves, Jacobians, output,
    /// events, projection) into `RunStats::profile`.
    #[serde(default)]
    pub profile: bool,
    /// Compile the model's constraint rows and applied forces to native code where the
    /// compiler covers the model (docs/compiled.md); `false` runs them interpreted. The
    /// results are the same to the bit.
    #[serde(default = "default_compiled")]
    pub compiled: bool,
    /// The implicit methods take the exact acceleration rows of `df/dy`, differentiated
    /// from the recorded evaluation where the compiler covers the model
    /// (docs/compiled.md); `false` takes the applied forces' part by forward
    /// differences, as where it does not.
    #[serde(default = "default_exact_jacobian")]
    pub exact_jacobian: bool,
    /// Accumulate the Archard wear of the dry journals in their bearings (revolute and
    /// cylindrical clearance joints) on angular grids
    /// into `SimResult::wear` (docs/wear.md); none by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear: Option<super::wear::WearOptions>,
}

impl SimOptions {
    /// Options with defaults for a run to `t_end`.
    pub fn new(t_end: f64) -> Self {
        SimOptions {
            t_end,
            rate: None,
            every_step: false,
            rtol: default_rtol(),
            atol: default_atol(),
            method: Method::default(),
            max_step: None,
            max_steps: None,
            channels: None,
            decimate: default_decimate(),
            step_peaks: false,
            energy: false,
            profile: false,
            compiled: default_compiled(),
            exact_jacobian: default_exact_jacobian(),
            wear: None,
        }
    }

    /// The step budget of this run: `max_steps`, or the default for `t_end`.
    pub fn step_budget(&self) -> usize {
        self.max_steps.unwrap_or_else(|| default_step_budget(self.t_end))
    }

    /// Rejects non-finite or out-of-range values, naming the option.
    pub fn check(&self) -> Result<(), crate::error::Error> {
        let bad = |key: &'static str, v: f64| {
            Err(crate::error::Error::Options {
                key,
                problem: format!("option {key} = {v}: must be finite and positive"),
            })
        };
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return bad("t_end", self.t_end);
        }
        if let Some(r) = self.rate {
            if !(r.is_finite() && r > 0.0) {
                return bad("rate", r);
            }
        }
        if !(self.rtol.is_finite() && self.rtol > 0.0 && self.rtol < 1.0) {
            return Err(crate::error::Error::Options {
                key: "rtol",
                problem: format!("option rtol = {}: must lie in (0, 1)", self.rtol),
            });
        }
        if !(self.atol.is_finite() && self.atol > 0.0) {
            return bad("atol", self.atol);
        }
        if let Some(h) = self.max_step {
            if !(h.is_finite() && h > 0.0) {
                return bad("max_step", h);
            }
        }
        if self.max_steps == Some(0) {
            return Err(crate::error::Error::Options {
                key: "max_steps",
                problem: "option max_steps = 0: must be at least 1".into(),
            });
        }
        if let Some(w) = &self.wear {
            w.check()?;
        }
        if self.decimate == 0 {
            return Err(crate::error::Error::Options {
                key: "decimate",
                problem: "option decimate = 0: must be at least 1".into(),
            });
        }
        Ok(())
    }
}
