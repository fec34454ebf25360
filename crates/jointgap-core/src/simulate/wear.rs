//! Archard wear accumulated in a run (docs/wear.md): for each dry journal in its bearing
//! (a planar revolute clearance joint, a spatial cylindrical one's two ends), the
//! integral `int p ds` of the contact pressure over the sliding distance on an angular
//! grid of the bearing (in its body's frame) and of the journal (in its own, which turns
//! under the contact), and the integral `int F_n ds` of the normal force.
//!
//! Archard's law (Archard 1953) makes the worn depth `h = k int p ds`, linear in the
//! dimensional wear coefficient `k` [1/Pa]: the run accumulates the integrals per unit
//! `k`, and whoever knows `k` multiplies (docs/wear.md).

use serde::{Deserialize, Serialize};

use super::kind::{Integrand, Kind};
use crate::error::Error;
use crate::math::Vec2;
use crate::mechanics::contact::geometry::{CylinderBearing, Worn};
use crate::mechanics::contact::spatial::SpatialClearance;
use crate::mechanics::contact::{self, ClearanceJoint, ClearanceRevolute, ContactState, WearContact};
use crate::mechanics::planar_body::BodyState;
use crate::mechanics::spatial::body::BodyState as SpatialState;
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
    // A worn journal resting on several rims: their forces together, and their mean
    // sliding speed weighted by force, at the deepest point.
    let (f_n, load) = points.iter().fold((0.0, 0.0), |(f, l), q| {
        let (f_n, _) = c.force(q, state.onset_for(q.penetration_rate));
        let f_n = f_n.max(0.0);
        (f + f_n, l + f_n * q.slip.norm())
    });
    (f_n > 0.0).then(|| {
        let alpha = p.normal.y.atan2(p.normal.x);
        let e = c.geometry.eccentricity(bearing, journal);
        Integrand {
            f_n,
            speed: load / f_n,
            bearing_angle: alpha - bearing.phi(),
            journal_angle: alpha - journal.phi(),
            spins: (bearing.omega, journal.omega),
            eccentricity: e.norm(),
            lead: wrap(e.y.atan2(e.x) - alpha),
        }
    })
}

/// The wear integrands of the two journal ends of the dry cylindrical joint `c`
/// (geometry `g`) at the bodies' states `(bearing, journal)`, the ends' points in
/// contact states `states`, into `out`: `None` for an end apart or unloaded. Angles and
/// the eccentricity are the section's through the end ([`CylinderBearing::section`]);
/// the spins are each body's about the bearing's axis; the force is the end's over its
/// share of the length.
pub fn cylinder_integrands(
    c: &SpatialClearance,
    g: &CylinderBearing,
    (bearing, journal): (&SpatialState, &SpatialState),
    states: &[ContactState],
    out: &mut [Option<Integrand>],
) {
    let points = c.contacts(bearing, journal, c.reach());
    let section = g.section(bearing, journal);
    let offsets = g.end_offsets(bearing, journal);
    let axis = bearing.rotate(&g.u_bearing);
    for (end, out) in out.iter_mut().enumerate() {
        let state = &states[end];
        let mut rims = points.iter().filter(|p| p.index == end).peekable();
        let Some(&&p) = rims.peek() else {
            *out = None;
            continue;
        };
        let (f_n, load) = rims.fold((0.0, 0.0), |(f, l), q| {
            let (f_n, _) = c.force(q, state.onset_for(q.penetration_rate));
            let f_n = f_n.max(0.0);
            (f + f_n, l + f_n * q.slip.norm())
        });
        *out = (f_n > 0.0).then(|| {
            let alpha = section.angle(&p.normal);
            let e = section.of(&offsets[end]);
            Integrand {
                f_n: f_n / CylinderBearing::END_SHARE,
                speed: load / f_n,
                bearing_angle: alpha,
                journal_angle: alpha - section.journal_turn,
                spins: (bearing.omega_global().dot(&axis), journal.omega_global().dot(&axis)),
                eccentricity: e.norm(),
                lead: wrap(e.y.atan2(e.x) - alpha),
            }
        });
    }
}

