//! Contact events of clearance joints during a run: onsets and separations located by
//! root finding on the penetration inside each step, which change the discrete state
//! ([`ContactState`]) of each contact point, and the impact list they build. Contact
//! states, impact lists and mode times are kept per contact point, joint after joint
//! ([`contact::slots`]): a point's place in that order is its slot.

use crate::integrators::ode::DenseStep;
use crate::mechanics::contact::{self, ClearanceJoint, ContactMeasure, ContactPoint, ContactState, Mode};
use crate::mechanics::kind::BodyKind;
use crate::output::{Impact, JointImpacts};
use crate::system::System;

use super::Kind;

/// Interior points at which a step is searched for a contact change, so that a brief
/// contact inside one step is not missed.
const PROBES: usize = 8;

/// Earliest contact change inside a step: `(theta, slot)` with theta in (0, 1], the
/// first point where a contact point's penetration sign disagrees with its contact flag.
/// Located by bisection to a relative width of 1e-12 of the step.
///
/// The search probes the dense output at 8 equally spaced points and at the interior
/// extreme of each contact point's end-point model of its penetration where that model crosses
/// zero ([`screen`]), so a graze between two equally spaced points is still found. A
/// step that [`screen`] shows quiet is not searched.
///
/// The probes before the change also raise the running impacts' peak force and
/// penetration in `log`: a step that spans the peak would otherwise report only the
/// smaller values at its ends.
pub fn locate<K: Kind>(
    sys: &System<K>,
    states: &[ContactState],
    log: &mut ImpactLog<PointOf<K>>,
    step: &DenseStep,
    scratch: &mut [f64],
) -> Option<(f64, usize)> {
    if sys.clearances.is_empty() || screen(sys, states, log, step, scratch) {
        return None;
    }
    let n = sys.layout.nq();
    let differs = |s: usize, d: f64| if states[s].in_contact { d < 0.0 } else { d > 0.0 };
    let mut points = std::mem::take(&mut log.points);
    points.extend((1..=PROBES).map(|p| p as f64 / PROBES as f64));
    points.sort_by(f64::total_cmp);
    points.dedup();
    let mut lo = 0.0;
    let mut found = None;
    for &hi in &points {
        step.at(hi, scratch);
        let (q, v) = scratch.split_at(n);
        // Each point's kinematics once per probe: the search and the peaks both use them.
        let mut probed = std::mem::take(&mut log.probed);
        points_at(sys, q, v, &mut probed);
        let change = probed.iter().enumerate().position(|(s, p)| differs(s, p.penetration()));
        if change.is_none() {
            for s in (0..states.len()).filter(|&s| states[s].in_contact) {
                log.raise_peak(sys, s, &states[s], &probed[s]);
            }
        }
        log.probed = probed;
        if let Some(k) = change {
            found = Some((lo, hi, k));
            break;
        }
        lo = hi;
    }
    points.clear();
    log.points = points;
    // Bisect on point s in (lo, hi]; an earlier change of another point inside the
    // bracket is caught by the next step's search.
    let (mut a, mut b, s) = found?;
    let (k, i) = log.owners[s];
    while b - a > 1e-12 {
        let mid = 0.5 * (a + b);
        step.at(mid, scratch);
        let d = sys.contact_points(k, &scratch[..n], &scratch[n..])[i].penetration();
        if differs(s, d) {
            b = mid;
        } else {
            a = mid;
        }
    }
    Some((b, s))
}

/// Every contact point of the mechanism at `(q, v)`, by slot, into `out`.
fn points_at<K: Kind>(sys: &System<K>, q: &[f64], v: &[f64], out: &mut Vec<PointOf<K>>) {
    out.clear();
    for k in 0..sys.clearances.len() {
        out.extend_from_slice(&sys.contact_points(k, q, v));
    }
}

/// The contact point type of body kind `K`'s clearance joints.
pub type PointOf<K> = <<K as BodyKind>::Clearance as ClearanceJoint>::Point;

