//! The `auto` method: explicit DOPRI5 until the problem turns stiff (Hairer's test on
//! DOPRI5's own stages), then SDIRK4 for as long as it advances further per force
//! evaluation than DOPRI5 would. Stiffness from a contact or a sticking friction law
//! comes and goes with the contact, and a non-smooth force keeps the implicit method's
//! steps short, so the cheaper method per simulated second wins. DOPRI5's progress is
//! estimated from the Jacobian's spectral radius rho: a stable step of at most
//! `3.25 / rho` (and no longer than SDIRK4's) for 6 evaluations.
//!
//! Sticking friction is a stiffness the model can name: a clearance joint's friction
//! law damps the slip at a rate `lambda_f` ([`crate::dynamics::friction_rate`]) that
//! rises a thousandfold as the slip falls below the stiction speed, for a few
//! milliseconds at a time. It hands the step to Radau IIA directly once friction holds an
//! explicit step near DOPRI5's stability edge of 3.3 (`lambda_f h > 2`), and takes it
//! back once the step Radau IIA proposes next lies well inside that region
//! (`lambda_f h_next < 1.5`). Waiting for Hairer's test and the measuring windows would
//! spend most of each short sticking phase in the wrong method: on the founding case
//! DOPRI5 alone took 8000 steps of 5 us in its 53 ms of sticking, Radau IIA 800.

use super::options::Method;

/// Consecutive stiff indications after which DOPRI5 hands over, at first.
const STIFF_SWITCH: usize = 15;
/// `h |lambda|` above which an explicit step counts as stiff (DOPRI5's stability edge).
const STIFF_EDGE: f64 = 3.25;
/// Accepted steps over which a method's progress per evaluation is measured.
const WINDOW: usize = 50;
/// Force evaluations of one DOPRI5 step (7 stages, the first reused).
const EXPLICIT_EVALUATIONS: f64 = 6.0;
/// Most consecutive stiff indications ever required.
const STIFF_SWITCH_MAX: usize = 16 * STIFF_SWITCH;
/// `lambda_f h` of an explicit step above which sticking friction hands the next one to
/// Radau IIA: the step is then held near DOPRI5's stability edge (3.3) by friction.
const FRICTION_STIFF: f64 = 2.0;
/// `lambda_f h` below which Radau IIA hands a sticking phase back.
const FRICTION_EASY: f64 = 1.5;

/// Where one method's measuring window started.
#[derive(Clone, Copy)]
struct Window {
    t: f64,
    evaluations: usize,
    steps: usize,
}

impl Window {
    fn at(t: f64, evaluations: usize) -> Self {
        Window { t, evaluations, steps: 0 }
    }

    /// Simulated time per force evaluation since the window opened.
    fn rate(&self, t: f64, evaluations: usize) -> f64 {
        (t - self.t) / (evaluations - self.evaluations).max(1) as f64
    }
}

/// Decides, after every accepted step of `auto`, which method takes the next one.
pub struct AutoSwitch {
    stiff_count: usize,
    needed: usize,
    window: Window,
    switches: usize,
    first_switch: Option<f64>,
    implicit_since: f64,
    implicit_time: f64,
    /// Sticking phases handed to Radau IIA, and the time they took.
    sticking: usize,
    sticking_time: f64,
}

impl Default for AutoSwitch {
    /// Starts with DOPRI5 at t = 0.
    fn default() -> Self {
        AutoSwitch {
            stiff_count: 0,
            needed: STIFF_SWITCH,
            window: Window::at(0.0, 0),
            switches: 0,
            first_switch: None,
            implicit_since: 0.0,
            implicit_time: 0.0,
            sticking: 0,
            sticking_time: 0.0,
        }
    }
}

impl AutoSwitch {
    /// Whether SDIRK4 has finished a measuring window: the caller then passes the
    /// Jacobian's spectral radius to [`AutoSwitch::after_step`].
    pub fn wants_radius(&self, method: Method) -> bool {
        method == Method::Sdirk4 && self.window.steps + 1 >= WINDOW
    }

    /// The friction rate [1/s] at and below which the decision of
    /// [`AutoSwitch::after_step`] after a step of `method` (`h`, `h_next` as there) is
    /// the same whatever the rate: rates below it need not be told apart (computed to
    /// their bound without the constraints). A margin of 1e-9 keeps the products with the
    /// step on the same side of the limits.
    pub fn friction_decides_above(method: Method, h: f64, h_next: f64) -> f64 {
        let limit = match method {
            Method::Radau5 => FRICTION_EASY / h_next,
            Method::Dopri5 => FRICTION_STIFF / h,
            _ => f64::INFINITY,
        };
        limit * (1.0 - 1e-9)
    }

