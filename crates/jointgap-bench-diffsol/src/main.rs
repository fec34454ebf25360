//! Does `diffsol` serve as jointgap's stiff integrator? The ideal founding slider-crank
//! (1 s, crank ramped to 300 rpm in 0.2 s, vertical plane) integrated by diffsol's BDF,
//! TR-BDF2, ESDIRK34 and Tsit45 on jointgap's own right-hand side, against jointgap's
//! sdirk4 and dopri5 at the same tolerances. Writes benchmarks/output/diffsol.md.
//!
//! The ODE is `y = (q, v)`, `f = jointgap_core::simulate::equations::Ode::rhs`, set up as
//! `simulate::simulate` does. The Jacobian is dense, built by diffsol column by column from
//! a forward-difference Jacobian-vector product. diffsol knows nothing of the ramp's
//! corner at 0.2 s: each run is two solves, [0, 0.2] and [0.2, 1], the second started
//! afresh from the first's end state (jointgap's integrator does the same at corners).
//! diffsol does not project onto the constraints: the drift is reported, and variants
//! apply jointgap's projection between steps.

#[path = "../../jointgap-core/tests/common.rs"]
mod common;

use std::cell::RefCell;
use std::error::Error;
use std::fmt::Write as _;
use std::time::Instant;

use diffsol::{
    NalgebraLU, NalgebraMat, OdeBuilder, OdeEquations, OdeSolverMethod, OdeSolverStopReason, Vector,
};
use jointgap_core::dynamics::{accelerations, constraints, project, violation, Workspace};
use jointgap_core::simulate::equations::Ode;
use jointgap_core::{simulate, Method, Model, SimOptions, SimResult};

const T_END: f64 = 1.0;
const RATE: f64 = 10_000.0;
/// Step budget of one solve.
const MAX_STEPS: usize = 100_000;

#[derive(Clone, Copy, Debug)]
enum Solver {
    Bdf,
    TrBdf2,
    Esdirk34,
    Tsit45,
}

/// The right-hand side with the cache of the last `f(x)` for the Jacobian columns.
struct Eval<'a> {
    ode: Ode<'a>,
    x: Vec<f64>,
    t: f64,
    fx: Vec<f64>,
    xp: Vec<f64>,
    fp: Vec<f64>,
}

impl Eval<'_> {
    fn rhs(&mut self, t: f64, x: &[f64], f: &mut [f64]) {
        if self.ode.rhs(t, x, f).is_err() {
            f.fill(f64::NAN); // singular: diffsol sees a failed evaluation
        }
    }

    /// `J v ~ (f(x + e v) - f(x)) / e`, with `f(x)` reused across the columns of one Jacobian.
    fn jac_vec(&mut self, t: f64, x: &[f64], v: &[f64], jv: &mut [f64]) {
        let norm = |a: &[f64]| a.iter().map(|z| z * z).sum::<f64>().sqrt();
        let vn = norm(v);
        if vn == 0.0 {
            jv.fill(0.0);
            return;
        }
        if self.t != t || self.x != x {
            let mut fx = std::mem::take(&mut self.fx);
            self.rhs(t, x, &mut fx);
            self.fx = fx;
            self.x = x.to_vec();
            self.t = t;
        }
        let e = f64::EPSILON.sqrt() * (1.0 + norm(x)) / vn;
        for i in 0..x.len() {
            self.xp[i] = x[i] + e * v[i];
        }
        let (xp, mut fp) = (std::mem::take(&mut self.xp), std::mem::take(&mut self.fp));
        self.rhs(t, &xp, &mut fp);
        for i in 0..x.len() {
            jv[i] = (fp[i] - self.fx[i]) / e;
        }
        (self.xp, self.fp) = (xp, fp);
    }
}

#[derive(Default)]
struct Outcome {
    wall: f64,
    steps: usize,
    rejected: usize,
    newton_fails: usize,
    rhs: usize,
    lu_setups: usize,
    err_ax: f64,
    err_x_end: f64,
    drift_end: f64,
    projections: usize,
}