/// Every contact point at the last step end asked for, by slot, and that state: a step's
/// end is asked for by the step's search, by the update after the step and by the next
/// step's search, and its points are the same each time.
#[derive(Debug, Clone)]
struct StepEnd<P> {
    /// Positions then velocities, as bits (a state is the same only if its bits are).
    state: Vec<u64>,
    points: Vec<P>,
}

impl<P> Default for StepEnd<P> {
    fn default() -> Self {
        StepEnd { state: Vec::new(), points: Vec::new() }
    }
}

impl<P: Copy> StepEnd<P> {
    /// The points at `(q, v)`, computed unless they are those of the last state asked for.
    fn points<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        q: &[f64],
        v: &[f64],
    ) -> &[P] {
        let bits = q.iter().chain(v).map(|x| x.to_bits());
        if self.state.len() != q.len() + v.len() || !bits.clone().eq(self.state.iter().copied()) {
            self.state.clear();
            self.state.extend(bits);
            points_at(sys, q, v, &mut self.points);
        }
        &self.points
    }
}

/// Interior points at which a step's penetration is compared with its end-point model.
const CHECKS: [f64; 2] = [1.0 / 3.0, 2.0 / 3.0];

/// Whether the search of [`locate`] can be skipped: no contact point changes contact
/// inside the step and no point in contact can raise its impact's peaks there. Where not,
/// leaves in `log.points` the extra points to search.
///
/// Contact: each point's penetration over the step is modelled by the cubic through its
/// values and rates at the ends (the dense output matches both there; in free flight
/// under constant forces it is exact). Where the cubic crosses zero, its interior extreme
/// is searched. Otherwise the dense output's penetration at [`CHECKS`] fits the model's
/// deviation `theta^2 (1 - theta)^2 (g0 + g1 theta)`, at most `(|g0| + |g1|) / 16`; the
/// step is clear when the cubic keeps its sign with twice that margin and the checks
/// agree.
///
/// Peaks: a point in contact needs the search unless it restitutes at both ends (the
/// force and penetration fall from the start) or, past its first restitution, the
/// larger force at the ends is below half the impact's peak: an accurate step cannot
/// double the force and back inside itself.
fn screen<K: Kind>(
    sys: &System<K>,
    states: &[ContactState],
    log: &mut ImpactLog<PointOf<K>>,
    step: &DenseStep,
    scratch: &mut [f64],
) -> bool {
    let n = sys.layout.nq();
    let mut models = std::mem::take(&mut log.models);
    models.clear();
    let mut quiet = true;
    let mut ends = std::mem::take(&mut log.probed);
    ends.clear();
    ends.extend_from_slice(log.step_end.points(sys, &step.y0[..n], &step.y0[n..]));
    let starts = ends.len();
    ends.extend_from_slice(log.step_end.points(sys, &step.y1[..n], &step.y1[n..]));
    for (s, state) in states.iter().enumerate() {
        let (a, b) = (ends[s], ends[starts + s]);
        let model = Cubic {
            d0: a.penetration(),
            r0: step.h * a.penetration_rate(),
            d1: b.penetration(),
            r1: step.h * b.penetration_rate(),
        };
        let (low, at) = model.lowest(side(state));
        if low <= 0.0 {
            quiet = false;
            if at > 0.0 && at < 1.0 {
                log.points.push(at);
            }
        }
        if state.in_contact && (a.penetration_rate() > 0.0 || b.penetration_rate() > 0.0) {
            let c = &sys.clearances[log.owners[s].0];
            let force = |p| c.force(p, state.onset_speed).0;
            let peak = log.impacts[s].last().map_or(0.0, |i| i.peak_force);
            quiet &= state.mode == Mode::Continuous && 2.0 * force(&a).max(force(&b)) < peak;
        }
        models.push((model, [0.0; 2]));
    }
    if quiet {
        for (i, &theta) in CHECKS.iter().enumerate() {
            step.at(theta, scratch);
            let (q, v) = scratch.split_at(n);
            points_at(sys, q, v, &mut ends);
            for ((_, checked), p) in models.iter_mut().zip(&ends) {
                checked[i] = p.penetration();
            }
        }
        quiet = models.iter().zip(states).all(|((model, checked), state)| {
            let sign = side(state);
            let dev = [checked[0] - model.at(CHECKS[0]), checked[1] - model.at(CHECKS[1])];
            // dev_i = theta_i^2 (1 - theta_i)^2 (g0 + g1 theta_i), theta = 1/3, 2/3.
            let g1 = 60.75 * (dev[1] - dev[0]);
            let g0 = 20.25 * (2.0 * dev[0] - dev[1]);
            let margin = (g0.abs() + g1.abs()) / 8.0;
            sign * checked[0] > margin && sign * checked[1] > margin && model.lowest(sign).0 > margin
        });
    }
    log.models = models;
    log.probed = ends;
    quiet
}

