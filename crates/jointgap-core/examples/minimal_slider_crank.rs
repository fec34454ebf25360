//! `make bench-peers`: the founding clearance slider-crank written as a special-purpose
//! compiled program, the kind the speed issue quotes ("minimal coordinates, Radau IIA"),
//! timed on this machine in the same run as jointgap's `simulate`.
//!
//! The crank angle is prescribed, so the unknowns are the rod angle `phi` and the slider
//! position `x`; the equations of motion are derived by hand (those of
//! `benchmarks/peers/scipy_slider_crank.py`, written here in Rust), and jointgap's Radau
//! IIA step (`integrators::radau5`) integrates the four states with a forward-difference
//! Jacobian (four evaluations, kept across steps as the method decides). No contact
//! events: the ADAMS IMPACT law needs no onset speed, and the error control finds the
//! contacts. The solve is split at the end of the crank's ramp, where its acceleration
//! jumps. Output: the slider acceleration at 10 kHz, from the quintic Hermite
//! interpolant of the positions and the equations of motion at each sample (as jointgap
//! records).
//!
//! Usage: `minimal_slider_crank MODEL.json OUT.json`, with MODEL.json the founding
//! clearance model (`jointgap.load(...).to_json()`): jointgap's `simulate` runs on it at
//! the same tolerances and grid, so both sides are timed in one process. OUT.json gets,
//! per side and rtol, the best wall time of the repeated runs, the counters and the 10 kHz
//! slider acceleration; the peer script scores them against its reference.

use std::f64::consts::PI;
use std::time::Instant;

use jointgap_core::integrators::ode::Singular;
use jointgap_core::integrators::ode::{hermite5, PositionRate, Rhs, StateShape, Tolerances};
use jointgap_core::integrators::radau5::Radau5;
use jointgap_core::integrators::stepper::Stepper;
use jointgap_core::profile::Profile;
use jointgap_core::{simulate, Method, Model, SimOptions};
use serde_json::json;

const T_END: f64 = 0.5;
const RATE: f64 = 10_000.0;
const RTOLS: [f64; 7] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 3e-9, 1e-9];

// The founding clearance case (docs/physics.md section 5), SI units.
const G: f64 = 9.81;
const OMEGA: f64 = 300.0 * 2.0 * PI / 60.0;
const RAMP: f64 = 0.2;
const R_CRANK: f64 = 0.08;
const L_ROD: f64 = 0.32;
const M_ROD: f64 = 0.72;
const J_ROD: f64 = 0.0006926;
const M_SLIDER: f64 = 2.28;
const R_BEARING: f64 = 7.5e-3;
const CLEARANCE: f64 = 0.5e-3;
const R_JOURNAL: f64 = R_BEARING - CLEARANCE;
const E_BEARING: f64 = 97e9;
const E_JOURNAL: f64 = 207e9;
const NU: f64 = 0.3;
const C_MAX: f64 = 27960.0;
const D_MAX: f64 = 1e-5;
const MU_S: f64 = 0.08;
const MU_D: f64 = 0.05;
const V_S: f64 = 1e-4;
const V_D: f64 = 0.01016;
const HALF_ROD: f64 = L_ROD / 2.0;

/// ADAMS cubic STEP from `(x0, h0)` to `(x1, h1)`.
fn step(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    let s = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
    h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)
}

/// ADAMS Coulomb: `mu_s` at `v_s`, `mu_d` beyond `v_d`, odd in the slip.
fn friction_coefficient(v: f64) -> f64 {
    let speed = v.abs();
    if speed <= V_S {
        return step(v, -V_S, -MU_S, V_S, MU_S);
    }
    let mu = if speed <= V_D { step(speed, V_S, MU_S, V_D, MU_D) } else { MU_D };
    mu.copysign(v)
}

/// The rod and slider in minimal coordinates, `y = (phi, x, phi', x')`.
struct SliderCrank {
    /// Hertz stiffness of the journal in its bearing [N/m^1.5].
    k: f64,
    /// Rod about the crank pin [kg m^2].
    j_pin: f64,
    /// The side of the ramp's end being integrated (0: ramp, 1: constant speed).
    piece: usize,
    evaluations: usize,
    profile: Option<Profile>,
}