/// One joint's accumulation.
struct Accumulating {
    /// The joint's index among the run's clearance joints.
    clearance: usize,
    /// Its first contact point's slot among the run's contact states.
    slot: usize,
    /// Its line contact.
    contact: WearContact,
    /// Bearing and journal radii [m].
    radii: (f64, f64),
    /// Radial clearance [m].
    clearance_gap: f64,
    /// The parts' profiles in the run (round without wear tables).
    profiles: Worn,
    /// The part of the length each point stands for ([`super::kind::Wearing::share`]).
    share: f64,
    /// What it has accumulated.
    out: JointWear,
    /// Each wearing point's integrand at the last accepted state.
    last: Vec<Option<Integrand>>,
    /// The same at the state a step reached (the step's scratch).
    now: Vec<Option<Integrand>>,
}

/// The wear a run accumulates: one grid pair per dry journal in its bearing.
pub struct Wear {
    joints: Vec<Accumulating>,
    cells: usize,
    start: f64,
}

impl Wear {
    /// The accumulators of `sys`'s journals in their bearings on grids of `opts.cells`;
    /// an error names a joint that lacks what wear needs (its length).
    pub fn new<K: Kind>(sys: &System<K>, opts: &WearOptions) -> Result<Self, Error> {
        opts.check()?;
        let n = opts.cells;
        let mut joints = Vec::new();
        for (k, c, range) in contact::slots(&sys.clearances) {
            let Some(w) = K::wears(c) else { continue };
            let contact = w.contact.clone().map_err(|problem| Error::Options { key: "wear", problem })?;
            joints.push(Accumulating {
                clearance: k,
                slot: range.start,
                contact,
                radii: w.radii,
                clearance_gap: w.clearance,
                profiles: w.worn.cloned().unwrap_or_else(Worn::round),
                share: w.share,
                out: JointWear::none(w.name, n),
                last: vec![None; w.points],
                now: vec![None; w.points],
            });
        }
        Ok(Wear { joints, cells: n, start: opts.start })
    }