/// The sign that a point's penetration keeps while its contact state holds: + in
/// contact, - in free flight.
fn side(state: &ContactState) -> f64 {
    if state.in_contact {
        1.0
    } else {
        -1.0
    }
}

/// A cubic in `theta` on [0, 1] from its values `d0`, `d1` and slopes `r0`, `r1` at the
/// ends (Hermite).
#[derive(Debug, Clone, Copy)]
struct Cubic {
    d0: f64,
    r0: f64,
    d1: f64,
    r1: f64,
}

impl Cubic {
    fn at(&self, s: f64) -> f64 {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * self.d0
            + (s3 - 2.0 * s2 + s) * self.r0
            + (3.0 * s2 - 2.0 * s3) * self.d1
            + (s3 - s2) * self.r1
    }

    /// The smallest value of `sign * p` on [0, 1] and where: at an end or where the
    /// slope vanishes.
    fn lowest(&self, sign: f64) -> (f64, f64) {
        // p' = 3 a s^2 + 2 b s + r0
        let a = 2.0 * (self.d0 - self.d1) + self.r0 + self.r1;
        let b = 3.0 * (self.d1 - self.d0) - 2.0 * self.r0 - self.r1;
        let mut low =
            if sign * self.d0 <= sign * self.d1 { (sign * self.d0, 0.0) } else { (sign * self.d1, 1.0) };
        let mut at = |s: f64| {
            let value = sign * self.at(s);
            if (0.0..=1.0).contains(&s) && value < low.0 {
                low = (value, s);
            }
        };
        // Roots of p' in the form that stays exact as `a` tends to zero (a quadratic).
        let disc = b * b - 3.0 * a * self.r0;
        if disc >= 0.0 {
            let q = -(b + disc.sqrt().copysign(b));
            if a != 0.0 {
                at(q / (3.0 * a));
            }
            if q != 0.0 {
                at(self.r0 / q);
            }
        }
        low
    }
}

/// Impact lists being built during a run.
pub struct ImpactLog<P = ContactPoint> {
    /// One list per contact point, by slot.
    pub impacts: Vec<Vec<Impact>>,
    /// The clearance joint of each slot and the point's index in it.
    owners: Vec<(usize, usize)>,
    /// Whether each slot is the only point of its joint.
    alone: Vec<bool>,
    /// Each point's kinematics at the current probe of [`locate`] (kept to reuse its
    /// allocation).
    probed: Vec<P>,
    /// Each point's penetration model and checks in [`screen`] (kept for its allocation).
    models: Vec<(Cubic, [f64; 2])>,
    /// Extra points for [`locate`] to search, from [`screen`].
    points: Vec<f64>,
    /// The points at the last step's end.
    step_end: StepEnd<P>,
    /// Time each point spent in free flight, impact and continuous contact [s] (indexed
    /// by [`Mode`]), summed over the accepted steps by [`ImpactLog::dwell`].
    pub mode_time: Vec<[f64; 3]>,
}

impl<P: ContactMeasure> ImpactLog<P> {
    /// Empty lists for a system.
    pub fn new<K: Kind>(sys: &System<K>) -> Self {
        Self::for_points(sys.clearances.iter().map(|c| c.points()))
    }