    /// After an accepted step of size `h` of `method` ending at `t` (`h_next`: the step
    /// the method proposes next, or `h`), with `evaluations` force evaluations so far, DOPRI5's stiffness estimate `h |lambda|`, (when
    /// [`AutoSwitch::wants_radius`]) the spectral radius, and the friction rate
    /// `lambda_f` at the step's end: the method of the next step, if it changes.
    pub fn after_step(
        &mut self,
        method: Method,
        (t, h, h_next): (f64, f64, f64),
        evaluations: usize,
        (stiffness, radius): (Option<f64>, Option<f64>),
        friction: f64,
    ) -> Option<Method> {
        self.window.steps += 1;
        if method == Method::Radau5 {
            if friction * h_next >= FRICTION_EASY {
                return None;
            }
            self.sticking_time += t - self.implicit_since;
            self.stiff_count = 0;
            return Some(Method::Dopri5);
        }
        if method == Method::Dopri5 && friction * h > FRICTION_STIFF {
            self.sticking += 1;
            self.implicit_since = t;
            return Some(Method::Radau5);
        }
        match method {
            Method::Sdirk4 => {
                if self.window.steps < WINDOW {
                    return None;
                }
                let rate = self.window.rate(t, evaluations);
                self.window = Window::at(t, evaluations);
                let stable = radius.map_or(0.0, |rho| STIFF_EDGE / rho.max(f64::MIN_POSITIVE));
                if stable.min(h) / EXPLICIT_EVALUATIONS <= rate {
                    return None;
                }
                // Back to the explicit method; it must prove stiffness longer next time.
                self.needed = (2 * self.needed).min(STIFF_SWITCH_MAX);
                self.stiff_count = 0;
                self.implicit_time += t - self.implicit_since;
                Some(Method::Dopri5)
            }
            _ => {
                match stiffness {
                    Some(s) if s > STIFF_EDGE => self.stiff_count += 1,
                    _ => self.stiff_count = self.stiff_count.saturating_sub(1),
                }
                if self.stiff_count < self.needed {
                    return None;
                }
                self.stiff_count = 0;
                self.switches += 1;
                self.first_switch.get_or_insert(t);
                self.implicit_since = t;
                self.window = Window::at(t, evaluations);
                Some(Method::Sdirk4)
            }
        }
    }

    /// The method line of the run statistics, e.g. `auto: dopri5, sdirk4 from t = 0.07 s`
    /// or `auto: dopri5, radau5 for sticking friction 12 times (9 % of the run)`.
    pub fn describe(&self, method: Method, t_end: f64) -> String {
        let share = |time: f64| 100.0 * time / t_end.max(f64::MIN_POSITIVE);
        let times = |n: usize| format!("{n} time{}", if n == 1 { "" } else { "s" });
        // Time in an implicit method, with the phase still running at the end.
        let spent = |past: f64, running: bool| past + if running { t_end - self.implicit_since } else { 0.0 };
        let mut line = "auto: dopri5".to_string();
        if let Some(first) = self.first_switch {
            if self.switches == 1 && method == Method::Sdirk4 {
                line += &format!(", sdirk4 from t = {first:.6} s");
            } else {
                line += &format!(
                    ", sdirk4 {} from t = {first:.6} s ({:.0} % of the run)",
                    times(self.switches),
                    share(spent(self.implicit_time, method == Method::Sdirk4))
                );
            }
        }
        if self.sticking > 0 {
            line += &format!(
                ", radau5 for sticking friction {} ({:.0} % of the run)",
                times(self.sticking),
                share(spent(self.sticking_time, method == Method::Radau5))
            );
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::{AutoSwitch, Method};

    /// The rule's decision after a step, at friction rate `rate`, from a fresh rule.
    fn decision(method: Method, (h, h_next): (f64, f64), rate: f64) -> Option<Method> {
        AutoSwitch::default().after_step(method, (0.1, h, h_next), 1000, (None, None), rate)
    }

    /// Any rate up to `friction_decides_above` takes the rule the same way as a rate of
    /// zero, and a rate just past the limit it guards turns it: so rates below it need
    /// not be told apart, and the margin is no wider than it needs to be.
    #[test]
    fn rates_below_the_deciding_rate_take_the_same_turn() {
        for (h, h_next) in [(1e-5, 1.3e-5), (3.7e-6, 2.9e-6), (0.01, 0.02)] {
            for (method, limit) in [(Method::Dopri5, 2.0 / h), (Method::Radau5, 1.5 / h_next)] {
                let decides = AutoSwitch::friction_decides_above(method, h, h_next);
                assert!(decides < limit && decides > limit * (1.0 - 1e-8), "{method:?}");
                let at_zero = decision(method, (h, h_next), 0.0);
                assert_eq!(decision(method, (h, h_next), decides), at_zero, "{method:?} h {h}");
                assert_ne!(decision(method, (h, h_next), limit * (1.0 + 1e-9)), at_zero, "{method:?}");
            }
            let free = AutoSwitch::friction_decides_above(Method::Sdirk4, h, h_next);
            assert_eq!(free, f64::INFINITY, "SDIRK4's rule reads no friction");
        }
    }
}
