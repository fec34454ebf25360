//! The integration loop shared by all methods: steps between input corners, error
//! control, switching to the implicit method when the problem turns stiff, projection
//! onto the constraints, and output at sample times from each step's dense output.

use super::equations::Ode;
use super::events::{self, ImpactLog, PointOf};
use super::monitor::{Monitor, Progress};
use super::options::{Method, SimOptions};
use super::record::{self, Recorder, SampleError, NON_FINITE_CAUSE};
use super::switching::AutoSwitch;
use super::wear::Wear;
use super::Kind;
use crate::dynamics::{project, violation};
use crate::integrators::dopri5::Dopri5;
use crate::integrators::ode::{DenseStep, PositionRate, Rhs, StateShape};
use crate::integrators::radau5::Radau5;
use crate::integrators::sdirk4::Sdirk4;
use crate::integrators::stepper::{StepFailure, Stepper};
use crate::output::{RunStats, Status};
use crate::profile;

/// The stepper of `method` for a state of shape `shape`: the one place where a method
/// becomes a stepper (`auto` starts with DOPRI5).
pub fn stepper<R: Rhs + ?Sized>(method: Method, shape: StateShape) -> Box<dyn Stepper<R>> {
    let StateShape { nq, nv, .. } = shape;
    match method {
        Method::Sdirk4 => Box::new(Sdirk4::new(nq, nv)),
        Method::Radau5 => Box::new(Radau5::new(nq, nv)),
        Method::Dopri5 | Method::Auto => Box::new(Dopri5::new(nq, nv)),
    }
}