    /// Empty lists for clearance joints of `counts` contact points each.
    fn for_points(counts: impl IntoIterator<Item = usize>) -> Self {
        let (mut owners, mut alone) = (Vec::new(), Vec::new());
        for (k, range) in contact::point_ranges(counts).enumerate() {
            owners.extend((0..range.len()).map(|i| (k, i)));
            alone.extend(range.clone().map(|_| range.len() == 1));
        }
        let slots = owners.len();
        ImpactLog {
            impacts: vec![Vec::new(); slots],
            owners,
            alone,
            probed: Vec::new(),
            models: Vec::new(),
            points: Vec::new(),
            step_end: StepEnd::default(),
            mode_time: vec![[0.0; 3]; slots],
        }
    }

    /// The impacts and mode times of each contact point, joint after joint: a joint of
    /// one point under its own name, the points of a joint of several numbered from 1.
    pub fn joint_impacts<K: Kind>(self, sys: &System<K>) -> Vec<JointImpacts> {
        let numbers: Vec<_> = (0..self.owners.len()).map(|slot| self.point_number(slot)).collect();
        self.impacts
            .into_iter()
            .zip(self.mode_time)
            .zip(self.owners.iter().zip(numbers))
            .map(|((impacts, mode_time), (&(k, _), point))| JointImpacts {
                joint: sys.clearances[k].name().to_string(),
                point,
                impacts,
                mode_time,
            })
            .collect()
    }

    /// The number from 1 of the point in slot `slot` in its joint, `None` when the joint
    /// has that one point.
    fn point_number(&self, slot: usize) -> Option<usize> {
        (!self.alone[slot]).then_some(self.owners[slot].1 + 1)
    }

    /// Adds a step of length `dt` to the time of each point's mode at the step's start.
    /// Onsets and separations end steps, so contact and free flight are exact; the change
    /// from impact to continuous contact is resolved to the step that sees it.
    pub fn dwell(&mut self, states: &[ContactState], dt: f64) {
        for (time, s) in self.mode_time.iter_mut().zip(states) {
            let mode = if s.in_contact { s.mode } else { Mode::FreeFlight };
            time[mode as usize] += dt;
        }
    }

    /// Switches the contact point in slot `slot` at time `t` and state `(q, v)`: onset or
    /// separation.
    pub fn switch<K: Kind>(
        &mut self,
        sys: &System<K>,
        states: &mut [ContactState],
        slot: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) {
        let (k, i) = self.owners[slot];
        let rate = sys.contact_points(k, q, v)[i].penetration_rate();
        let s = &mut states[slot];
        if s.in_contact {
            s.separate();
            if let Some(last) = self.impacts[slot].last_mut() {
                last.duration = Some(t - last.onset_time);
            }
        } else {
            s.touch(rate);
            self.impacts[slot].push(Impact {
                onset_time: t,
                onset_speed: rate,
                peak_force: 0.0,
                max_penetration: 0.0,
                duration: None,
            });
        }
    }

