//! The discrete contact state of one contact point of a clearance joint: whether its
//! two parts touch there (the journal its bearing), the approach speed of the current
//! impact, and the contact mode. The hysteresis laws read the onset speed; the run's
//! event location changes the state at onsets and separations. A run keeps one state per
//! contact point, joint after joint ([`super::slots`]).

use crate::scalar::Real;

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

/// State of one contact point, kept in the workspace.
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

/// [`ContactState::onset_for`] of a state whose `in_contact` is 1 or 0 and whose onset
/// speed is `onset_speed`, in any number type: a compiled evaluation reads both as inputs.
#[inline]
pub fn onset_for<T: Real>(in_contact: T, onset_speed: T, rate: T) -> T {
    if in_contact > 0.5 {
        onset_speed
    } else {
        rate
    }
}

impl ContactState {
    /// Approach speed for the hysteresis laws: the located onset's, or, outside a
    /// located contact (a run that starts in contact), the current penetration rate
    /// `rate` [m/s].
    pub fn onset_for(&self, rate: f64) -> f64 {
        onset_for(if self.in_contact { 1.0 } else { 0.0 }, self.onset_speed, rate)
    }

    /// An onset: contact begins at the approach speed `rate` [m/s], as an impact.
    pub fn touch(&mut self, rate: f64) {
        self.in_contact = true;
        self.onset_speed = rate;
        self.mode = Mode::Impact;
        self.restituting = false;
    }

    /// A separation: free flight until the next onset.
    pub fn separate(&mut self) {
        self.in_contact = false;
        self.mode = Mode::FreeFlight;
    }

    /// At an accepted state in contact with penetration rate `rate`: an impact turns
    /// into continuous contact once its restitution (the rate turned negative) is over
    /// (the rate no longer negative).
    pub fn follow(&mut self, rate: f64) {
        if self.mode == Mode::Impact {
            if rate < 0.0 {
                self.restituting = true;
            } else if self.restituting {
                self.mode = Mode::Continuous;
            }
        }
    }
}
