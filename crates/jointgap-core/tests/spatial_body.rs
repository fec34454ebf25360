//! A free spatial body, integrated with the body kind's own items (its position rate,
//! the gyroscopic moment as its only load, its inverse mass, the quaternion normalised
//! after each step) by DOPRI5, against the closed form of torque-free motion.
//!
//! An asymmetric body with principal moments `J1 < J2 < J3`, set spinning close to its
//! intermediate axis, turns over and back (the tennis racket, or Dzhanibekov, effect).
//! With energy `E` and angular momentum `M`, `M^2 > 2 E J2`, its body rates are
//! (Landau and Lifshitz, Mechanics, section 37)
//!
//! ```text
//! w1 = sqrt((2 E J3 - M^2) / (J1 (J3 - J1))) cn(tau)
//! w2 = sqrt((2 E J3 - M^2) / (J2 (J3 - J2))) sn(tau)
//! w3 = sqrt((M^2 - 2 E J1) / (J3 (J3 - J1))) dn(tau)
//! tau = sqrt((J3 - J2) (M^2 - 2 E J1) / (J1 J2 J3)) t
//! k^2 = (J2 - J1) (2 E J3 - M^2) / ((J3 - J2) (M^2 - 2 E J1))
//! ```
//!
//! with sn, cn, dn Jacobi's elliptic functions of modulus k. Starting at `tau = K(k)`
//! (`sn = 1`, `cn = 0`, `dn = k'`) the body spins about its intermediate axis with a
//! little turn about the third, `w = (0, w2, w3)`, the point of a flip nearest the axis.

use jointgap_core::integrators::dopri5::Dopri5;
use jointgap_core::integrators::ode::{PositionRate, Rhs, Singular, StateShape, Tolerances};
use jointgap_core::integrators::radau5::Radau5;
use jointgap_core::integrators::sdirk4::Sdirk4;
use jointgap_core::integrators::stepper::{StepFailure, Stepper};
use jointgap_core::mechanics::spatial::body::{
    self, add_gyroscopic, inverse_mass, kinetic_energy, normalise, rate_block, BodyState, Orientation, Vec3,
    NQ, NV,
};
use jointgap_core::profile::Profile;
use nalgebra::DMatrixViewMut;
use std::f64::consts::PI;