/// Integrates from `(0, y)` to `t_end`, recording into `rec`, reporting to `monitor`,
/// and accumulating `wear` at each accepted step. Returns the final status.
#[allow(clippy::too_many_arguments)]
pub fn integrate<K: Kind>(
    ode: &mut Ode<'_, K>,
    opts: &SimOptions,
    y: &mut Vec<f64>,
    rec: &mut Recorder<K>,
    log: &mut ImpactLog<PointOf<K>>,
    stats: &mut RunStats,
    monitor: &mut dyn Monitor,
    mut wear: Option<&mut Wear>,
) -> Status {
    let mut clock = ProgressClock::start(monitor.progress_interval());
    let chunk = monitor.chunk_len();
    let shape = ode.shape();
    let (n_state, n) = (shape.state_len(), shape.nq);
    let sys = ode.sys;
    let mut methods = MethodInUse::new(opts.method, shape);
    let mut f = vec![0.0; n_state];
    let mut y_new = vec![0.0; n_state];
    let mut f_new = vec![0.0; n_state];
    let mut sample = vec![0.0; n_state];
    // Where `q' = G(q) v`: the positions' second derivatives at the step's ends, which
    // make its dense output's positions quintic as they are where `q' = v`.
    let mapped = shape.rate == PositionRate::Mapped;
    let (mut qdd0, mut qdd1) =
        (vec![0.0; if mapped { shape.nq } else { 0 }], vec![0.0; if mapped { shape.nq } else { 0 }]);

    let mut t = 0.0;
    let mut grid = Sampling::new(opts);
    let budget = opts.step_budget();
    let mut boundaries: Vec<f64> = sys.corners.iter().copied().filter(|&c| c < opts.t_end).collect();
    boundaries.push(opts.t_end);

    // Every exit leads past the counters below, so a failed run reports them too.
    let status = 'run: {
        ode.ws.t_piece = 0.0;
        if ode.rhs(t, y, &mut f).is_err() {
            break 'run singular(t);
        }
        let mut h = initial_step(ode, y, &f, methods.stepper.error_exponent(), boundaries[0]);
        if let Some(hmax) = opts.max_step {
            h = h.min(hmax);
        }
        let mut last_rejected = false;

        for &segment_end in &boundaries {
            // At a corner the inputs change piece: re-evaluate the derivative on the new side.
            if t > 0.0 {
                ode.ws.t_piece = 0.5 * (t + segment_end);
                if ode.rhs(t, y, &mut f).is_err() {
                    break 'run singular(t);
                }
            }
            while t < segment_end {
                if stats.accepted_steps + stats.rejected_steps >= budget {
                    break 'run fail(
                        t,
                        format!(
                            "step budget of {budget} steps spent (max_steps): raise max_steps \
                             (--max-steps) for a longer run, or look for what keeps the steps small"
                        ),
                    );
                }
                if let Some(hmax) = opts.max_step {
                    h = h.min(hmax);
                }
                let last;
                (h, last) = match step_in_segment(h, t, segment_end) {
                    Ok(step) => step,
                    Err(status) => break 'run status,
                };
                ode.ws.t_piece = t + 0.5 * h;
                let tol = ode.tolerances;
                let stepper = &mut methods.stepper;
                match stepper.attempt(ode, tol, t, y, &f, h, &mut y_new, &mut f_new) {
                    Err(StepFailure::Singular) => break 'run singular(t),
                    Err(StepFailure::Convergence) => {
                        stats.rejected_steps += 1;
                        stepper.rejected();
                        h *= stepper.step_factor().map_or(0.5, |f| f.clamp(0.1, 0.9));
                        last_rejected = true;
                    }
                    Ok(att) if att.error > 1.0 || att.error.is_nan() => {
                        stats.rejected_steps += 1;
                        stepper.rejected();
                        h *= shrink_after_error(&**stepper, att.error);
                        last_rejected = true;
                    }
                    Ok(att) => {
                        stats.accepted_steps += 1;
                        // The drift at the step's end from the step's last evaluation, taken
                        // before output samples reuse the workspace.
                        let residuals = ode.ws.violation_here(&y_new[n..]);
                        let drift_at_end =
                            (residuals, rounding_where_needed(ode, residuals, &y_new[..n], &y_new[n..]));
                        // A contact onset or separation inside the step ends the step there.
                        if mapped {
                            for (qdd, y, f) in [(&mut qdd0, &*y, &f), (&mut qdd1, &y_new, &f_new)] {
                                ode.position_acceleration(&y[..n], &y[n..], &f[n..], qdd);
                            }
                        }
                        let qdd = mapped.then_some([qdd0.as_slice(), qdd1.as_slice()]);
                        let step = DenseStep { shape, h, y0: y, f0: &f, y1: &y_new, f1: &f_new, qdd };
                        let event = locate_event(ode, log, &step, &mut sample);
                        let (t_new, last) = match event {
                            Some((theta, _)) if theta < 1.0 => (t + theta * h, false),
                            _ => (if last { segment_end } else { t + h }, last),
                        };
                        log.dwell(&ode.ws.contacts, t_new - t);
                        if let Err(status) =
                            record_samples_inside(ode, rec, log, &step, (t, t_new), &mut grid, &mut sample)
                        {
                            break 'run status;
                        }
                        let mut refresh = false;
                        if let Some((theta, k)) = event {
                            if theta < 1.0 {
                                step.at(theta, &mut sample);
                                y_new.copy_from_slice(&sample);
                                ode.update_positions(&mut y_new[..n]);
                            }
                            let (q, v) = y_new.split_at(n);
                            log.switch(sys, &mut ode.ws.contacts, k, t_new, q, v);
                            stats.events += 1;
                            refresh = true;
                        }
                        let h_taken = t_new - t;
                        // The state is still the one the step's last evaluation saw.
                        let at_attempt_end = t_new == t + h && event.is_none_or(|(theta, _)| theta >= 1.0);
                        t = t_new;
                        std::mem::swap(y, &mut y_new);
                        std::mem::swap(&mut f, &mut f_new);
                        if let Err(status) = check_state_finite(sys, t, y) {
                            break 'run status;
                        }
                        let drift = at_attempt_end.then_some(drift_at_end);
                        match keep_on_constraints(ode, t, y, drift, stats) {
                            Ok(projected) => refresh |= projected,
                            Err(status) => break 'run status,
                        }
                        if refresh {
                            ode.ws.t_piece = t - 0.5 * h_taken;
                            if ode.rhs(t, y, &mut f).is_err() {
                                break 'run singular(t);
                            }
                        }
                        log.update_at_step_end(sys, &mut ode.ws.contacts, &y[..n], &y[n..]);
                        if let Some(wear) = wear.as_deref_mut() {
                            wear.step(sys, &ode.ws.contacts, (t, h_taken), &y[..n], &y[n..]);
                        }
                        if let Err(status) = record_step_end(ode, rec, &grid, t, y) {
                            break 'run status;
                        }
                        if let Err(status) = hand_over_samples(monitor, chunk, rec, t) {
                            break 'run status;
                        }
                        if let Some(wall_time) = clock.due(stats.accepted_steps) {
                            let progress = Progress {
                                time: t,
                                t_end: opts.t_end,
                                steps: stats.accepted_steps + stats.rejected_steps,
                                impacts: log.impacts.iter().map(Vec::len).sum(),
                                wall_time,
                            };
                            if let Err(stop) = monitor.progress(&progress) {
                                break 'run stop.status(t, "stopped");
                            }
                        }
                        if opts.method == Method::Auto {
                            let points = log.points_at_step_end(sys, &y[..n], &y[n..]);
                            methods.after_step(ode, stats, (t, h_taken), (y, &f), att.stiffness, points);
                        }
                        h = grow_after_success(
                            &*methods.stepper,
                            att.error,
                            h,
                            last_rejected || event.is_some(),
                            last,
                        );
                        last_rejected = false;
                    }
                }
            }
        }
        Status::Finished
    };
    if let Some(p) = ode.ws.profile.as_mut() {
        p.total = clock.started.elapsed().as_secs_f64();
    }
    stats.jacobian_evaluations += methods.stepper.jacobian_evaluations();
    stats.newton_iterations += methods.stepper.newton_iterations();
    stats.method = if opts.method == Method::Auto {
        methods.switch.describe(methods.method, t)
    } else {
        methods.stepper.name().to_string()
    };
    status
}

