//! `make bench`: speed and accuracy of the ideal founding slider-crank (crank ramped
//! 0 -> 300 rpm in 0.2 s, vertical plane), 1 s simulated, and where the time goes.
//! Prints Markdown tables and writes them to benchmarks/output/bench_ideal.md.

#[path = "../tests/common.rs"]
mod common;

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Instant;

use jointgap_core::dynamics::{
    accelerations, applied_forces, constraints, project, violation, Workspace, POSITION_TOL,
};
use jointgap_core::integrators::ode::hermite5;
use jointgap_core::simulate::equations::{state_shape, Ode};
use jointgap_core::simulate::integrate::stepper;
use jointgap_core::simulate::record::Recorder;
use jointgap_core::{simulate, Method, Model, SimOptions, SimResult, Status};

const T_END: f64 = 1.0;
const RATE: f64 = 10_000.0;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median wall time [s] of at least 7 runs (one warm-up first), more while under 1 s.
fn timed_runs(model: &Model, opts: &SimOptions) -> (f64, SimResult) {
    let res = simulate(model, opts).unwrap();
    let mut times = Vec::new();
    let started = Instant::now();
    while times.len() < 7 || (times.len() < 51 && started.elapsed().as_secs_f64() < 1.0) {
        let t = Instant::now();
        black_box(simulate(model, opts).unwrap());
        times.push(t.elapsed().as_secs_f64());
    }
    (median(times), res)
}

/// Median over 7 batches of the time per call [ns]; batches last at least 20 ms.
fn ns_per_call(mut f: impl FnMut()) -> f64 {
    let mut n = 64;
    loop {
        let t = Instant::now();
        for _ in 0..n {
            f();
        }
        if t.elapsed().as_secs_f64() > 0.02 {
            break;
        }
        n *= 2;
    }
    median(
        (0..7)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..n {
                    f();
                }
                t.elapsed().as_secs_f64() * 1e9 / n as f64
            })
            .collect(),
    )
}

/// Max |slider.ax - closed form| over the samples, and the closed-form peak |a|.
fn slider_error(res: &SimResult) -> (f64, f64) {
    let ax = res.channel("slider.ax").unwrap();
    let (mut err, mut peak) = (0.0f64, 0.0f64);
    for (i, &t) in res.time.iter().enumerate() {
        let exact = common::slider_closed_form(t).2;
        err = err.max((ax[i] - exact).abs());
        peak = peak.max(exact.abs());
    }
    (err, peak)
}