/// Jacobi's elliptic functions `(sn, cn, dn)` of `u` with modulus `k` (`0 <= k < 1`) by
/// the descending Landen transformation (the arithmetic-geometric mean; Abramowitz and
/// Stegun 16.4): `phi_N = 2^N a_N u`, then
/// `phi_(n-1) = (phi_n + asin(c_n / a_n sin phi_n)) / 2` down to `phi_0`, the amplitude,
/// and `sn = sin phi_0`, `cn = cos phi_0`, `dn^2 = cn^2 + k'^2 sn^2` (a sum, exact where
/// `dn` is small).
fn jacobi(u: f64, k: f64) -> (f64, f64, f64) {
    let k_prime = (1.0 - k * k).sqrt();
    let (mut a, mut b, mut c) = (vec![1.0], k_prime, vec![k]);
    while c.last().unwrap().abs() > f64::EPSILON && a.len() < 40 {
        let an = *a.last().unwrap();
        c.push(0.5 * (an - b));
        a.push(0.5 * (an + b));
        b = (an * b).sqrt();
    }
    let n = a.len() - 1;
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    for m in (1..=n).rev() {
        phi = 0.5 * (phi + (c[m] / a[m] * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    (sn, cn, (cn * cn + k_prime * k_prime * sn * sn).sqrt())
}

/// The complete elliptic integral of the first kind `K(k) = pi / (2 agm(1, k'))`.
fn quarter_period(k: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    while (a - b).abs() > f64::EPSILON * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// The incomplete integral `F(phi, k) = int_0^phi dtheta / sqrt(1 - k^2 sin^2 theta)` by
/// Simpson's rule on 2000 panels: the inverse of `sn` (`sn(F(phi)) = sin phi`), computed
/// another way.
fn incomplete_integral(phi: f64, k: f64) -> f64 {
    let n = 2000;
    let f = |t: f64| 1.0 / (1.0 - (k * t.sin()).powi(2)).sqrt();
    let h = phi / n as f64;
    let inner: f64 = (1..n).map(|i| f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 }).sum();
    h / 3.0 * (f(0.0) + inner + f(phi))
}

/// The elliptic functions against their known values and limits, against the integral
/// that they invert, and against their derivatives.
#[test]
fn jacobi_elliptic_functions_match_known_values() {
    // K(1/sqrt 2) = Gamma(1/4)^2 / (4 sqrt(pi)) (the lemniscatic case)
    let k = std::f64::consts::FRAC_1_SQRT_2;
    assert!((quarter_period(k) - 1.854_074_677_301_372).abs() < 1e-14, "K = {}", quarter_period(k));
    assert!((quarter_period(0.0) - PI / 2.0).abs() < 1e-15);
    for k in [0.3, k, 0.99, 0.999_999] {
        let kk = quarter_period(k);
        let (sn, cn, dn) = jacobi(kk, k);
        let k_prime = (1.0 - k * k).sqrt();
        assert!((sn - 1.0).abs() < 1e-14 && cn.abs() < 1e-14 && (dn - k_prime).abs() < 1e-14, "at K({k})");
        for phi in [0.3, 1.0, 1.5] {
            let (sn, cn, _) = jacobi(incomplete_integral(phi, k), k);
            assert!((sn - phi.sin()).abs() < 1e-10 && (cn - phi.cos()).abs() < 1e-10, "sn(F({phi}, {k}))");
        }
        for u in [0.2, 1.3, 2.9, -0.7] {
            let (sn, cn, dn) = jacobi(u, k);
            let h = 1e-5;
            let (p, m) = (jacobi(u + h, k), jacobi(u - h, k));
            let d = |a: f64, b: f64| (a - b) / (2.0 * h);
            assert!((d(p.0, m.0) - cn * dn).abs() < 1e-9, "sn' = cn dn at {u}, {k}");
            assert!((d(p.1, m.1) + sn * dn).abs() < 1e-9, "cn' = -sn dn at {u}, {k}");
            assert!((d(p.2, m.2) + k * k * sn * cn).abs() < 1e-9, "dn' = -k^2 sn cn at {u}, {k}");
        }
    }
    for u in [0.4, 2.0] {
        let (sn, cn, dn) = jacobi(u, 0.0);
        assert!((sn - u.sin()).abs() < 1e-15 && (cn - u.cos()).abs() < 1e-15 && dn == 1.0);
    }
}

/// A body with no load but its gyroscopic moment; `mass` [kg], principal `moments`
/// [kg m^2].
struct FreeBody {
    mass: f64,
    moments: Vec3,
    profile: Option<Profile>,
}

impl Rhs for FreeBody {
    fn shape(&self) -> StateShape {
        StateShape { nq: NQ, nv: NV, rate: PositionRate::Mapped }
    }

    fn eval(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Singular> {
        let (q, v) = y.split_at(NQ);
        self.position_rate(q, v, &mut dy[..NQ]);
        let mut qe = [0.0; NV];
        add_gyroscopic(&mut qe, self.moments, &Vec3::new(v[3], v[4], v[5]));
        let m_inv = inverse_mass(self.mass, self.moments);
        for k in 0..NV {
            dy[NQ + k] = m_inv[k] * qe[k];
        }
        Ok(())
    }

    fn position_rate(&self, q: &[f64], v: &[f64], qdot: &mut [f64]) {
        body::position_rate(q, v, qdot);
    }

    fn rate_jacobian(&self, q: &[f64], mut g: DMatrixViewMut<'_, f64>) {
        let block = rate_block(q);
        for (i, row) in block.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                g[(i, j)] = *x;
            }
        }
    }

    fn update_positions(&mut self, q: &mut [f64]) -> bool {
        normalise(q)
    }

    fn profile(&mut self) -> &mut Option<Profile> {
        &mut self.profile
    }
}

/// Angular momentum about the centre of mass in global axes, `A J w'`.
fn momentum(body: &FreeBody, y: &[f64]) -> Vec3 {
    let state = BodyState::read(&y[..NQ], &y[NQ..]);
    state.a * body.moments.component_mul(&state.omega)
}

/// The largest departures over a run, each relative to its scale.
#[derive(Debug, Default)]
struct Departures {
    /// Accepted steps.
    steps: usize,
    /// Body rates from the closed form, of `w2`.
    rates: f64,
    /// Angular momentum in global axes from its start, relative.
    momentum: f64,
    /// Kinetic energy from its start, relative.
    energy: f64,
    /// `|e| - 1`.
    norm: f64,
    /// Centre from its straight line [m].
    line: f64,
    /// Whether the intermediate axis turned over (`w2` below `-0.9` of its start).
    flipped: bool,
}

/// Integrates the free body set spinning near its intermediate axis (principal moments
/// 0.010, 0.020, 0.025 kg m^2, `w' = (0, 6, 0.3)` rad/s, turned and moving off the
/// origin) over one period of the closed form's body rates (two flips) with the loop's
/// step-size rules, and returns the largest departures at the step ends.
fn flip(stepper: &mut dyn Stepper<FreeBody>, tol: Tolerances) -> Departures {
    let mut body = FreeBody { mass: 3.0, moments: Vec3::new(0.010, 0.020, 0.025), profile: None };
    let j = body.moments;
    let (w2, w3) = (6.0, 0.3);
    let energy = 0.5 * (j.y * w2 * w2 + j.z * w3 * w3);
    let m2 = (j.y * w2).powi(2) + (j.z * w3).powi(2);
    assert!(m2 > 2.0 * energy * j.y, "the closed form's case");
    let amplitude = Vec3::new(
        ((2.0 * energy * j.z - m2) / (j.x * (j.z - j.x))).sqrt(),
        ((2.0 * energy * j.z - m2) / (j.y * (j.z - j.y))).sqrt(),
        ((m2 - 2.0 * energy * j.x) / (j.z * (j.z - j.x))).sqrt(),
    );
    let rate = ((j.z - j.y) * (m2 - 2.0 * energy * j.x) / (j.x * j.y * j.z)).sqrt();
    let k = ((j.y - j.x) * (2.0 * energy * j.z - m2) / ((j.z - j.y) * (m2 - 2.0 * energy * j.x))).sqrt();
    let kk = quarter_period(k);
    let exact = |t: f64| {
        let (sn, cn, dn) = jacobi(kk + rate * t, k);
        Vec3::new(amplitude.x * cn, amplitude.y * sn, amplitude.z * dn)
    };
    let period = 4.0 * kk / rate;
    println!("k = {k}, K = {kk}, period of the rates {period} s");

    let orientation = Orientation::from_scaled_axis(Vec3::new(0.4, -0.3, 0.8));
    let (r0, v0) = (Vec3::new(0.1, 0.2, -0.3), Vec3::new(0.5, -0.2, 0.3));
    let omega0 = Vec3::new(0.0, w2, w3);
    let (q0, v) = body::placement_coordinates(&r0, &orientation, &v0, &(orientation * omega0));
    let mut y: Vec<f64> = q0.iter().chain(v.iter()).copied().collect();
    assert!((Vec3::new(y[10], y[11], y[12]) - exact(0.0)).norm() < 1e-12, "the start is the closed form's");
    let (h0, e0) = (momentum(&body, &y), kinetic_energy(body.mass, j, &y[NQ..]));

    let n = NQ + NV;
    let (mut f, mut y1, mut f1) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    body.eval(0.0, &y, &mut f).unwrap();
    let (mut t, mut h) = (0.0f64, 1e-4f64);
    let mut d = Departures::default();
    while t < period {
        h = h.min(period - t);
        match stepper.attempt(&mut body, tol, t, &y, &f, h, &mut y1, &mut f1) {
            Ok(a) if a.error <= 1.0 => {
                t += h;
                std::mem::swap(&mut y, &mut y1);
                std::mem::swap(&mut f, &mut f1);
                d.steps += 1;
                let omega = Vec3::new(y[10], y[11], y[12]);
                d.rates = d.rates.max((omega - exact(t)).norm() / w2);
                d.momentum = d.momentum.max((momentum(&body, &y) - h0).norm() / h0.norm());
                d.energy = d.energy.max((kinetic_energy(body.mass, j, &y[NQ..]) - e0).abs() / e0);
                let e = Vec3::new(y[4], y[5], y[6]).norm_squared() + y[3] * y[3];
                d.norm = d.norm.max((e.sqrt() - 1.0).abs());
                d.line = d.line.max((Vec3::new(y[0], y[1], y[2]) - (r0 + v0 * t)).norm());
                d.flipped |= omega.y < -0.9 * w2;
                let own = 0.9 * a.error.max(1e-10).powf(-stepper.error_exponent());
                h *= stepper.step_factor().unwrap_or(own).clamp(0.2, 5.0);
            }
            Ok(a) => {
                stepper.rejected();
                let own = 0.9 * a.error.powf(-stepper.error_exponent());
                h *= stepper.step_factor().unwrap_or(own).clamp(0.1, 0.9);
            }
            Err(StepFailure::Convergence) => {
                stepper.rejected();
                h *= stepper.step_factor().unwrap_or(0.5).clamp(0.1, 0.9);
            }
            Err(StepFailure::Singular) => panic!("{}: a free body has no singular state", stepper.name()),
        }
    }
    println!(
        "{}: {} steps; body rates off the closed form by {:.1e} of w2; angular momentum drift {:.1e}, \
         energy drift {:.1e} (relative); |e| - 1 up to {:.1e}; centre off its line by {:.1e} m",
        stepper.name(),
        d.steps,
        d.rates,
        d.momentum,
        d.energy,
        d.norm,
        d.line
    );
    assert!(d.flipped, "{}: the body turns over within the period", stepper.name());
    assert!(d.norm < 1e-12, "{}: |e| - 1 = {:e}", stepper.name(), d.norm);
    assert!(d.line < 1e-12, "{}: the centre leaves its line by {:e} m", stepper.name(), d.line);
    d
}

/// DOPRI5 at rtol = atol = 1e-12 follows the closed form's body rates, and keeps the
/// angular momentum in global axes and the kinetic energy to 1e-10 (relative), the
/// quaternion unit to 1e-12 and the centre on its line. A wrong sign or factor in the
/// gyroscopic moment or the inverse mass changes the rates by their size; the angular
/// velocity taken in global axes in the position rate turns the body the wrong way and
/// moves the momentum by its size.
#[test]
fn a_free_body_flips_as_the_closed_form_says() {
    let d = flip(&mut Dopri5::new(NQ, NV), Tolerances { rtol: 1e-12, atol: 1e-12 });
    assert!(d.rates < 1e-8, "body rates off the closed form by {:e} of w2", d.rates);
    assert!(d.momentum < 1e-10, "angular momentum in global axes drifts by {:e}", d.momentum);
    assert!(d.energy < 1e-10, "kinetic energy drifts by {:e}", d.energy);
}

/// The implicit methods, whose Newton matrices take the quaternion's rate block
/// [`rate_block`], follow the same flip at rtol = atol = 1e-10 (their global errors,
/// near the flip's sensitive turn, stay below 1e-6 of the rates).
#[test]
fn implicit_methods_follow_the_free_body() {
    let tol = Tolerances { rtol: 1e-10, atol: 1e-10 };
    let steppers: [Box<dyn Stepper<FreeBody>>; 2] =
        [Box::new(Radau5::new(NQ, NV)), Box::new(Sdirk4::new(NQ, NV))];
    for mut stepper in steppers {
        let d = flip(&mut *stepper, tol);
        assert!(d.rates < 1e-6, "{}: body rates off the closed form by {:e} of w2", stepper.name(), d.rates);
        assert!(d.momentum < 1e-6, "{}: angular momentum drifts by {:e}", stepper.name(), d.momentum);
    }
}