/// The method taking the steps and, under `auto`, the rule that changes it.
struct MethodInUse<'a, K: Kind> {
    /// The method now.
    method: Method,
    /// Its stepper.
    stepper: Box<dyn Stepper<Ode<'a, K>>>,
    /// The `auto` method's rule.
    switch: AutoSwitch,
}

impl<'a, K: Kind> MethodInUse<'a, K> {
    /// The first method of a run of `requested` (`auto` starts with DOPRI5).
    fn new(requested: Method, shape: StateShape) -> Self {
        let method = if requested == Method::Auto { Method::Dopri5 } else { requested };
        MethodInUse { method, stepper: stepper(method, shape), switch: AutoSwitch::default() }
    }

    /// Under `auto`, after an accepted step of `h_taken` to `(t, y)` with `f = f(t, y)`
    /// (`stiffness`: the explicit method's estimate; `points`: the contact points at
    /// `y`): the method of the next step, from the stiffness and the sticking friction
    /// the step shows.
    fn after_step(
        &mut self,
        ode: &mut Ode<'a, K>,
        stats: &mut RunStats,
        (t, h_taken): (f64, f64),
        (y, f): (&[f64], &[f64]),
        stiffness: Option<f64>,
        points: &[PointOf<K>],
    ) {
        let radius = if self.switch.wants_radius(self.method) {
            self.stepper.spectral_radius(ode, t, y, f)
        } else {
            None
        };
        let (q, v) = y.split_at(ode.sys.layout.nq());
        let h_next = h_taken * self.stepper.step_factor().unwrap_or(1.0);
        let decides = AutoSwitch::friction_decides_above(self.method, h_taken, h_next);
        let friction = K::friction_rate(ode.sys, q, v, points, decides, &mut ode.ws);
        let next = self.switch.after_step(
            self.method,
            (t, h_taken, h_next),
            ode.evaluations,
            (stiffness, radius),
            friction,
        );
        if let Some(next) = next {
            self.method = next;
            stats.jacobian_evaluations += self.stepper.jacobian_evaluations();
            stats.newton_iterations += self.stepper.newton_iterations();
            self.stepper = stepper(next, ode.shape());
        }
    }
}

/// When the run's output is sampled: on the grid of the output rate, and at every
/// accepted step when asked (or without a rate).
struct Sampling {
    /// Spacing of the output grid [s] (none without a rate).
    dt: Option<f64>,
    /// The next grid sample's index (sample 0, at t = 0, is recorded by the caller).
    next: usize,
    /// End time of the run [s].
    t_end: f64,
    /// Record every accepted step too.
    every_step: bool,
    /// Raise the peaks at each accepted step without recording it.
    step_peaks: bool,
}

