//! The integration loop shared by all methods: steps between input corners, error
//! control, switching to the implicit method when the problem turns stiff, projection
//! onto the constraints, and output at sample times by quintic Hermite interpolation.

use super::equations::Ode;
use super::events::{self, ImpactLog};
use super::monitor::{Monitor, Progress};
use super::options::{Method, SimOptions};
use super::record::{self, Recorder, SampleError, NON_FINITE_CAUSE};
use super::switching::AutoSwitch;
use crate::dynamics::{friction_rate, project, violation};
use crate::integrators::dopri5::Dopri5;
use crate::integrators::ode::DenseStep;
use crate::integrators::radau5::Radau5;
use crate::integrators::sdirk4::Sdirk4;
use crate::integrators::stepper::{StepFailure, Stepper};
use crate::output::{RunStats, Status};
use crate::profile;

/// Integrates from `(0, y)` to `t_end`, recording into `rec` and reporting to `monitor`.
/// Returns the final status.
pub fn integrate(
    ode: &mut Ode,
    opts: &SimOptions,
    y: &mut Vec<f64>,
    rec: &mut Recorder,
    log: &mut ImpactLog,
    stats: &mut RunStats,
    monitor: &mut dyn Monitor,
) -> Status {
    let started = std::time::Instant::now();
    let report_every = monitor.progress_interval();
    let mut next_report = report_every.unwrap_or(f64::INFINITY);
    let chunk = monitor.chunk_len();
    let n_state = ode.state_len();
    let n = n_state / 2;
    let sys = ode.sys;
    let mut method = if opts.method == Method::Auto { Method::Dopri5 } else { opts.method };
    let mut stepper: Box<dyn Stepper<Ode>> = match method {
        Method::Sdirk4 => Box::new(Sdirk4::new(n_state)),
        Method::Radau5 => Box::new(Radau5::new(n_state)),
        _ => Box::new(Dopri5::new(n_state)),
    };
    let mut switch = AutoSwitch::default();
    let mut f = vec![0.0; n_state];
    let mut y_new = vec![0.0; n_state];
    let mut f_new = vec![0.0; n_state];
    let mut sample = vec![0.0; n_state];

    let mut t = 0.0;
    let sample_dt = opts.rate.map(|r| 1.0 / r);
    let mut next_sample = 1usize; // sample 0 is recorded by the caller
    let sample_time = |k: usize| sample_dt.map(|dt| k as f64 * dt);
    let every_step = opts.every_step || opts.rate.is_none();
    let budget = opts.step_budget();

    let mut boundaries: Vec<f64> = sys.corners.iter().copied().filter(|&c| c < opts.t_end).collect();
    boundaries.push(opts.t_end);

    let fail = |t: f64, reason: String| Status::Failed { time: t, reason };
    let singular = |t: f64| {
        fail(t, format!(
            "the constraint equations became singular at t = {t:.6} s: the mechanism locks up or passes a \
             singular position (e.g. a four-bar at a change point, a crank at a dead centre with the driver on the rod)"
        ))
    };
    let sample_failed = |t: f64, error: SampleError| match error {
        SampleError::Singular => singular(t),
        SampleError::NonFinite { channel, value } => {
            fail(t, format!("{channel} = {value}: {NON_FINITE_CAUSE}"))
        }
    };
    // Every exit leads past the counters below, so a failed run reports them too.
    let status = 'run: {
        ode.ws.t_piece = 0.0;
        if ode.rhs(t, y, &mut f).is_err() {
            break 'run singular(t);
        }
        let mut h = initial_step(ode, y, &f, stepper.error_exponent(), boundaries[0]);
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
                let remaining = segment_end - t;
                let hmin = 1e-14 * t.abs().max(1e-3);
                // A step that would leave a remainder too small to step over ends the segment.
                let last = h >= remaining * (1.0 - 1e-12) || remaining - h < 4.0 * hmin;
                if last {
                    h = remaining;
                }
                if h < hmin {
                    break 'run fail(
                        t,
                        format!("step size {h:.3e} s below the smallest resolvable step at t = {t:.6} s"),
                    );
                }
                ode.ws.t_piece = t + 0.5 * h;
                let tol = ode.tolerances;
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
                        let factor = if let Some(f) = stepper.step_factor() {
                            f
                        } else if att.error.is_finite() {
                            0.9 * att.error.powf(-stepper.error_exponent())
                        } else {
                            0.1
                        };
                        h *= factor.clamp(0.1, 0.9);
                        last_rejected = true;
                    }
                    Ok(att) => {
                        stats.accepted_steps += 1;
                        // The drift at the step's end from the step's last evaluation, taken
                        // before output samples reuse the workspace.
                        let drift_at_end =
                            (ode.ws.violation_here(&y_new[n..]), ode.ws.rounding(&y_new[..n], &y_new[n..]));
                        // A contact onset or separation inside the step ends the step there.
                        let lap = profile::start(&ode.ws.profile);
                        let step = DenseStep { h, y0: y, f0: &f, y1: &y_new, f1: &f_new };
                        let event = events::locate(sys, &ode.ws.contacts, log, &step, &mut sample);
                        profile::stop(&mut ode.ws.profile, lap, |p| &mut p.events);
                        let (t_new, last) = match event {
                            Some((theta, _)) if theta < 1.0 => (t + theta * h, false),
                            _ => (if last { segment_end } else { t + h }, last),
                        };
                        log.dwell(&ode.ws.contacts, t_new - t);
                        // Output samples inside (t, t_new].
                        let lap = profile::start(&ode.ws.profile);
                        if rec.begin_step(sys, &ode.ws.contacts, &step, t, t_new).is_err() {
                            break 'run singular(t);
                        }
                        while let Some(ts) = sample_time(next_sample) {
                            if ts > t_new * (1.0 + 1e-14) || ts > opts.t_end * (1.0 + 1e-12) {
                                break;
                            }
                            // The last grid time is the end time, whatever its rounding.
                            let ts =
                                if (ts - opts.t_end).abs() <= 1e-12 * opts.t_end { opts.t_end } else { ts };
                            let ts = ts.min(t_new);
                            step.at((ts - t) / h, &mut sample);
                            let (q, v) = sample.split_at(n);
                            if let Err(error) = rec.push(sys, &mut ode.ws, ts, q, v) {
                                break 'run sample_failed(ts, error);
                            }
                            rec.mark_sample();
                            log.update(sys, &mut ode.ws.contacts, q, v);
                            next_sample += 1;
                        }
                        profile::stop(&mut ode.ws.profile, lap, |p| &mut p.output);
                        let mut refresh = false;
                        if let Some((theta, k)) = event {
                            if theta < 1.0 {
                                step.at(theta, &mut sample);
                                y_new.copy_from_slice(&sample);
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
                        if let Some(i) = y.iter().position(|x| !x.is_finite()) {
                            let name = record::state_name(sys, i);
                            break 'run fail(
                                t,
                                format!("the state became non-finite, {name} = {}: {NON_FINITE_CAUSE}", y[i]),
                            );
                        }
                        // Keep the drift far below the tolerance: project when it shows.
                        let lap = profile::start(&ode.ws.profile);
                        let ((pos, vel), rounding) = if at_attempt_end {
                            drift_at_end
                        } else {
                            let (q, v) = y.split_at(n);
                            (violation(sys, t, q, v, &mut ode.ws), ode.ws.rounding(q, v))
                        };
                        let (pos_limit, vel_limit) = drift_limits(ode.tolerances.atol, rounding);
                        if pos > pos_limit || vel > vel_limit {
                            let (q, v) = y.split_at_mut(n);
                            if project(sys, t, q, v, &mut ode.ws).is_err() {
                                break 'run singular(t);
                            }
                            stats.projections += 1;
                            refresh = true;
                        }
                        profile::stop(&mut ode.ws.profile, lap, |p| &mut p.projection);
                        if refresh {
                            ode.ws.t_piece = t - 0.5 * h_taken;
                            if ode.rhs(t, y, &mut f).is_err() {
                                break 'run singular(t);
                            }
                        }
                        log.update(sys, &mut ode.ws.contacts, &y[..n], &y[n..]);
                        let lap = profile::start(&ode.ws.profile);
                        if every_step && rec.last_time.is_none_or(|tl| tl < t) {
                            if let Err(error) = rec.push(sys, &mut ode.ws, t, &y[..n], &y[n..]) {
                                break 'run sample_failed(t, error);
                            }
                        }
                        if !every_step && opts.step_peaks {
                            if let Err(error) = rec.peek(sys, &mut ode.ws, t, &y[..n], &y[n..]) {
                                break 'run sample_failed(t, error);
                            }
                        }
                        profile::stop(&mut ode.ws.profile, lap, |p| &mut p.output);
                        if chunk.is_some_and(|c| rec.time.len() >= c) {
                            if let Err(stop) = monitor.samples(&rec.names(), &rec.time, &rec.data) {
                                break 'run stop.status(t, "stopped by the output sink");
                            }
                            rec.clear();
                        }
                        if report_every.is_some() && stats.accepted_steps.is_multiple_of(16) {
                            let wall_time = started.elapsed().as_secs_f64();
                            if wall_time >= next_report {
                                next_report = wall_time + report_every.unwrap_or(f64::INFINITY);
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
                        }
                        if opts.method == Method::Auto {
                            let radius = if switch.wants_radius(method) {
                                stepper.spectral_radius(ode, t, y, &f)
                            } else {
                                None
                            };
                            let (q, v) = y.split_at(n);
                            let friction = friction_rate(sys, q, v, &mut ode.ws);
                            let next = switch.after_step(
                                method,
                                (t, h_taken, h_taken * stepper.step_factor().unwrap_or(1.0)),
                                ode.evaluations,
                                (att.stiffness, radius),
                                friction,
                            );
                            if let Some(next) = next {
                                method = next;
                                stats.jacobian_evaluations += stepper.jacobian_evaluations();
                                stepper = match next {
                                    Method::Sdirk4 => Box::new(Sdirk4::new(n_state)),
                                    Method::Radau5 => Box::new(Radau5::new(n_state)),
                                    _ => Box::new(Dopri5::new(n_state)),
                                };
                            }
                        }
                        let factor = if let Some(f) = stepper.step_factor() {
                            f
                        } else if att.error > 0.0 {
                            0.9 * att.error.powf(-stepper.error_exponent())
                        } else {
                            5.0
                        };
                        let grow = if last_rejected || event.is_some() { 1.0 } else { 5.0 };
                        let h_next = h * factor.clamp(0.2, grow);
                        // A step cut short by a corner does not shrink the next one.
                        h = if last { h_next.max(h) } else { h_next };
                        last_rejected = false;
                    }
                }
            }
        }
        Status::Finished
    };
    if let Some(p) = ode.ws.profile.as_mut() {
        p.total = started.elapsed().as_secs_f64();
    }
    stats.jacobian_evaluations += stepper.jacobian_evaluations();
    stats.method =
        if opts.method == Method::Auto { switch.describe(method, t) } else { stepper.name().to_string() };
    status
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
fn initial_step(ode: &mut Ode, y: &[f64], f: &[f64], exponent: f64, horizon: f64) -> f64 {
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