    /// Raises the running impact peak force and penetration of the point in slot `slot`
    /// to those of a state in contact (the point given).
    fn raise_peak<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        slot: usize,
        state: &ContactState,
        p: &P,
    ) {
        let (f_n, _) = sys.clearances[self.owners[slot].0].force(p, state.onset_speed);
        if let Some(last) = self.impacts[slot].last_mut() {
            last.peak_force = last.peak_force.max(f_n);
            last.max_penetration = last.max_penetration.max(p.penetration());
        }
    }

    /// At an output sample: the mode from the penetration rate, and the peaks of the
    /// current impact.
    pub fn update<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        states: &mut [ContactState],
        q: &[f64],
        v: &[f64],
    ) {
        for (k, _, range) in contact::slots(&sys.clearances) {
            if !states[range.clone()].iter().any(|s| s.in_contact) {
                continue;
            }
            for p in sys.contact_points(k, q, v).iter() {
                self.follow(sys, states, range.start + p.index(), p);
            }
        }
    }

    /// [`ImpactLog::update`] at an accepted step's end, whose points the step's search
    /// has mostly found already.
    pub fn update_at_step_end<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        states: &mut [ContactState],
        q: &[f64],
        v: &[f64],
    ) {
        if !states.iter().any(|s| s.in_contact) {
            return;
        }
        let mut end = std::mem::take(&mut self.step_end);
        for (slot, p) in end.points(sys, q, v).iter().enumerate() {
            self.follow(sys, states, slot, p);
        }
        self.step_end = end;
    }

    /// Every contact point at an accepted step's end `(q, v)`, by slot.
    pub fn points_at_step_end<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        q: &[f64],
        v: &[f64],
    ) -> &[P] {
        self.step_end.points(sys, q, v)
    }

    /// Follows the point in slot `slot`, at `p`, if it is in contact.
    fn follow<K: Kind<Clearance: ClearanceJoint<Point = P>>>(
        &mut self,
        sys: &System<K>,
        states: &mut [ContactState],
        slot: usize,
        p: &P,
    ) {
        let s = &mut states[slot];
        if s.in_contact {
            s.follow(p.penetration_rate());
            self.raise_peak(sys, slot, s, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Cubic, ImpactLog};

    /// Joints of 1, 3 and 2 contact points: each slot knows its joint and point, a
    /// joint's one point goes by the joint's name, the points of the others by number, and
    /// each slot has its own impact list and mode times.
    #[test]
    fn impact_log_is_kept_per_joint_and_point() {
        let log: ImpactLog = ImpactLog::for_points([1, 3, 2]);
        assert_eq!(log.owners, vec![(0, 0), (1, 0), (1, 1), (1, 2), (2, 0), (2, 1)]);
        let numbers: Vec<_> = (0..6).map(|s| log.point_number(s)).collect();
        assert_eq!(numbers, vec![None, Some(1), Some(2), Some(3), Some(1), Some(2)]);
        assert_eq!((log.impacts.len(), log.mode_time.len()), (6, 6));
        let mut log = log;
        let mut states = vec![crate::mechanics::contact::ContactState::default(); 6];
        states[2].touch(0.1);
        log.dwell(&states, 0.5);
        let contact: Vec<_> = log.mode_time.iter().map(|t| t[1]).collect();
        assert_eq!(contact, vec![0.0, 0.0, 0.5, 0.0, 0.0, 0.0]);
    }

    /// The lowest value and its place agree with a fine sampling, for cubics, a parabola
    /// whose cubic coefficient is rounding noise, and lines.
    #[test]
    fn cubic_lowest_matches_sampling() {
        let parabola =
            |p0: f64, s0: f64, c2: f64| Cubic { d0: p0, r0: s0, d1: p0 + s0 + c2, r1: s0 + 2.0 * c2 };
        let cases = [
            Cubic { d0: -1.0, r0: 3.0, d1: -0.5, r1: -4.0 },
            Cubic { d0: 0.2, r0: -1.5, d1: 0.1, r1: 2.0 },
            Cubic { d0: 1.0, r0: 0.5, d1: 2.0, r1: 0.3 },
            parabola(-1.6815036225893492e-4, 9.051454773886002e-4, -1.2180852386691708e-3),
            Cubic { d0: 0.0, r0: 1.0, d1: 1.0, r1: 1.0 },
        ];
        for cubic in cases {
            for sign in [1.0, -1.0] {
                let (low, at) = cubic.lowest(sign);
                let sampled = (0..=100_000)
                    .map(|i| i as f64 / 1e5)
                    .map(|s| (sign * cubic.at(s), s))
                    .fold((f64::INFINITY, 0.0), |m, x| if x.0 < m.0 { x } else { m });
                let scale = cubic.d0.abs() + cubic.d1.abs() + cubic.r0.abs() + cubic.r1.abs();
                assert!(low <= sampled.0 + 1e-15 * scale, "{cubic:?} {sign}: {low} vs {}", sampled.0);
                assert!(sampled.0 - low < 1e-9 * scale, "{cubic:?} {sign}: {low} vs {}", sampled.0);
                assert!((at - sampled.1).abs() < 1e-3, "{cubic:?} {sign}: at {at} vs {}", sampled.1);
                assert!((sign * cubic.at(at) - low).abs() <= 1e-15 * scale);
            }
        }
        // The parabola's top is above zero though both ends are well below.
        let (low, at) = cases[3].lowest(-1.0);
        assert!(low < 0.0 && (at - 0.3715).abs() < 1e-3, "{low} at {at}");
    }
}