impl Sampling {
    fn new(opts: &SimOptions) -> Self {
        Sampling {
            dt: opts.rate.map(|r| 1.0 / r),
            next: 1,
            t_end: opts.t_end,
            every_step: opts.every_step || opts.rate.is_none(),
            step_peaks: opts.step_peaks,
        }
    }

    /// Time of the next grid sample.
    fn next_time(&self) -> Option<f64> {
        self.dt.map(|dt| self.next as f64 * dt)
    }
}

/// When a run reports its progress: every `every` seconds of wall time, looked at every
/// 16 accepted steps.
struct ProgressClock {
    started: std::time::Instant,
    every: Option<f64>,
    next: f64,
}

impl ProgressClock {
    fn start(every: Option<f64>) -> Self {
        ProgressClock { started: std::time::Instant::now(), every, next: every.unwrap_or(f64::INFINITY) }
    }

    /// The wall time when a report is due after `accepted` steps.
    fn due(&mut self, accepted: usize) -> Option<f64> {
        if self.every.is_some() && accepted.is_multiple_of(16) {
            let wall_time = self.started.elapsed().as_secs_f64();
            if wall_time >= self.next {
                self.next = wall_time + self.every.unwrap_or(f64::INFINITY);
                return Some(wall_time);
            }
        }
        None
    }
}

/// A run that fails at `t` for `reason`.
fn fail(t: f64, reason: String) -> Status {
    Status::Failed { time: t, reason }
}

/// A run that fails at `t` because its constraint equations are singular there.
fn singular(t: f64) -> Status {
    fail(
        t,
        format!(
            "the constraint equations became singular at t = {t:.6} s: the mechanism locks up or passes a \
             singular position (e.g. a four-bar at a change point, a crank at a dead centre with the driver on the rod)"
        ),
    )
}

/// A run that fails at `t` because a sample there cannot be recorded.
fn sample_failed(t: f64, error: SampleError) -> Status {
    match error {
        SampleError::Singular => singular(t),
        SampleError::NonFinite { channel, value } => {
            fail(t, format!("{channel} = {value}: {NON_FINITE_CAUSE}"))
        }
    }
}

/// The step to try from `t` in a segment that ends at `segment_end`: `h`, or the rest of
/// the segment where `h` reaches its end or would leave a remainder too small to step
/// over (then the step is the segment's last); a failure where the step falls below the
/// smallest one resolvable at `t`.
fn step_in_segment(h: f64, t: f64, segment_end: f64) -> Result<(f64, bool), Status> {
    let remaining = segment_end - t;
    let hmin = 1e-14 * t.abs().max(1e-3);
    let last = h >= remaining * (1.0 - 1e-12) || remaining - h < 4.0 * hmin;
    let h = if last { remaining } else { h };
    if h < hmin {
        return Err(fail(
            t,
            format!("step size {h:.3e} s below the smallest resolvable step at t = {t:.6} s"),
        ));
    }
    Ok((h, last))
}

/// `h_next / h` after an attempt rejected for its error: the method's own factor where
/// it chooses its steps, else the error's, bounded to [0.1, 0.9].
fn shrink_after_error<K: Kind>(stepper: &dyn Stepper<Ode<'_, K>>, error: f64) -> f64 {
    let factor = if let Some(f) = stepper.step_factor() {
        f
    } else if error.is_finite() {
        0.9 * error.powf(-stepper.error_exponent())
    } else {
        0.1
    };
    factor.clamp(0.1, 0.9)
}

/// The step after an accepted one of size `h` with error `error`: the method's own
/// factor where it chooses its steps, else the error's, at least 0.2 and at most 5
/// (1 after a rejection or an event, `held`). A step cut short by a corner (`last`)
/// does not shrink the next one.
fn grow_after_success<K: Kind>(
    stepper: &dyn Stepper<Ode<'_, K>>,
    error: f64,
    h: f64,
    held: bool,
    last: bool,
) -> f64 {
    let factor = if let Some(f) = stepper.step_factor() {
        f
    } else if error > 0.0 {
        0.9 * error.powf(-stepper.error_exponent())
    } else {
        5.0
    };
    let grow = if held { 1.0 } else { 5.0 };
    let h_next = h * factor.clamp(0.2, grow);
    if last {
        h_next.max(h)
    } else {
        h_next
    }
}

