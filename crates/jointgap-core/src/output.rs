//! Run results: named channels sampled in time, run statistics and status.

use serde::Serialize;

/// How a run ended.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Status {
    /// Reached the end time.
    Finished,
    /// Stopped early; the result holds everything computed up to `time`.
    Failed {
        /// Simulated time at which the run stopped [s].
        time: f64,
        /// Why it stopped.
        reason: String,
    },
    /// Stopped by its caller (Ctrl-C); the result holds everything computed up to `time`.
    Interrupted {
        /// Simulated time at which the run stopped [s].
        time: f64,
    },
}

/// Counters of one run.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct RunStats {
    /// Accepted integration steps.
    pub accepted_steps: usize,
    /// Rejected integration steps (error test or Newton failure).
    pub rejected_steps: usize,
    /// Evaluations of the equations of motion (each one an augmented solve).
    pub rhs_evaluations: usize,
    /// Jacobian evaluations of the implicit method.
    pub jacobian_evaluations: usize,
    /// Newton iterations of the implicit method, converged or not.
    pub newton_iterations: usize,
    /// Position and velocity projections onto the constraint manifold.
    pub projections: usize,
    /// Located contact onsets and separations.
    pub events: usize,
    /// Integrator that ran.
    pub method: String,
    /// Wall-clock time of the run [s].
    pub wall_time: f64,
    /// Time per stage, when the run was asked to measure it.
    pub profile: Option<crate::profile::Profile>,
    /// How the rows and forces ran: compiled to native code (paths, compile time,
    /// evaluations each way) or interpreted, and why (docs/compiled.md).
    pub compiled: String,
    /// Seconds spent compiling native code during the run (part of `wall_time`).
    pub compile_time: f64,
}

/// One impact of a clearance joint: from the located contact onset to separation.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Impact {
    /// Time of the contact onset [s].
    pub onset_time: f64,
    /// Penetration rate at onset, the approach speed delta_dot(-) [m/s].
    pub onset_speed: f64,
    /// Largest normal force during the contact [N].
    pub peak_force: f64,
    /// Largest penetration during the contact [m].
    pub max_penetration: f64,
    /// Time from onset to separation [s]; `None` if still in contact at the end.
    pub duration: Option<f64>,
}

/// The impacts of one contact point of a clearance joint, in time order.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct JointImpacts {
    /// Joint name.
    pub joint: String,
    /// The contact point, numbered from 1, of a joint whose geometry has several (whose
    /// channels are `<joint>.p<point>.<quantity>`); `None` for a joint of one point,
    /// whose impacts are the joint's.
    pub point: Option<usize>,
    /// Its impacts.
    pub impacts: Vec<Impact>,
    /// Time spent in free flight, impact and continuous contact [s], summed over the
    /// accepted steps (each step in the mode it starts in): exact where contact begins
    /// and ends, since those end steps, whatever the output rate.
    pub mode_time: [f64; 3],
}

/// A clearance joint's contact data as the engine resolved them: the radii it was not
/// given and the stiffness computed from the materials, which calibration and plots need.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ClearanceData {
    /// Joint name.
    pub joint: String,
    /// Bearing radius R_B [m].
    pub bearing_radius: f64,
    /// Journal radius R_J [m].
    pub journal_radius: f64,
    /// Radial clearance c = R_B - R_J [m].
    pub clearance: f64,
    /// Contact stiffness K [N/m^n].
    pub stiffness: f64,
    /// Exponent n of the normal law.
    pub exponent: f64,
}

/// The outcome of a run: `data[k][i]` is channel `names[k]` at `time[i]`.
#[derive(Debug, Clone, Serialize)]
pub struct SimResult {
    /// Sample times [s].
    pub time: Vec<f64>,
    /// For a run that records every step as well as the samples at its rate: the indices
    /// (into `time`) of the output samples, at `k / rate` and at the end time. `None`
    /// when every record is an output sample (or, without a rate, a step).
    pub samples: Option<Vec<usize>>,
    /// Channel names, `<element>.<quantity>`, in model order.
    pub names: Vec<String>,
    /// One vector per channel, SI units.
    pub data: Vec<Vec<f64>>,
    /// Largest absolute value of each channel over its samples, and over every accepted
    /// step with `step_peaks` (or `every_step`, whatever the decimation keeps).
    pub peaks: Vec<f64>,
    /// Counters.
    pub stats: RunStats,
    /// Finished, or failed with time and reason.
    pub status: Status,
    /// Non-fatal notes (e.g. redundant constraints removed).
    pub warnings: Vec<String>,
    /// Impacts of each contact point of the clearance joints, joint after joint in model
    /// order.
    pub impacts: Vec<JointImpacts>,
    /// Contact data of each clearance joint, in model order.
    pub clearances: Vec<ClearanceData>,
    /// The wear each revolute clearance joint accumulated, in model order, when the run
    /// was asked for it (`SimOptions::wear`); a run that stopped early has what it
    /// accumulated until then.
    pub wear: Vec<JointWear>,
}

/// The Archard wear one revolute clearance joint accumulated in a run, per unit wear
/// coefficient `k` [1/Pa] (docs/wear.md): a part's worn depth is `k` times its
/// `*_depth`, its worn volume `k` times its `*_volume`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct JointWear {
    /// Joint name.
    pub joint: String,
    /// Angles of the grid's cell centres `2 pi c / N` in each part's body frame, from its
    /// x axis about the joint's point [rad]: the angles of a wear table.
    pub angles: Vec<f64>,
    /// `int p ds` over the bearing's cells (the cell average of the pressure) [Pa m].
    pub bearing_depth: Vec<f64>,
    /// `int p ds` over the journal's cells [Pa m].
    pub journal_depth: Vec<f64>,
    /// `int F_n ds`, the normal force over the sliding distance [N m]: `k` times it is
    /// the volume each part loses.
    pub load_distance: f64,
    /// The bearing's worn volume per unit `k`, `sum depth R_B dtheta L` [N m].
    pub bearing_volume: f64,
    /// The journal's, `sum depth R_J dtheta L` [N m].
    pub journal_volume: f64,
}

impl JointWear {
    /// Nothing accumulated yet for joint `joint` on grids of `cells` cells.
    pub fn none(joint: &str, cells: usize) -> Self {
        let step = std::f64::consts::TAU / cells as f64;
        JointWear {
            joint: joint.to_owned(),
            angles: (0..cells).map(|i| step * i as f64).collect(),
            bearing_depth: vec![0.0; cells],
            journal_depth: vec![0.0; cells],
            load_distance: 0.0,
            bearing_volume: 0.0,
            journal_volume: 0.0,
        }
    }
}

impl SimResult {
    /// The samples of one channel, if present.
    pub fn channel(&self, name: &str) -> Option<&[f64]> {
        self.names.iter().position(|n| n == name).map(|k| self.data[k].as_slice())
    }
}