/// Steps `s` to its stop time, calling `sample(t, y)` at each of `times` passed on the way
/// and `fix(t, y, dy)` after each step (it may project `y` and then sets `dy = f(y)`);
/// returns the end state and the counts of steps, error-test failures, Newton failures
/// and LU setups.
fn drive<'a, Eqn, S>(
    mut s: S,
    stop: f64,
    times: &[f64],
    sample: &mut impl FnMut(f64, &[f64]),
    fix: &mut impl FnMut(f64, &mut [f64], &mut [f64]) -> bool,
) -> Result<(Vec<f64>, [usize; 4]), Box<dyn Error>>
where
    Eqn: OdeEquations<T = f64> + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    s.set_stop_time(stop)?;
    let mut k = 0;
    loop {
        if s.get_statistics().number_of_steps >= MAX_STEPS {
            return Err(format!("gave up after {MAX_STEPS} steps at t = {:.4} s", s.state().t).into());
        }
        let reason = s.step()?;
        while k < times.len() && times[k] <= s.state().t {
            sample(times[k], &s.interpolate(times[k])?.clone_as_vec());
            k += 1;
        }
        let (t, mut y) = (s.state().t, s.state().y.clone_as_vec());
        let mut dy = vec![0.0; y.len()];
        if !matches!(reason, OdeSolverStopReason::TstopReached) && fix(t, &mut y, &mut dy) {
            let ctx = s.state().y.context().clone();
            let st = s.state_mut();
            st.y.copy_from(&Eqn::V::from_slice(&y, ctx.clone()));
            st.dy.copy_from(&Eqn::V::from_slice(&dy, ctx));
        }
        if matches!(reason, OdeSolverStopReason::TstopReached) {
            let st = s.get_statistics();
            let counts = [
                st.number_of_steps,
                st.number_of_error_test_failures,
                st.number_of_nonlinear_solver_fails,
                st.number_of_linear_solver_setups,
            ];
            return Ok((s.state().y.clone_as_vec(), counts));
        }
    }
}