/// The first contact onset or separation inside an accepted step, `(theta, joint)`.
fn locate_event<K: Kind>(
    ode: &mut Ode<'_, K>,
    log: &mut ImpactLog<PointOf<K>>,
    step: &DenseStep,
    sample: &mut [f64],
) -> Option<(f64, usize)> {
    let lap = profile::start(&ode.ws.profile);
    let event = events::locate(ode.sys, &ode.ws.contacts, log, step, sample);
    profile::stop(&mut ode.ws.profile, lap, |p| &mut p.events);
    event
}

/// Records the output grid's samples inside the accepted part `(t, t_new]` of a step,
/// from its dense output, following the contact modes at each.
fn record_samples_inside<K: Kind>(
    ode: &mut Ode<'_, K>,
    rec: &mut Recorder<K>,
    log: &mut ImpactLog<PointOf<K>>,
    step: &DenseStep,
    (t, t_new): (f64, f64),
    grid: &mut Sampling,
    sample: &mut [f64],
) -> Result<(), Status> {
    let sys = ode.sys;
    let n = sys.layout.nq();
    let t_end = grid.t_end;
    let lap = profile::start(&ode.ws.profile);
    if rec.begin_step(sys, &ode.ws.contacts, step, t, t_new).is_err() {
        return Err(singular(t));
    }
    while let Some(ts) = grid.next_time() {
        if ts > t_new * (1.0 + 1e-14) || ts > t_end * (1.0 + 1e-12) {
            break;
        }
        // The last grid time is the end time, whatever its rounding.
        let ts = if (ts - t_end).abs() <= 1e-12 * t_end { t_end } else { ts };
        let ts = ts.min(t_new);
        step.at((ts - t) / step.h, sample);
        let (q, v) = sample.split_at(n);
        rec.push(sys, &mut ode.ws, ts, q, v).map_err(|error| sample_failed(ts, error))?;
        rec.mark_sample();
        log.update(sys, &mut ode.ws.contacts, q, v);
        grid.next += 1;
    }
    profile::stop(&mut ode.ws.profile, lap, |p| &mut p.output);
    Ok(())
}

/// A state that is no longer finite ends the run, naming the coordinate.
fn check_state_finite<K: Kind>(sys: &crate::system::System<K>, t: f64, y: &[f64]) -> Result<(), Status> {
    match y.iter().position(|x| !x.is_finite()) {
        Some(i) => {
            let name = record::state_name(sys, i);
            Err(fail(t, format!("the state became non-finite, {name} = {}: {NON_FINITE_CAUSE}", y[i])))
        }
        None => Ok(()),
    }
}

/// Keeps the drift far below the tolerance: projects the state at `t` onto the
/// constraints when its residuals exceed [`drift_limits`]. `drift`: the residuals and
/// their rounding floor, when the step's last evaluation was at this state. Returns
/// whether it projected.
fn keep_on_constraints<K: Kind>(
    ode: &mut Ode<'_, K>,
    t: f64,
    y: &mut [f64],
    drift: Option<((f64, f64), (f64, f64))>,
    stats: &mut RunStats,
) -> Result<bool, Status> {
    let sys = ode.sys;
    let n = sys.layout.nq();
    let lap = profile::start(&ode.ws.profile);
    let ((pos, vel), rounding) = match drift {
        Some(drift) => drift,
        None => {
            let (q, v) = y.split_at(n);
            let residuals = violation(sys, t, q, v, &mut ode.ws);
            (residuals, rounding_where_needed(ode, residuals, q, v))
        }
    };
    let (pos_limit, vel_limit) = drift_limits(ode.tolerances.atol, rounding);
    let projected = pos > pos_limit || vel > vel_limit;
    if projected {
        let (q, v) = y.split_at_mut(n);
        if project(sys, t, q, v, &mut ode.ws, pos_limit).is_err() {
            return Err(singular(t));
        }
        stats.projections += 1;
    }
    profile::stop(&mut ode.ws.profile, lap, |p| &mut p.projection);
    Ok(projected)
}

