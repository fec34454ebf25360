//! Archard wear accumulated in a run (docs/wear.md): for each dry revolute clearance
//! joint, the integral `int p ds` of the contact pressure over the sliding distance on an
//! angular grid of the bearing (in its body's frame) and of the journal (in its own, which
//! turns under the contact), and the integral `int F_n ds` of the normal force.
//!
//! Archard's law (Archard 1953) makes the worn depth `h = k int p ds`, linear in the
//! dimensional wear coefficient `k` [1/Pa]: the run accumulates the integrals per unit
//! `k`, and whoever knows `k` multiplies (docs/wear.md).

use serde::{Deserialize, Serialize};

use super::kind::{Integrand, Kind};
use crate::error::Error;
use crate::mechanics::contact::{self, ClearanceJoint, ClearanceRevolute, ContactState, WearContact};
use crate::mechanics::planar::BodyState;
use crate::output::JointWear;
use crate::system::System;

/// The fewest cells of a wear grid: as many as a wear table takes, so that the grid's
/// depths can be handed back as the joint's profile
/// ([`crate::mechanics::contact::geometry::worn::MIN_POINTS`]).
pub const MIN_CELLS: usize = crate::mechanics::contact::geometry::worn::MIN_POINTS;

/// The wear option of a run.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WearOptions {
    /// Cells of each part's angular grid, at least [`MIN_CELLS`]: cell `c` is centred
    /// on the angle `2 pi c / cells` of its body's frame.
    pub cells: usize,
    /// Time [s] from which the wear counts (0 by default): a mechanism's wear per cycle
    /// is that of its steady cycles, after its start-up.
    #[serde(default)]
    pub start: f64,
}

impl WearOptions {
    /// Rejects a grid too coarse to be a wear table.
    pub fn check(&self) -> Result<(), Error> {
        if self.cells < MIN_CELLS {
            return Err(Error::Options {
                key: "wear",
                problem: format!(
                    "option wear.cells = {}: a wear grid has at least {MIN_CELLS} cells",
                    self.cells
                ),
            });
        }
        if !(self.start.is_finite() && self.start >= 0.0) {
            return Err(Error::Options {
                key: "wear",
                problem: format!("option wear.start = {} s: must be zero or positive", self.start),
            });
        }
        Ok(())
    }
}

/// The wear integrand of joint `c` at the bodies' states `(bearing, journal)`, its point
/// in contact state `state`: `None` apart or unloaded.
pub fn integrand(
    c: &ClearanceRevolute,
    bearing: &BodyState,
    journal: &BodyState,
    state: &ContactState,
) -> Option<Integrand> {
    let points = c.contacts(bearing, journal, c.reach());
    let p = points.first()?;
    let (f_n, _) = c.force(p, state.onset_for(p.penetration_rate));
    (f_n > 0.0).then(|| {
        let alpha = p.normal.y.atan2(p.normal.x);
        Integrand {
            f_n,
            speed: p.slip.norm(),
            bearing_angle: alpha - bearing.phi(),
            journal_angle: alpha - journal.phi(),
            spins: (bearing.omega, journal.omega),
        }
    })
}

/// One joint's accumulation.
struct Accumulating {
    /// The joint's index among the run's clearance joints.
    clearance: usize,
    /// Its contact point's slot among the run's contact states.
    slot: usize,
    /// Its line contact.
    contact: WearContact,
    /// Bearing and journal radii [m].
    radii: (f64, f64),
    /// What it has accumulated.
    out: JointWear,
    /// The integrand at the last accepted state.
    last: Option<Integrand>,
}

/// The wear a run accumulates: one grid pair per dry revolute clearance joint.
pub struct Wear {
    joints: Vec<Accumulating>,
    cells: usize,
    start: f64,
}

impl Wear {
    /// The accumulators of `sys`'s revolute clearance joints on grids of `opts.cells`;
    /// an error names a joint that lacks what wear needs (its length).
    pub fn new<K: Kind>(sys: &System<K>, opts: &WearOptions) -> Result<Self, Error> {
        opts.check()?;
        let n = opts.cells;
        let mut joints = Vec::new();
        for (k, c, range) in contact::slots(&sys.clearances) {
            let Some(c) = K::wears(c) else { continue };
            let contact =
                c.wear_contact.clone().map_err(|problem| Error::Options { key: "wear", problem })?;
            let step = std::f64::consts::TAU / n as f64;
            joints.push(Accumulating {
                clearance: k,
                slot: range.start,
                contact,
                radii: (c.geometry.r_bearing, c.geometry.r_journal),
                out: JointWear {
                    joint: c.name.clone(),
                    angles: (0..n).map(|i| step * i as f64).collect(),
                    bearing_depth: vec![0.0; n],
                    journal_depth: vec![0.0; n],
                    load_distance: 0.0,
                    bearing_volume: 0.0,
                    journal_volume: 0.0,
                },
                last: None,
            });
        }
        Ok(Wear { joints, cells: n, start: opts.start })
    }