/// One run: prepare, two solves, slider acceleration at each sample from the state;
/// with `projecting`, jointgap's projection after each step where the drift shows.
fn run(
    model: &Model,
    which: Solver,
    rtol: f64,
    dense: bool,
    projecting: bool,
) -> Result<Outcome, Box<dyn Error>> {
    let started = Instant::now();
    let prepared = jointgap_core::simulate::prepare(model).expect("model assembles");
    let sys = &prepared.system;
    let n = sys.layout.nv();
    let slider = sys.bodies.iter().position(|b| b.name == "slider").unwrap();
    let ode = Ode::new(sys, prepared.initial.active.clone(), rtol, rtol * 1e-2);
    let cell = RefCell::new(Eval {
        ode,
        x: Vec::new(),
        t: f64::NAN,
        fx: vec![0.0; 2 * n],
        xp: vec![0.0; 2 * n],
        fp: vec![0.0; 2 * n],
    });
    // Samples: slider x and ax from the state, as jointgap's recorder does.
    let mut ws = Workspace::new(sys, prepared.initial.active.clone());
    let mut out = Outcome::default();
    let mut record = |t: f64, y: &[f64], piece: f64| {
        ws.t_piece = piece;
        accelerations(sys, t, &y[..n], &y[n..], &mut ws).expect("regular state");
        let exact = common::slider_closed_form(t);
        out.err_ax = out.err_ax.max((ws.qdd[3 * slider] - exact.2).abs());
        if t == T_END {
            out.err_x_end = (y[3 * slider] - exact.0).abs();
            constraints(sys, t, &y[..n], &y[n..], &mut ws);
            out.drift_end = ws.c.amax();
        }
    };
    // jointgap's rule (simulate::integrate): project when the drift exceeds 1e-2 atol.
    let mut projections = 0;
    let mut fix = |t: f64, y: &mut [f64], dy: &mut [f64]| {
        let mut e = cell.borrow_mut();
        let (q, v) = y.split_at_mut(n);
        let (pos, vel) = violation(sys, t, q, v, &mut e.ode.ws);
        if !projecting || (pos <= 1e-4 * rtol && vel <= 1e-4 * rtol) {
            return false;
        }
        project(sys, t, q, v, &mut e.ode.ws, 1e-4 * rtol).expect("projection converges");
        e.rhs(t, y, dy);
        projections += 1;
        true
    };
    let mut y = [prepared.initial.q.as_slice(), prepared.initial.v.as_slice()].concat();
    if dense {
        record(0.0, &y, 0.0);
    }
    for (a, b) in [(0.0, common::T_RAMP), (common::T_RAMP, T_END)] {
        let piece = 0.5 * (a + b);
        cell.borrow_mut().ode.ws.t_piece = piece;
        let times: Vec<f64> = if dense {
            (0..=(T_END * RATE) as usize).map(|k| k as f64 / RATE).filter(|&t| t > a && t <= b).collect()
        } else if b == T_END {
            vec![T_END]
        } else {
            Vec::new()
        };
        let y0 = y.clone();
        let problem = OdeBuilder::<NalgebraMat<f64>>::new()
            .t0(a)
            .rtol(rtol)
            .atol([rtol * 1e-2])
            .rhs_implicit(
                |x, _p, t, f| cell.borrow_mut().rhs(t, x, f),
                |x, _p, t, v, jv| cell.borrow_mut().jac_vec(t, x, v, jv),
            )
            .init(move |_p, _t, y| y.copy_from_slice(&y0), 2 * n)
            .build()?;
        let mut on_sample = |t: f64, y: &[f64]| record(t, y, piece);
        let (y_end, st) = match which {
            Solver::Bdf => drive(problem.bdf::<NalgebraLU<f64>>()?, b, &times, &mut on_sample, &mut fix)?,
            Solver::TrBdf2 => {
                drive(problem.tr_bdf2::<NalgebraLU<f64>>()?, b, &times, &mut on_sample, &mut fix)?
            }
            Solver::Esdirk34 => {
                drive(problem.esdirk34::<NalgebraLU<f64>>()?, b, &times, &mut on_sample, &mut fix)?
            }
            Solver::Tsit45 => drive(problem.tsit45()?, b, &times, &mut on_sample, &mut fix)?,
        };
        y = y_end;
        out.steps += st[0];
        out.rejected += st[1];
        out.newton_fails += st[2];
        out.lu_setups += st[3];
    }
    out.rhs = cell.borrow().ode.evaluations;
    out.projections = projections;
    out.wall = started.elapsed().as_secs_f64();
    Ok(out)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median over at least 3 runs (more while under 1 s), after one warm-up.
fn repeat<T>(mut f: impl FnMut() -> (f64, T)) -> (f64, T) {
    let (_, first) = f();
    let mut walls = Vec::new();
    let started = Instant::now();
    while walls.len() < 3 || (walls.len() < 31 && started.elapsed().as_secs_f64() < 1.0) {
        walls.push(f().0);
    }
    (median(walls), first)
}

fn jointgap_row(model: &Model, method: Method, rtol: f64, dense: bool) -> String {
    let opts = SimOptions {
        rate: Some(if dense { RATE } else { 1.0 }),
        rtol,
        atol: rtol * 1e-2,
        method,
        channels: Some(vec!["slider.*".into(), "system.constraint_error".into()]),
        ..SimOptions::new(T_END)
    };
    let (wall, res): (f64, SimResult) = repeat(|| {
        let t = Instant::now();
        let r = simulate(model, &opts).unwrap();
        (t.elapsed().as_secs_f64(), r)
    });
    let s = &res.stats;
    let ax = res.channel("slider.ax").unwrap();
    let x = res.channel("slider.x").unwrap();
    let err_ax = res
        .time
        .iter()
        .zip(ax)
        .map(|(&t, a)| (a - common::slider_closed_form(t).2).abs())
        .fold(0.0, f64::max);
    let err_x_end = (x.last().unwrap() - common::slider_closed_form(T_END).0).abs();
    let drift = res.channel("system.constraint_error").unwrap().last().unwrap();
    format!(
        "| jointgap {} | {rtol:.0e} | {:.2} | {} | {} | - | {} | {} Jacobians | {} | {err_ax:.2e} | {err_x_end:.1e} | {drift:.1e} |",
        method.name(),
        wall * 1e3,
        s.accepted_steps,
        s.rejected_steps,
        s.rhs_evaluations,
        s.jacobian_evaluations,
        s.projections
    )
}

fn main() {
    let model = common::slider_crank(9.81);
    let mut md = String::new();
    writeln!(md, "## diffsol 0.18 on jointgap's right-hand side\n").unwrap();
    writeln!(
        md,
        "Ideal slider-crank, 1 s, atol = rtol x 1e-2 (diffsol: the same scalar atol for every \
         state). Wall: median of >= 3 runs, each including `prepare` (compile + assembly). diffsol \
         runs are two solves split at the ramp corner (0.2 s); its Jacobian is dense, from \
         forward-difference Jacobian-vector products (one RHS per column, f(x) reused). Plain \
         diffsol does not project, so the constraint drift at 1 s is shown; '+ projection' rows \
         apply jointgap's `project` after each step where the drift exceeds 1e-2 atol (through \
         `state_mut`, which restarts BDF at order 1). jointgap rows record `slider.*`. err ax: \
         max |slider ax - closed form| over the samples, computed from the state with \
         `accelerations` for diffsol. 'steps': accepted steps; 'rej.': error-test failures; \
         'Newton fails': diffsol's nonlinear-solver failures; 'LU': diffsol's Jacobian/LU setups.\n"
    )
    .unwrap();
    let solvers = [Solver::Bdf, Solver::TrBdf2, Solver::Esdirk34, Solver::Tsit45];
    for (dense, title) in
        [(true, "10 kHz samples (each with an `accelerations` call)"), (false, "state at 1 s only")]
    {
        writeln!(md, "### Output: {title}\n").unwrap();
        writeln!(md, "| solver | rtol | wall [ms] | steps | rej. | Newton fails | RHS | LU / Jacobians | proj. | max err ax [m/s^2] | err x(1 s) [m] | drift at 1 s [m] |").unwrap();
        writeln!(md, "|---|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|").unwrap();
        for rtol in [1e-6, 1e-9] {
            for m in [Method::Dopri5, Method::Sdirk4] {
                writeln!(md, "{}", jointgap_row(&model, m, rtol, dense)).unwrap();
            }
            let variants = if dense { vec![false] } else { vec![false, true] };
            for projecting in variants {
                for which in solvers {
                    let name = format!("diffsol {which:?}{}", if projecting { " + projection" } else { "" });
                    let line = match run(&model, which, rtol, dense, projecting) {
                        Err(e) => format!("| {name} | {rtol:.0e} | failed: {e} | | | | | | | | | |"),
                        Ok(o) => {
                            let (wall, ()) = repeat(|| {
                                (run(&model, which, rtol, dense, projecting).map_or(f64::NAN, |o| o.wall), ())
                            });
                            format!(
                                "| {name} | {rtol:.0e} | {:.2} | {} | {} | {} | {} | {} LU | {} | {:.2e} | {:.1e} | {:.1e} |",
                                wall * 1e3,
                                o.steps,
                                o.rejected,
                                o.newton_fails,
                                o.rhs,
                                o.lu_setups,
                                o.projections,
                                o.err_ax,
                                o.err_x_end,
                                o.drift_end
                            )
                        }
                    };
                    eprintln!("{line}");
                    writeln!(md, "{line}").unwrap();
                }
            }
        }
        writeln!(md).unwrap();
    }
    print!("{md}");
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../benchmarks/output");
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(format!("{dir}/diffsol.md"), &md).unwrap();
    eprintln!("wrote benchmarks/output/diffsol.md");
}