/// The rounding floor of the constraint residuals `(pos, vel)` at `(q, v)`
/// ([`crate::dynamics::Workspace::rounding`], from the last evaluation, made there); zero
/// where the residuals are within the tolerance's own limits, as there the floor changes
/// nothing.
fn rounding_where_needed<K: Kind>(
    ode: &Ode<'_, K>,
    (pos, vel): (f64, f64),
    q: &[f64],
    v: &[f64],
) -> (f64, f64) {
    let (pos_limit, vel_limit) = drift_limits(ode.tolerances.atol, (0.0, 0.0));
    if pos > pos_limit || vel > vel_limit {
        ode.ws.rounding(q, v)
    } else {
        (0.0, 0.0)
    }
}

/// At an accepted step's end `(t, y)`: records it when every step is recorded, else
/// raises the channels' peaks there when asked.
fn record_step_end<K: Kind>(
    ode: &mut Ode<'_, K>,
    rec: &mut Recorder<K>,
    grid: &Sampling,
    t: f64,
    y: &[f64],
) -> Result<(), Status> {
    let sys = ode.sys;
    let (q, v) = y.split_at(sys.layout.nq());
    let lap = profile::start(&ode.ws.profile);
    if grid.every_step && rec.last_time.is_none_or(|tl| tl < t) {
        rec.push(sys, &mut ode.ws, t, q, v).map_err(|error| sample_failed(t, error))?;
    }
    if !grid.every_step && grid.step_peaks {
        rec.peek(sys, &mut ode.ws, t, q, v).map_err(|error| sample_failed(t, error))?;
    }
    profile::stop(&mut ode.ws.profile, lap, |p| &mut p.output);
    Ok(())
}

/// Hands the samples recorded so far to a monitor that takes them in chunks of `chunk`,
/// once a chunk is full.
fn hand_over_samples<K: Kind>(
    monitor: &mut dyn Monitor,
    chunk: Option<usize>,
    rec: &mut Recorder<K>,
    t: f64,
) -> Result<(), Status> {
    if chunk.is_some_and(|c| rec.time.len() >= c) {
        if let Err(stop) = monitor.samples(&rec.names(), &rec.time, &rec.data) {
            return Err(stop.status(t, "stopped by the output sink"));
        }
        rec.clear();
    }
    Ok(())
}

/// Position and velocity residuals above which a step's end is projected onto the
/// constraints: a hundredth of `atol`, but no less than what the rounding of the state
/// leaves in them ([`Workspace::rounding`](crate::dynamics::Workspace::rounding)), which
/// grows with the angle of a crank that turns on. Below that floor a projection removes
/// nothing that the next step's rounding does not bring back, and a fixed threshold
/// projected more of the steps the longer the run (17 % at 5 s, 29 % at 60 s in the
/// founding case).
pub fn drift_limits(atol: f64, (position_rounding, velocity_rounding): (f64, f64)) -> (f64, f64) {
    ((1e-2 * atol).max(position_rounding), (1e-2 * atol).max(velocity_rounding))
}

/// Starting step (Hairer, Norsett, Wanner I, II.4, algorithm of `hinit`).
fn initial_step<K: Kind>(ode: &mut Ode<'_, K>, y: &[f64], f: &[f64], exponent: f64, horizon: f64) -> f64 {
    let zeros = vec![0.0; y.len()];
    let d0 = ode.tolerances.error_norm(y, &zeros, y);
    let d1 = ode.tolerances.error_norm(f, &zeros, y);
    let mut h0 = if d0 < 1e-5 || d1 < 1e-5 { 1e-6 } else { 0.01 * d0 / d1 };
    h0 = h0.min(horizon);
    let y1: Vec<f64> = y.iter().zip(f).map(|(a, b)| a + h0 * b).collect();
    let mut f1 = vec![0.0; y.len()];
    if ode.rhs(h0, &y1, &mut f1).is_err() {
        return h0;
    }
    let diff: Vec<f64> = f1.iter().zip(f).map(|(a, b)| a - b).collect();
    let d2 = ode.tolerances.error_norm(&diff, &zeros, y) / h0;
    let h1 = if d1.max(d2) <= 1e-15 { (h0 * 1e-3).max(1e-6) } else { (0.01 / d1.max(d2)).powf(exponent) };
    (100.0 * h0).min(h1).min(horizon)
}