    /// At the start of a run, the state `(q, v)` with contact states `states`: the
    /// integrands the first step starts from.
    pub fn start<K: Kind>(&mut self, sys: &System<K>, states: &[ContactState], q: &[f64], v: &[f64]) {
        for j in &mut self.joints {
            j.last = K::wear_integrand(sys, j.clearance, &states[j.slot], q, v);
        }
    }

    /// After an accepted step of `dt` [s] to the state `(q, v)` with contact states
    /// `states`: the step's share of each integral, by the trapezoidal rule on the
    /// step's two ends (second order in the step; a contact's onset or separation ends
    /// a step, where the force is zero, and an end apart counts as that). A journal can
    /// turn through many cells in one step: the step's share is laid along the contact's
    /// path, on sub-steps that move it by at most half a cell on either part (and a quarter
    /// of the contact's half width), each part's
    /// contact angle, the normal force (for the contact's width) and the integrand `F_n
    /// |v_t|` interpolated linearly between the ends, with composite trapezoid weights.
    /// Being linear, the integrand's composite sum is the plain trapezoid's, so the
    /// totals do not depend on the grid.
    ///
    /// The step ends at time `t`; the time before the option's start counts nothing (a
    /// step across the start counts the part of each sub-step's weight after it).
    pub fn step<K: Kind>(
        &mut self,
        sys: &System<K>,
        states: &[ContactState],
        (t, dt): (f64, f64),
        q: &[f64],
        v: &[f64],
    ) {
        let half_cell = std::f64::consts::PI / self.cells as f64;
        for j in &mut self.joints {
            let now = K::wear_integrand(sys, j.clearance, &states[j.slot], q, v);
            let ends = match (j.last, now) {
                (None, None) => None,
                (Some(a), None) => Some((a, Integrand { f_n: 0.0, speed: 0.0, ..a })),
                (None, Some(b)) => Some((Integrand { f_n: 0.0, speed: 0.0, ..b }, b)),
                (Some(a), Some(b)) => Some((a, b)),
            };
            if let Some((a, b)) = ends {
                // Each part's turn under the contact, told apart from its turn less
                // whole revolutions by the part's spin (the contact's own direction
                // turns by less than half a revolution in a step).
                let spun = |ends: (f64, f64)| -0.5 * (ends.0 + ends.1) * dt;
                let turn = |from: f64, to: f64, spin: f64| spin + wrap(to - from - spin);
                let turn = (
                    turn(a.bearing_angle, b.bearing_angle, spun((a.spins.0, b.spins.0))),
                    turn(a.journal_angle, b.journal_angle, spun((a.spins.1, b.spins.1))),
                );
                // Sub-steps at most half a cell apart, and a quarter of the contact's
                // half width on the bearing (the narrower angle): the deposits then
                // sample the pressure's path finely enough that a cell wider than the
                // contact gets its share whatever the step (never closer than 1/64 of
                // half a cell, for a contact at its first touch).
                let narrowest = j.contact.half_width(a.f_n.max(b.f_n)) / j.radii.0;
                let spacing = half_cell.min(0.25 * narrowest).max(half_cell / 64.0);
                let swept = turn.0.abs().max(turn.1.abs());
                let m = ((swept / spacing).ceil() as usize).max(1);
                let (load_a, load_b) = (a.f_n * a.speed, b.f_n * b.speed);
                let h = dt / m as f64;
                for i in 0..=m {
                    let s = i as f64 / m as f64;
                    // The composite trapezoid's weight is the time the point stands
                    // for, `[at - h/2, at + h/2]` within the step; only its part after
                    // the start counts.
                    let at = t - (1.0 - s) * dt;
                    let from = if i == 0 { at } else { at - 0.5 * h }.max(self.start);
                    let to = if i == m { at } else { at + 0.5 * h };
                    let weight = to - from;
                    if weight <= 0.0 {
                        continue;
                    }
                    let f_n = a.f_n + s * (b.f_n - a.f_n);
                    let load = (load_a + s * (load_b - load_a)) * weight;
                    if f_n > 0.0 && load > 0.0 {
                        deposit(j, f_n, load, (a.bearing_angle + s * turn.0, a.journal_angle + s * turn.1));
                    }
                }
            }
            j.last = now;
        }
    }

    /// What each joint accumulated, with its worn volumes per unit `k`.
    pub fn finish(self) -> Vec<JointWear> {
        self.joints
            .into_iter()
            .map(|j| {
                let arc = std::f64::consts::TAU / self.cells as f64 * j.contact.length;
                let volume = |depth: &[f64], r: f64| depth.iter().sum::<f64>() * r * arc;
                JointWear {
                    bearing_volume: volume(&j.out.bearing_depth, j.radii.0),
                    journal_volume: volume(&j.out.journal_depth, j.radii.1),
                    ..j.out
                }
            })
            .collect()
    }
}

/// The angle `x` [rad] brought into `(-pi, pi]`: the shorter way between two angles.
fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(std::f64::consts::TAU);
    if y > std::f64::consts::PI {
        y - std::f64::consts::TAU
    } else {
        y
    }
}