impl SliderCrank {
    fn new() -> Self {
        let sigma = (1.0 - NU * NU) / E_JOURNAL + (1.0 - NU * NU) / E_BEARING;
        let k = 4.0 / (3.0 * sigma) * (R_JOURNAL * R_BEARING / (R_BEARING - R_JOURNAL)).sqrt();
        SliderCrank { k, j_pin: J_ROD + M_ROD * HALF_ROD * HALF_ROD, piece: 0, evaluations: 0, profile: None }
    }

    /// Prescribed crank angle, speed and acceleration on the current piece.
    fn crank(&self, t: f64) -> (f64, f64, f64) {
        if self.piece == 0 {
            (0.5 * OMEGA * t * t / RAMP, OMEGA * t / RAMP, OMEGA / RAMP)
        } else {
            (0.5 * OMEGA * RAMP + OMEGA * (t - RAMP), OMEGA, 0.0)
        }
    }

    /// `(phi'', x'')`: moments about the crank pin A for the rod, the guide's direction
    /// for the slider; the contact force acts at the contact point on the journal.
    fn accelerations(&self, t: f64, y: &[f64]) -> (f64, f64) {
        let (phi, x, phi_d, x_d) = (y[0], y[1], y[2], y[3]);
        let (th, th_d, th_dd) = self.crank(t);
        let (s, c) = th.sin_cos();
        let (ax, ay) = (R_CRANK * c, R_CRANK * s);
        let (vax, vay) = (-ay * th_d, ax * th_d);
        let aax = -ay * th_dd - ax * th_d * th_d;
        let aay = ax * th_dd - ay * th_d * th_d;
        let (sp, cp) = phi.sin_cos();
        let (jx, jy) = (ax + L_ROD * cp, ay + L_ROD * sp);
        let (ex, ey) = (jx - x, jy);
        let ecc = ex.hypot(ey);
        let (mut fx, mut moment) = (0.0, 0.0);
        if ecc > CLEARANCE {
            let delta = ecc - CLEARANCE;
            let (nx, ny) = (ex / ecc, ey / ecc);
            let (qx, qy) = (jx + R_JOURNAL * nx, jy + R_JOURNAL * ny);
            let vx = vax - phi_d * (qy - ay) - x_d;
            let vy = vay + phi_d * (qx - ax);
            let delta_d = vx * nx + vy * ny;
            let slip = -vx * ny + vy * nx;
            let f_n = self.k * delta * delta.sqrt() + step(delta, 0.0, 0.0, D_MAX, C_MAX) * delta_d;
            if f_n > 0.0 {
                let f_t = -friction_coefficient(slip) * f_n;
                fx = -f_n * nx - f_t * ny;
                let fy = -f_n * ny + f_t * nx;
                moment = (qx - ax) * fy - (qy - ay) * fx;
            }
        }
        let phi_dd = (M_ROD * HALF_ROD * (sp * aax - cp * aay - cp * G) + moment) / self.j_pin;
        (phi_dd, -fx / M_SLIDER)
    }
}

impl Rhs for SliderCrank {
    fn shape(&self) -> StateShape {
        StateShape { nq: 2, nv: 2, rate: PositionRate::Identity }
    }

    fn eval(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
        self.evaluations += 1;
        let (phi_dd, x_dd) = self.accelerations(t, y);
        dy.copy_from_slice(&[y[2], y[3], phi_dd, x_dd]);
        Ok(())
    }

    fn profile(&mut self) -> &mut Option<Profile> {
        &mut self.profile
    }
}

/// Counters and the 10 kHz slider acceleration of one run.
struct Run {
    steps: usize,
    rejected: usize,
    evaluations: usize,
    ax: Vec<f64>,
}