fn main() {
    let model = common::slider_crank(9.81);
    let mut md = String::new();
    let mut runs = Vec::new();

    writeln!(md, "## Ideal slider-crank, 1 s simulated (Rust, `jointgap_core::simulate`)\n").unwrap();
    writeln!(
        md,
        "atol = rtol x 1e-2. Wall: median of >= 7 runs, model parsed once (each run compiles, \
         assembles, integrates and records). Error: max |slider.ax - closed form| over the \
         samples; peak |a| of the closed form is 98.7 m/s^2 (for the 1 Hz rows: the samples are \
         t = 0 and 1 s only).\n"
    )
    .unwrap();
    writeln!(md, "| method | rtol | output | wall [ms] | accepted | rejected | RHS | Jacobians | projections | max abs err [m/s^2] | rel. to peak |").unwrap();
    writeln!(md, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|").unwrap();
    let outputs: [(&str, f64, bool); 3] = [
        ("all channels @ 10 kHz", RATE, false),
        ("slider.* @ 10 kHz", RATE, true),
        ("slider.* @ 1 Hz", 1.0, true),
    ];
    for method in [Method::Dopri5, Method::Sdirk4, Method::Auto] {
        for rtol in [1e-6, 1e-9] {
            for (label, rate, only_slider) in outputs {
                let opts = SimOptions {
                    rate: Some(rate),
                    rtol,
                    atol: rtol * 1e-2,
                    method,
                    channels: only_slider.then(|| vec!["slider.*".to_string()]),
                    ..SimOptions::new(T_END)
                };
                let (wall, res) = timed_runs(&model, &opts);
                assert_eq!(res.status, Status::Finished, "{method:?} rtol {rtol}");
                let s = &res.stats;
                let (err, peak) = slider_error(&res);
                writeln!(
                    md,
                    "| {} | {rtol:.0e} | {label} | {:.2} | {} | {} | {} | {} | {} | {err:.2e} | {:.1e} |",
                    s.method,
                    wall * 1e3,
                    s.accepted_steps,
                    s.rejected_steps,
                    s.rhs_evaluations,
                    s.jacobian_evaluations,
                    s.projections,
                    err / peak,
                )
                .unwrap();
                runs.push((method, rtol, label, wall, res));
            }
        }
    }

    where_time_goes(&model, &runs, &mut md);
    print!("{md}");
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../benchmarks/output");
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(format!("{dir}/bench_ideal.md"), &md).unwrap();
    eprintln!("wrote benchmarks/output/bench_ideal.md");
}

type Run = (Method, f64, &'static str, f64, SimResult);

/// Microbenchmarks of the pipeline stages at the state of t = 0.5 s, then the share of
/// whole runs they explain (count x cost).
fn where_time_goes(model: &Model, runs: &[Run], md: &mut String) {
    let prepared = jointgap_core::simulate::prepare(model).unwrap();
    let sys = &prepared.system;
    let n = sys.layout.nv();
    // State at t = 0.5 s from an accurate run.
    let opts = SimOptions { rate: Some(2.0), rtol: 1e-10, atol: 1e-12, ..SimOptions::new(T_END) };
    let res = simulate(model, &opts).unwrap();
    let t = 0.5;
    let mut y = vec![0.0; 2 * n];
    for (k, b) in sys.bodies.iter().enumerate() {
        for (d, (qn, vn)) in [("x", "vx"), ("y", "vy"), ("angle", "omega")].iter().enumerate() {
            y[3 * k + d] = res.channel(&format!("{}.{qn}", b.name)).unwrap()[1];
            y[n + 3 * k + d] = res.channel(&format!("{}.{vn}", b.name)).unwrap()[1];
        }
    }
    let mut ode = Ode::new(sys, prepared.initial.active.clone(), 1e-6, 1e-8);
    ode.ws.t_piece = t;
    let mut f0 = vec![0.0; 2 * n];
    ode.rhs(t, &y, &mut f0).unwrap();
    let (q, v) = (&y[..n], &y[n..]);

    let c_constraints = ns_per_call(|| constraints(sys, black_box(t), q, v, &mut ode.ws));
    let c_forces = ns_per_call(|| applied_forces(sys, black_box(t), q, v, &mut ode.ws));
    let c_accel = ns_per_call(|| accelerations(sys, black_box(t), q, v, &mut ode.ws).unwrap());
    // Reference for the augmented solve: a plain Cholesky factor + solve of the Schur
    // complement of every active row (what `accelerations` adds to it: regularisation,
    // refinement, allocation; what it saves: the rows of bodies their drivers fix).
    let cq = ode.ws.dense_jacobian();
    let m_inv = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
        n,
        sys.bodies.iter().flat_map(|b| [1.0 / b.mass, 1.0 / b.mass, 1.0 / b.inertia]),
    ));
    let (schur, rhs) = (&cq * m_inv * cq.transpose(), ode.ws.lambda.clone());
    let c_cholesky = ns_per_call(|| {
        black_box(nalgebra::Cholesky::new(black_box(schur.clone())).unwrap().solve(&rhs));
    });
    let c_prepare = ns_per_call(|| drop(black_box(jointgap_core::simulate::prepare(model).unwrap())));
    let c_violation = ns_per_call(|| {
        black_box(violation(sys, black_box(t), q, v, &mut ode.ws));
    });
    let (mut qp, mut vp) = (q.to_vec(), v.to_vec());
    let c_project = ns_per_call(|| {
        qp.copy_from_slice(q);
        vp.copy_from_slice(v);
        qp[0] += 1e-9; // a drift to remove
        project(sys, t, &mut qp, &mut vp, &mut ode.ws, POSITION_TOL).unwrap();
    });
    let mut sample = vec![0.0; 2 * n];
    let c_hermite = ns_per_call(|| hermite5(black_box(0.37), 1e-4, n, &y, &f0, &y, &f0, &mut sample));
    // Recorder::push: batches of one run's 10 001 samples into a fresh recorder.
    let push_cost = |select: Option<&[String]>, ws: &mut Workspace| {
        let mut per = Vec::new();
        for _ in 0..9 {
            let mut rec = Recorder::new(sys, ws, select, 1, false).unwrap();
            let start = Instant::now();
            for i in 0..=10_000 {
                rec.push(sys, ws, t + i as f64 * 1e-12, q, v).unwrap();
            }
            per.push(start.elapsed().as_secs_f64() * 1e9 / 10_001.0);
        }
        median(per)
    };
    let c_push_all = push_cost(None, &mut ode.ws);
    let c_push_slider = push_cost(Some(&["slider.*".to_string()]), &mut ode.ws);

    // One trial step at the mean step size of the rtol = 1e-6 runs.
    let mean_h = |m: Method| {
        let r = runs.iter().find(|r| r.0 == m && r.1 == 1e-6).unwrap();
        T_END / r.4.stats.accepted_steps as f64
    };
    let (mut y_new, mut f_new) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
    let tol = ode.tolerances;
    let mut dp = stepper::<Ode>(Method::Dopri5, state_shape(sys));
    let h = mean_h(Method::Dopri5);
    let c_dopri = ns_per_call(|| {
        let _ = black_box(dp.attempt(&mut ode, tol, t, &y, &f0, h, &mut y_new, &mut f_new));
    });
    let h = mean_h(Method::Sdirk4);
    let mut sd = stepper::<Ode>(Method::Sdirk4, state_shape(sys));
    let c_sdirk_same_h = ns_per_call(|| {
        let _ = black_box(sd.attempt(&mut ode, tol, t, &y, &f0, h, &mut y_new, &mut f_new));
    });
    let mut flip = false;
    let c_sdirk_new_h = ns_per_call(|| {
        flip = !flip;
        let hh = if flip { h } else { h * (1.0 + 1e-9) };
        let _ = black_box(sd.attempt(&mut ode, tol, t, &y, &f0, hh, &mut y_new, &mut f_new));
    });
    let c_sdirk_fresh = ns_per_call(|| {
        let mut s = stepper::<Ode>(Method::Sdirk4, state_shape(sys));
        let _ = black_box(s.attempt(&mut ode, tol, t, &y, &f0, h, &mut y_new, &mut f_new));
    });
    ode.evaluations = 0;
    let mut s = stepper::<Ode>(Method::Sdirk4, state_shape(sys));
    let _ = s.attempt(&mut ode, tol, t, &y, &f0, h, &mut y_new, &mut f_new);
    let rhs_fresh = ode.evaluations;
    ode.evaluations = 0;
    let _ = s.attempt(&mut ode, tol, t, &y, &f0, h, &mut y_new, &mut f_new);
    let rhs_steady = ode.evaluations;

    writeln!(md, "\n## Where the time goes (Rust microbenchmarks, state at t = 0.5 s)\n").unwrap();
    writeln!(md, "Median of 7 batches of repeated calls on one state (warm caches).\n").unwrap();
    writeln!(md, "| stage | ns per call |").unwrap();
    writeln!(md, "|---|---:|").unwrap();
    let rows: [(String, f64); 15] = [
        ("`dynamics::constraints`".into(), c_constraints),
        ("`dynamics::applied_forces`".into(), c_forces),
        ("`dynamics::accelerations` (augmented solve, = one RHS)".into(), c_accel),
        (
            format!("reference: nalgebra Cholesky factor + solve, {0}x{0} Schur complement", schur.nrows()),
            c_cholesky,
        ),
        ("`dynamics::violation` (every accepted step)".into(), c_violation),
        ("`dynamics::project` (1e-9 m drift)".into(), c_project),
        ("`ode::hermite5` (per sample)".into(), c_hermite),
        ("`Recorder::push`, all channels".into(), c_push_all),
        ("`Recorder::push`, slider.*".into(), c_push_slider),
        (format!("`Dopri5::attempt`, h = {:.2e} s", mean_h(Method::Dopri5)), c_dopri),
        (format!("`Sdirk4::attempt`, same h ({rhs_steady} RHS, Jacobian and LU reused)"), c_sdirk_same_h),
        ("`Sdirk4::attempt`, h changed (LU refactored)".into(), c_sdirk_new_h),
        (format!("`Sdirk4::attempt`, fresh stepper ({rhs_fresh} RHS, Jacobian + LU)"), c_sdirk_fresh),
        ("`Sdirk4` Jacobian + LU (fresh minus same h)".into(), c_sdirk_fresh - c_sdirk_same_h),
        ("`simulate::prepare` (compile + assembly, once per run)".into(), c_prepare),
    ];
    for (name, ns) in &rows {
        writeln!(md, "| {name} | {ns:.0} |").unwrap();
    }

    writeln!(md, "\n### Share of whole runs explained (count x cost, all channels @ 10 kHz)\n").unwrap();
    writeln!(
        md,
        "RHS = evaluations x `accelerations`; output = samples x (`push` + `hermite5`); checks = \
         accepted steps x `violation` + projections x `project`; rest = wall - the three \
         (step arithmetic, Newton/LU of sdirk4, allocation, compile and assembly).\n"
    )
    .unwrap();
    writeln!(
        md,
        "| method | rtol | wall [ms] | RHS [ms] | output [ms] | checks [ms] | rest [ms] | explained |"
    )
    .unwrap();
    writeln!(md, "|---|---|---:|---:|---:|---:|---:|---:|").unwrap();
    for (_, rtol, _, wall, res) in runs.iter().filter(|r| r.2.starts_with("all")) {
        let s = &res.stats;
        let rhs = s.rhs_evaluations as f64 * c_accel * 1e-6;
        let out = res.time.len() as f64 * (c_push_all + c_hermite) * 1e-6;
        let checks = (s.accepted_steps as f64 * c_violation + s.projections as f64 * c_project) * 1e-6;
        let wall = wall * 1e3;
        writeln!(
            md,
            "| {} | {rtol:.0e} | {wall:.2} | {rhs:.2} | {out:.2} | {checks:.2} | {:.2} | {:.0}% |",
            s.method,
            wall - rhs - out - checks,
            100.0 * (rhs + out + checks) / wall
        )
        .unwrap();
    }
}