/// Adds to joint `j`'s integrals a load `F_n ds` [N m] (the normal force `f_n` [N] over
/// a sliding distance) at the contact angles `(bearing, journal)` [rad]: to `int F_n ds`,
/// and to each part's cells the cell averages of the Hertz pressure times the distance.
fn deposit(j: &mut Accumulating, f_n: f64, load: f64, (bearing, journal): (f64, f64)) {
    j.out.load_distance += load;
    let half_width = j.contact.half_width(f_n);
    let per_length = load / j.contact.length;
    spread(&mut j.out.bearing_depth, bearing, half_width / j.radii.0, per_length / j.radii.0);
    spread(&mut j.out.journal_depth, journal, half_width / j.radii.1, per_length / j.radii.1);
}

/// Adds to the cells of `grid` (cell `c` centred on `2 pi c / N`, periodic) the cell
/// averages of the elliptical pressure of a Hertz line contact (Johnson 1985, eq. 5.40),
/// `p(s) = 2 F / (pi b L) sqrt(1 - s^2/b^2)`, centred on angle `centre` [rad] with
/// half width `half_angle = b / R` [rad], whose integral over the angle is `load_per_rad`
/// (`F / L` times the sliding distance, over the radius): each cell gets the exact
/// integral of the pressure over its arc ([`elliptic_share`]) over its angle, so that the
/// cells' sum times their angle is `load_per_rad`, whatever the grid. A contact wider than
/// the whole circumference (no joint's) is cut to it.
fn spread(grid: &mut [f64], centre: f64, half_angle: f64, load_per_rad: f64) {
    let n = grid.len();
    let step = std::f64::consts::TAU / n as f64;
    let half_angle = half_angle.min(std::f64::consts::PI);
    let edge = |x: f64| ((x / step) + 0.5).floor();
    let (first, last) = (edge(centre - half_angle), edge(centre + half_angle));
    let scale = load_per_rad / step;
    let mut below = 0.0;
    let mut c = first;
    while c <= last {
        let upper = (c + 0.5) * step;
        let above = elliptic_share((upper - centre) / half_angle);
        let cell = (c as i64).rem_euclid(n as i64) as usize;
        grid[cell] += (above - below) * scale;
        below = above;
        c += 1.0;
    }
}

/// The share of an elliptical pressure `sqrt(1 - x^2)` on `[-1, 1]` that lies below
/// `x`: `1/2 + (x sqrt(1 - x^2) + asin x) / pi`, clamped to `[0, 1]` outside.
fn elliptic_share(x: f64) -> f64 {
    let x = x.clamp(-1.0, 1.0);
    0.5 + (x * (1.0 - x * x).sqrt() + x.asin()) / std::f64::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shares of the ellipse: half below the centre, all below its edge, and the
    /// area under `sqrt(1 - x^2)` by a midpoint sum.
    #[test]
    fn elliptic_share_is_the_ellipse_area() {
        assert_eq!(elliptic_share(-2.0), 0.0);
        assert!((elliptic_share(0.0) - 0.5).abs() < 1e-16);
        assert_eq!(elliptic_share(1.0), 1.0);
        let x = 0.37;
        let m = 100_000;
        let sum: f64 = (0..m)
            .map(|i| {
                let s = -1.0 + (x + 1.0) * (i as f64 + 0.5) / m as f64;
                (1.0 - s * s).sqrt() * (x + 1.0) / m as f64
            })
            .sum();
        assert!((elliptic_share(x) - sum / (std::f64::consts::PI / 2.0)).abs() < 1e-7);
    }

    /// A spread keeps its load on any grid (across the grid's seam at 0 too), and puts it
    /// in the cells the contact covers, symmetric about its centre.
    #[test]
    fn spread_keeps_the_load() {
        for (n, centre, half) in [(36, 0.0, 0.05), (360, 3.0, 0.05), (8, -0.1, 0.3), (720, 6.27, 1e-4)] {
            let mut grid = vec![0.0; n];
            spread(&mut grid, centre, half, 2.5);
            let step = std::f64::consts::TAU / n as f64;
            let total: f64 = grid.iter().sum::<f64>() * step;
            assert!((total - 2.5).abs() < 1e-13, "{n}: {total}");
            for (c, g) in grid.iter().enumerate() {
                let d = (c as f64 * step - centre + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                if d.abs() > half + step {
                    assert_eq!(*g, 0.0, "{n}: cell {c}");
                }
            }
        }
        // Centred on a cell's centre: its neighbours take equal shares.
        let mut grid = vec![0.0; 360];
        let step = std::f64::consts::TAU / 360.0;
        spread(&mut grid, 10.0 * step, 2.5 * step, 1.0);
        assert!(
            (grid[9] - grid[11]).abs() < 1e-12 * grid[10] && (grid[8] - grid[12]).abs() < 1e-12 * grid[10]
        );
        assert_eq!(grid[7], 0.0);
    }
}