    /// At the start of a run, the state `(q, v)` with contact states `states`: the
    /// integrands the first step starts from.
    pub fn start<K: Kind>(&mut self, sys: &System<K>, states: &[ContactState], q: &[f64], v: &[f64]) {
        for j in &mut self.joints {
            let points = j.last.len();
            K::wear_integrands(sys, j.clearance, &states[j.slot..j.slot + points], q, v, &mut j.last);
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
            let points = j.last.len();
            let mut now = std::mem::take(&mut j.now);
            K::wear_integrands(sys, j.clearance, &states[j.slot..j.slot + points], q, v, &mut now);
            for (point, now) in now.iter().enumerate() {
                let last = std::mem::replace(&mut j.last[point], *now);
                step_point(j, (last, *now), (t, dt), self.start, half_cell);
            }
            j.now = now;
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

/// One wearing point's share of a step of `dt` [s] ending at `t`, its integrands at the
/// step's ends `(last, now)` ([`Wear::step`]); nothing counts before `start`.
fn step_point(
    j: &mut Accumulating,
    (last, now): (Option<Integrand>, Option<Integrand>),
    (t, dt): (f64, f64),
    start: f64,
    half_cell: f64,
) {
    let (a, b) = match (last, now) {
        (None, None) => return,
        (Some(a), None) => (a, Integrand { f_n: 0.0, speed: 0.0, ..a }),
        (None, Some(b)) => (Integrand { f_n: 0.0, speed: 0.0, ..b }, b),
        (Some(a), Some(b)) => (a, b),
    };
    // Each part's turn under the contact, told apart from its turn less whole
    // revolutions by the part's spin (the contact's own direction turns by less than
    // half a revolution in a step).
    let spun = |ends: (f64, f64)| -0.5 * (ends.0 + ends.1) * dt;
    let turn = |from: f64, to: f64, spin: f64| spin + wrap(to - from - spin);
    let turn = (
        turn(a.bearing_angle, b.bearing_angle, spun((a.spins.0, b.spins.0))),
        turn(a.journal_angle, b.journal_angle, spun((a.spins.1, b.spins.1))),
    );
    // Sub-steps at most half a cell apart, and a quarter of the contact's half width on
    // the bearing (the narrower angle): the deposits then sample the pressure's path
    // finely enough that a cell wider than the contact gets its share whatever the step
    // (never closer than 1/64 of half a cell, for a contact at its first touch).
    let narrowest = j.contact.half_width(a.f_n.max(b.f_n)) / j.radii.0;
    let spacing = half_cell.min(0.25 * narrowest).max(half_cell / 64.0);
    let swept = turn.0.abs().max(turn.1.abs());
    let m = ((swept / spacing).ceil() as usize).max(1);
    // The point's own load, its part of the length's.
    let (load_a, load_b) = (j.share * a.f_n * a.speed, j.share * b.f_n * b.speed);
    let h = dt / m as f64;
    for i in 0..=m {
        let s = i as f64 / m as f64;
        // The composite trapezoid's weight is the time the point stands for, `[at - h/2,
        // at + h/2]` within the step; only its part after the start counts.
        let at = t - (1.0 - s) * dt;
        let from = if i == 0 { at } else { at - 0.5 * h }.max(start);
        let to = if i == m { at } else { at + 0.5 * h };
        let weight = to - from;
        if weight <= 0.0 {
            continue;
        }
        let f_n = a.f_n + s * (b.f_n - a.f_n);
        let load = (load_a + s * (load_b - load_a)) * weight;
        if f_n > 0.0 && load > 0.0 {
            let at = Placement {
                bearing: a.bearing_angle + s * turn.0,
                journal: a.journal_angle + s * turn.1,
                eccentricity: a.eccentricity + s * (b.eccentricity - a.eccentricity),
                lead: a.lead + s * wrap(b.lead - a.lead),
            };
            deposit(j, f_n, load, &at, half_cell);
        }
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

/// Where the parts touch at one instant of a step, in each part's frame.
struct Placement {
    /// The contact normal's angle in the bearing's frame [rad].
    bearing: f64,
    /// The same normal's angle in the journal's frame [rad].
    journal: f64,
    /// `|e|` [m].
    eccentricity: f64,
    /// The eccentricity's angle less the normal's [rad].
    lead: f64,
}

/// The most samples of the pressure at one instant.
const MAX_SAMPLES: usize = 1024;

/// Adds to joint `j`'s integrals a load `F_n ds` [N m] (the normal force `f_n` [N] over
/// a sliding distance) at placement `at`: to `int F_n ds`, and to each part's cells the
/// pressure times the distance (docs/wear.md, "Contact pressure").
///
/// The pressure is an elastic foundation's (Winkler; Johnson 1985, section 4.2) over the
/// parts' overlap `delta(alpha)` ([`Worn::overlap`]): proportional to how far the
/// overlap stands above `delta_max - d` in each direction `alpha`,
/// `p(alpha) ~ max(0, delta(alpha) - delta_max + d)`, scaled to the force. The depth `d
/// = |e| b^2 / (2 R_B^2)` gives round parts Hertz's half width `b` on the bearing
/// ([`WearContact::half_width`]): a parabola of peak `3 F / (4 b L)`. On worn parts the
/// pressure spreads over the arc where the worn surfaces conform, and reaches every rim
/// of a pocket that stands within `d` of the deepest one, so that a pocket widens as it
/// deepens instead of growing narrower than the journal that wears it.
///
/// The pressure is sampled about the contact normal at a sixteenth of `b / R_B` (and a
/// quarter of `half_cell`), each sample standing for its interval; the samples' weights
/// are normalised, so that the cells' sum is the load whatever the sampling.
fn deposit(j: &mut Accumulating, f_n: f64, load: f64, at: &Placement, half_cell: f64) {
    j.out.load_distance += load;
    let (r_b, r_j) = j.radii;
    let band = j.contact.half_width(f_n) / r_b;
    let depth = 0.5 * at.eccentricity * band * band;
    // The bearing's frame: the journal's turned by the difference of the normal's angles.
    let beta = at.bearing + at.lead;
    let e = Vec2::new(beta.cos(), beta.sin()) * at.eccentricity;
    let phis = (0.0, at.bearing - at.journal);
    let overlap = |alpha: f64| j.profiles.overlap(e, phis, j.clearance_gap, alpha).0;
    let top = overlap(at.bearing);
    let half = j.profiles.window(e, j.clearance_gap, top - depth);
    let h = (band / 16.0).min(0.5 * half_cell).max(2.0 * half / MAX_SAMPLES as f64);
    // Samples at `at.bearing + k h` over `beta +- half`, one of them at the normal.
    let (first, last) = (((beta - half - at.bearing) / h).ceil(), ((beta + half - at.bearing) / h).floor());
    let mut samples = [0.0; MAX_SAMPLES + 2];
    let count = ((last - first) as usize + 1).min(samples.len());
    let mut deepest = top;
    for (i, x) in samples[..count].iter_mut().enumerate() {
        *x = overlap(at.bearing + (first + i as f64) * h);
        deepest = deepest.max(*x);
    }
    let floor = deepest - depth;
    let total: f64 = samples[..count].iter().map(|x| (x - floor).max(0.0)).sum();
    if total <= 0.0 {
        return;
    }
    let per_length = load / j.contact.length;
    for (i, x) in samples[..count].iter().enumerate() {
        let share = (x - floor).max(0.0) / total;
        if share > 0.0 {
            let offset = (first + i as f64) * h;
            spread(&mut j.out.bearing_depth, at.bearing + offset, h, share * per_length / r_b);
            spread(&mut j.out.journal_depth, at.journal + offset, h, share * per_length / r_j);
        }
    }
}

/// Adds `load_per_rad` (a wear per unit `k` times the angle it covers) spread evenly over the angles
/// `centre +- width / 2` [rad] to the cells of `grid` (cell `c` centred on `2 pi c / N`,
/// periodic) as cell averages: each cell gets its share of the interval over its angle,
/// so that the cells' sum times their angle is `load_per_rad`.
fn spread(grid: &mut [f64], centre: f64, width: f64, load_per_rad: f64) {
    let n = grid.len();
    let step = std::f64::consts::TAU / n as f64;
    let (lo, hi) = ((centre - 0.5 * width) / step + 0.5, (centre + 0.5 * width) / step + 0.5);
    let scale = load_per_rad / (step * (hi - lo));
    let mut c = lo.floor();
    while c < hi {
        let covered = hi.min(c + 1.0) - lo.max(c);
        grid[(c as i64).rem_euclid(n as i64) as usize] += covered * scale;
        c += 1.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// A spread keeps its load on any grid (across the grid's seam at 0 too), puts it in
    /// the cells the interval covers, and shares it by the covered angle.
    #[test]
    fn spread_keeps_the_load() {
        for (n, centre, width) in [(36, 0.0, 0.05), (360, 3.0, 0.001), (8, -0.1, 0.3), (720, 6.27, 1e-4)] {
            let mut grid = vec![0.0; n];
            spread(&mut grid, centre, width, 2.5);
            let step = TAU / n as f64;
            let total: f64 = grid.iter().sum::<f64>() * step;
            assert!((total - 2.5).abs() < 1e-13, "{n}: {total}");
            for (c, g) in grid.iter().enumerate() {
                let d = wrap(c as f64 * step - centre);
                if d.abs() > 0.5 * (width + step) {
                    assert_eq!(*g, 0.0, "{n}: cell {c}");
                }
            }
        }
        // An interval across two cells' border at a quarter of its width.
        let mut grid = vec![0.0; 4];
        spread(&mut grid, PI / 4.0 + 0.25 * 0.2 - 0.1 + 0.1, 0.2, 1.0);
        let step = TAU / 4.0;
        assert!((grid[0] * step - 0.25).abs() < 1e-12 && (grid[1] * step - 0.75).abs() < 1e-12, "{grid:?}");
    }

    /// A joint of radii 10 mm and 9.5 mm, 10 mm long, on grids of `cells`, worn as given.
    fn joint(cells: usize, profiles: Worn) -> Accumulating {
        Accumulating {
            clearance: 0,
            slot: 0,
            contact: WearContact { length: 0.01, contact_modulus: 1e11, effective_radius: 0.19 },
            radii: (0.01, 0.0095),
            clearance_gap: 0.0005,
            profiles,
            share: 1.0,
            out: JointWear::none("c", cells),
            last: vec![None],
            now: vec![None],
        }
    }

    /// Round parts: the foundation's pressure on the bearing is a parabola of Hertz's
    /// half width `b` and peak `3 F / (4 b L)`, `b = sqrt(4 F R* / (pi L E*))`, centred
    /// on the normal; the journal takes the same load at its own angle; both sum to the
    /// load.
    #[test]
    fn round_parts_wear_under_a_parabola_of_hertz_width() {
        let cells = 7200;
        let mut j = joint(cells, Worn::round());
        let (f_n, slid) = (2000.0, 1e-3);
        let b = j.contact.half_width(f_n);
        let penetration = 1e-5;
        let at = Placement { bearing: 1.0, journal: -2.0, eccentricity: 0.0005 + penetration, lead: 0.0 };
        deposit(&mut j, f_n, f_n * slid, &at, PI / cells as f64);
        let step = TAU / cells as f64;
        let (r_b, length) = (0.01, 0.01);
        let peak = 3.0 * f_n / (4.0 * b * length) * slid;
        for (c, d) in j.out.bearing_depth.iter().enumerate() {
            let s = wrap(c as f64 * step - 1.0) * r_b;
            let parabola = if s.abs() < b { peak * (1.0 - (s / b).powi(2)) } else { 0.0 };
            // Within the sampling's resolution (b / 16 against b's parabola).
            assert!((d - parabola).abs() < 0.02 * peak, "cell {c}: {d:e} vs {parabola:e}");
        }
        let centre = (1.0 / step).round() as usize;
        assert!((j.out.bearing_depth[centre] / peak - 1.0).abs() < 5e-3, "{:e}", j.out.bearing_depth[centre]);
        let sum = |g: &[f64], r: f64| g.iter().sum::<f64>() * step * r * length;
        assert!((sum(&j.out.bearing_depth, r_b) / (f_n * slid) - 1.0).abs() < 1e-12);
        assert!((sum(&j.out.journal_depth, 0.0095) / (f_n * slid) - 1.0).abs() < 1e-12);
        let journal_centre = ((TAU - 2.0) / step).round() as usize;
        let max = j.out.journal_depth.iter().cloned().fold(0.0, f64::max);
        assert_eq!(j.out.journal_depth[journal_centre], max);
    }

    /// A journal pressed across a pocket narrower than itself (a bearing worn 20 um deep
    /// over 6 degrees at 90 degrees, 3 table points, the journal's centre above it) touches
    /// the pocket's two rims, not its bottom: the wear goes to the rims, equally, and none
    /// to the pocket's middle; the overlap's largest value is at a rim.
    #[test]
    fn a_pocket_narrower_than_the_journal_wears_at_its_rims() {
        let n = 360;
        let table: Vec<f64> = (0..n)
            .map(|k| {
                let d = (k as f64 - 90.0).abs();
                if d <= 3.0 {
                    2e-5 * (1.0 - (d / 3.0).powi(2))
                } else {
                    0.0
                }
            })
            .collect();
        let worn =
            Worn::new(crate::error::Named::joint("c"), (Some(&table[..]), None), 0.0095).unwrap().unwrap();
        let mut j = joint(3600, worn);
        let e = 0.0005 + 2e-6;
        let at = Placement { bearing: PI / 2.0, journal: 0.0, eccentricity: e, lead: 0.0 };
        deposit(&mut j, 500.0, 1.0, &at, PI / 3600.0);
        let cell = |deg: f64| (deg * 10.0).round() as usize;
        assert_eq!(j.out.bearing_depth[cell(90.0)], 0.0, "the pocket's bottom");
        let (left, right) =
            (&j.out.bearing_depth[cell(85.0)..cell(90.0)], &j.out.bearing_depth[cell(90.0)..cell(95.0)]);
        let (l, r): (f64, f64) = (left.iter().sum(), right.iter().sum());
        assert!(l > 0.0 && (l / r - 1.0).abs() < 1e-6, "rims {l:e} {r:e}");
    }
}
