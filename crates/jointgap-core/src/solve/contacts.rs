//! Discrete state of clearance joints during a run: whether each journal touches its
//! bearing, the onset speed of the current impact, the contact mode, and the impact
//! list. Onsets and separations are events located by root finding on the penetration.

use super::ode::hermite5;
use crate::contact::ContactKinematics;
use crate::output::Impact;
use crate::system::System;

/// Contact mode reported in the `mode` channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No contact (penetration < 0).
    FreeFlight = 0,
    /// From onset through the first compression and restitution.
    Impact = 1,
    /// Contact that lasts beyond the first restitution: the journal follows the wall.
    Continuous = 2,
}

/// State of one clearance joint, kept in the workspace.
#[derive(Debug, Clone, Copy)]
pub struct ContactState {
    /// True between a located onset and the next separation.
    pub in_contact: bool,
    /// Approach speed of the current impact [m/s].
    pub onset_speed: f64,
    /// Mode for the output.
    pub mode: Mode,
    /// Seen the penetration rate turn negative since onset (restitution phase).
    restituting: bool,
}

impl Default for ContactState {
    fn default() -> Self {
        ContactState { in_contact: false, onset_speed: 0.0, mode: Mode::FreeFlight, restituting: false }
    }
}

/// Kinematics of clearance joint `k` at state `(q, v)`.
pub fn kinematics(sys: &System, k: usize, q: &[f64], v: &[f64]) -> ContactKinematics {
    let c = &sys.clearances[k];
    c.kinematics(&sys.body_state(c.bearing, q, v), &sys.body_state(c.journal, q, v))
}

impl ContactState {
    /// Approach speed for the hysteresis laws: the located onset's, or, outside a
    /// located contact (a run that starts in contact), the current rate.
    pub fn onset_for(&self, kin: &ContactKinematics) -> f64 {
        if self.in_contact {
            self.onset_speed
        } else {
            kin.penetration_rate
        }
    }
}

/// Interior points at which a step is searched for a contact change, so that a brief
/// contact inside one step is not missed.
const PROBES: usize = 8;

/// Earliest contact change inside a step: `(theta, joint)` with theta in (0, 1], the
/// first point where a joint's penetration sign disagrees with its contact flag.
/// Located by bisection to a relative width of 1e-12 of the step.
///
/// The probes before the change also raise the running impacts' peak force and
/// penetration in `log`: a step that spans the peak would otherwise report only the
/// smaller values at its ends.
#[allow(clippy::too_many_arguments)]
pub fn locate(
    sys: &System,
    states: &[ContactState],
    log: &mut ImpactLog,
    h: f64,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    scratch: &mut [f64],
) -> Option<(f64, usize)> {
    if sys.clearances.is_empty() {
        return None;
    }
    let n = y0.len() / 2;
    let differs = |k: usize, d: f64| if states[k].in_contact { d < 0.0 } else { d > 0.0 };
    let mut lo = 0.0;
    for p in 1..=PROBES {
        let hi = p as f64 / PROBES as f64;
        hermite5(hi, h, y0, f0, y1, f1, scratch);
        let (q, v) = scratch.split_at(n);
        // Each joint's kinematics once per probe: the search and the peaks both use them.
        let mut probed = std::mem::take(&mut log.probed);
        probed.clear();
        probed.extend((0..states.len()).map(|k| kinematics(sys, k, q, v)));
        let change = probed.iter().enumerate().position(|(k, kin)| differs(k, kin.penetration));
        if let Some(k) = change {
            log.probed = probed;
            // Bisect on joint k in (lo, hi]; an earlier change of another joint inside
            // the bracket is caught by the next step's search.
            let (mut a, mut b) = (lo, hi);
            while b - a > 1e-12 {
                let mid = 0.5 * (a + b);
                hermite5(mid, h, y0, f0, y1, f1, scratch);
                let d = kinematics(sys, k, &scratch[..n], &scratch[n..]).penetration;
                if differs(k, d) {
                    b = mid;
                } else {
                    a = mid;
                }
            }
            return Some((b, k));
        }
        for k in (0..states.len()).filter(|&k| states[k].in_contact) {
            log.raise_peak(sys, k, &states[k], &probed[k]);
        }
        log.probed = probed;
        lo = hi;
    }
    None
}

/// Impact lists being built during a run.
pub struct ImpactLog {
    /// One list per clearance joint.
    pub impacts: Vec<Vec<Impact>>,
    /// Each joint's kinematics at the current probe of [`locate`] (kept to reuse its
    /// allocation).
    probed: Vec<ContactKinematics>,
}

impl ImpactLog {
    /// Empty lists for a system.
    pub fn new(sys: &System) -> Self {
        ImpactLog { impacts: vec![Vec::new(); sys.clearances.len()], probed: Vec::new() }
    }

    /// Switches joint `k` at time `t` and state `(q, v)`: onset or separation.
    pub fn switch(
        &mut self,
        sys: &System,
        states: &mut [ContactState],
        k: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
    ) {
        let rate = kinematics(sys, k, q, v).penetration_rate;
        let s = &mut states[k];
        if s.in_contact {
            s.in_contact = false;
            s.mode = Mode::FreeFlight;
            if let Some(last) = self.impacts[k].last_mut() {
                last.duration = Some(t - last.onset_time);
            }
        } else {
            s.in_contact = true;
            s.onset_speed = rate;
            s.mode = Mode::Impact;
            s.restituting = false;
            self.impacts[k].push(Impact {
                onset_time: t,
                onset_speed: rate,
                peak_force: 0.0,
                max_penetration: 0.0,
                duration: None,
            });
        }
    }

    /// Raises joint `k`'s running impact peak force and penetration to those of a state
    /// in contact (its kinematics given).
    fn raise_peak(&mut self, sys: &System, k: usize, state: &ContactState, kin: &ContactKinematics) {
        let (f_n, _) = sys.clearances[k].contact_force(kin, state.onset_speed);
        if let Some(last) = self.impacts[k].last_mut() {
            last.peak_force = last.peak_force.max(f_n);
            last.max_penetration = last.max_penetration.max(kin.penetration);
        }
    }

    /// At an accepted state (step end or output sample): the mode from the penetration
    /// rate, and the peaks of the current impact.
    pub fn update(&mut self, sys: &System, states: &mut [ContactState], q: &[f64], v: &[f64]) {
        for k in 0..states.len() {
            let s = &mut states[k];
            if !s.in_contact {
                continue;
            }
            let kin = kinematics(sys, k, q, v);
            if s.mode == Mode::Impact {
                if kin.penetration_rate < 0.0 {
                    s.restituting = true;
                } else if s.restituting {
                    s.mode = Mode::Continuous;
                }
            }
            self.raise_peak(sys, k, s, &kin);
        }
    }
}