/// Integrates from rest (rod along +x, journal centred) to `T_END` at `rtol`,
/// `atol = 1e-3 rtol`, with the step-size rules of jointgap's integration loop.
fn solve(rtol: f64) -> Run {
    let atol = 1e-3 * rtol;
    let mut ode = SliderCrank::new();
    let mut radau = Radau5::new(2, 2);
    let mut y = vec![0.0, R_CRANK + L_ROD, 0.0, 0.0];
    let (mut f, mut y1, mut f1, mut sample) = (vec![0.0; 4], vec![0.0; 4], vec![0.0; 4], vec![0.0; 4]);
    let n_samples = (T_END * RATE).round() as usize + 1;
    let mut ax = Vec::with_capacity(n_samples);
    let (mut steps, mut rejected) = (0, 0);
    ode.eval(0.0, &y, &mut f).unwrap();
    ax.push(f[3]);
    let (mut t, mut h) = (0.0, 1e-6);
    for (piece, end) in [RAMP, T_END].into_iter().enumerate() {
        ode.piece = piece;
        ode.eval(t, &y, &mut f).unwrap();
        let mut last_rejected = false;
        while t < end {
            let last = h >= (end - t) * (1.0 - 1e-12);
            if last {
                h = end - t;
            }
            let attempt = radau.step(&mut ode, Tolerances { rtol, atol }, t, &y, &f, h, &mut y1, &mut f1);
            let factor = Stepper::<SliderCrank>::step_factor(&radau).unwrap_or(0.5);
            match attempt {
                Ok(a) if a.error <= 1.0 => {
                    steps += 1;
                    let t1 = if last { end } else { t + h };
                    while ax.len() < n_samples && ax.len() as f64 / RATE <= t1 * (1.0 + 1e-14) {
                        let ts = ax.len() as f64 / RATE;
                        hermite5((ts - t) / h, h, 2, &y, &f, &y1, &f1, &mut sample);
                        ax.push(ode.accelerations(ts, &sample).1);
                    }
                    t = t1;
                    std::mem::swap(&mut y, &mut y1);
                    std::mem::swap(&mut f, &mut f1);
                    h *= factor.clamp(0.2, if last_rejected { 1.0 } else { 5.0 });
                    last_rejected = false;
                }
                Ok(_) | Err(_) => {
                    rejected += 1;
                    Stepper::<SliderCrank>::rejected(&mut radau);
                    h *= factor.clamp(0.1, 0.9);
                    last_rejected = true;
                }
            }
        }
    }
    Run { steps, rejected, evaluations: ode.evaluations, ax }
}

/// Timed runs of the program and of jointgap.
const PROGRAM_RUNS: usize = 5;
const JOINTGAP_RUNS: usize = 3;

/// Best wall time [s] of `runs` calls after a first untimed one, and the last result.
fn best_of<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = f();
    for _ in 0..runs {
        let started = Instant::now();
        out = f();
        best = best.min(started.elapsed().as_secs_f64());
    }
    (best, out)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, model, out] = args.as_slice() else {
        eprintln!("usage: minimal_slider_crank MODEL.json OUT.json");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(model).unwrap_or_else(|e| panic!("{model}: {e}"));
    let model: Model = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{model}: {e}"));
    let mut rows = Vec::new();
    for rtol in RTOLS {
        let (wall, run) = best_of(PROGRAM_RUNS, || solve(rtol));
        println!(
            "minimal radau5 rtol {rtol:.0e}: {:.2} ms, {} steps + {} rejected, {} evaluations",
            wall * 1e3,
            run.steps,
            run.rejected,
            run.evaluations
        );
        rows.push(json!({
            "side": "minimal", "method": "radau5", "rtol": rtol, "wall": wall, "runs": PROGRAM_RUNS,
            "steps": run.steps, "rejected": run.rejected, "nfev": run.evaluations, "ax": run.ax,
        }));
        for method in [Method::Auto, Method::Radau5] {
            let opts = SimOptions {
                rtol,
                atol: 1e-3 * rtol,
                method,
                rate: Some(RATE),
                channels: Some(vec!["slider.ax".into()]),
                ..SimOptions::new(T_END)
            };
            let (wall, res) =
                best_of(JOINTGAP_RUNS, || simulate(&model, &opts).expect("the founding model runs"));
            let s = &res.stats;
            println!(
                "jointgap {method:?} rtol {rtol:.0e}: {:.2} ms, {} steps + {} rejected, {} evaluations",
                wall * 1e3,
                s.accepted_steps,
                s.rejected_steps,
                s.rhs_evaluations
            );
            rows.push(json!({
                "side": "jointgap", "method": format!("{method:?}").to_lowercase(), "rtol": rtol,
                "wall": wall, "runs": JOINTGAP_RUNS, "steps": s.accepted_steps,
                "rejected": s.rejected_steps, "nfev": s.rhs_evaluations,
                "ax": res.channel("slider.ax").expect("slider.ax is recorded"),
            }));
        }
    }
    std::fs::write(out, serde_json::Value::Array(rows).to_string()).unwrap_or_else(|e| panic!("{out}: {e}"));
}
