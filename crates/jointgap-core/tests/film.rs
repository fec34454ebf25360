//! The oil film of a lubricated journal bearing (`mechanics::contact::film`) against
//! computations written here independently: quadratures of the short-bearing Reynolds
//! pressure, a finite-difference solution of the long-bearing Reynolds equation, both
//! with the film's motion differentiated numerically from the moving geometry; the
//! closed-form steady bearings; the published pi-film formula; the shear stress.

use std::f64::consts::PI;

use jointgap_core::mechanics::contact::film::{Film, FilmForce, FilmMotion};
use jointgap_core::model::FilmModel;

/// Journal radius [m], radial clearance [m], bearing length [m], viscosity [Pa s].
const R: f64 = 0.01;
const C: f64 = 5e-5;
const L: f64 = 0.01;
const MU: f64 = 0.04;
/// Direction of the eccentricity: away from the x axis, so the tests see the frame.
const GAMMA: f64 = 0.7;

fn film(model: FilmModel) -> Film {
    Film { radius: R, clearance: C, length: L, viscosity: MU, model }
}

/// A motion from the eccentricity ratio, its rate [1/s], the attitude rate and the
/// journal's and bearing's angular velocities [rad/s].
fn motion(eps: f64, eps_rate: f64, attitude_rate: f64, omega_journal: f64, omega_bearing: f64) -> FilmMotion {
    FilmMotion {
        eccentricity: eps * C,
        eccentricity_rate: eps_rate * C,
        attitude_rate,
        omega_journal,
        omega_bearing,
    }
}

/// Squeeze-dominated, wedge-dominated and mixed motions, eps from 0.05 to 0.95, rates of
/// both signs.
const CASES: [(f64, f64, f64, f64, f64); 11] = [
    (0.05, 0.0, 0.0, 100.0, 0.0),
    (0.5, 0.1, 5.0, 100.0, 0.0),
    (0.95, 0.0, 0.0, -80.0, 20.0),
    (0.3, 50.0, 0.0, 0.0, 0.0),
    (0.7, -30.0, 0.0, 0.0, 0.0),
    (0.95, 5.0, 0.0, 1.0, 0.0),
    (0.6, 20.0, 30.0, 40.0, -10.0),
    (0.8, -10.0, -20.0, 50.0, 30.0),
    (0.2, -40.0, 10.0, 10.0, 0.0),
    (0.9, 3.0, 60.0, 100.0, 0.0),
    (0.4, -60.0, -5.0, -30.0, 0.0),
];

/// Film thickness at global angle `theta` and time `t` of the journal moving with `m`
/// from the eccentricity direction `GAMMA` at t = 0.
fn thickness(m: &FilmMotion, theta: f64, t: f64) -> f64 {
    C - (m.eccentricity + m.eccentricity_rate * t) * (theta - GAMMA - m.attitude_rate * t).cos()
}

/// Right-hand side of the Reynolds equation, `6 mu [(omega_j + omega_b) dh/dtheta + 2
/// dh/dt]`, with the derivatives of the moving film taken by central differences.
fn reynolds_rhs(m: &FilmMotion, theta: f64) -> f64 {
    let d = 1e-6;
    let dh_dtheta = (thickness(m, theta + d, 0.0) - thickness(m, theta - d, 0.0)) / (2.0 * d);
    let dh_dt = (thickness(m, theta, d) - thickness(m, theta, -d)) / (2.0 * d);
    6.0 * MU * ((m.omega_journal + m.omega_bearing) * dh_dtheta + 2.0 * dh_dt)
}

/// Which pressure counts at `phi` (from the eccentricity direction): its positive part
/// (Gumbel) or all of it over the half `phi` in `[pi, 2 pi]` (pi-film).
fn kept(model: FilmModel, phi: f64, p: f64) -> f64 {
    match model {
        FilmModel::Short | FilmModel::Long => p.max(0.0),
        FilmModel::ShortPi | FilmModel::LongPi => {
            if phi.sin() <= 0.0 {
                p
            } else {
                0.0
            }
        }
    }
}

/// Force along and across the eccentricity [N] from a pressure integral
/// `-R int int p (cos theta, sin theta)` given as its x and y parts.
fn along_across(fx: f64, fy: f64) -> (f64, f64) {
    let (s, c) = GAMMA.sin_cos();
    (fx * c + fy * s, -fx * s + fy * c)
}

/// Short bearing by quadrature: `h^3 d2p/dz2 = rhs` with `p(+-L/2) = 0` gives `p = rhs
/// (z^2 - L^2/4) / (2 h^3)`; Simpson's rule across the length (exact for the parabola),
/// the midpoint rule on `n` angles (`n` even). Returns the force along and across, the largest
/// mid-length pressure at the cells' centres and edges, and the shear torque on the journal
/// `R^2 int int [mu R (omega_b - omega_j)/h - (h/2R) dp/dtheta]` (full-circle Couette;
/// the pressure part as `h` between two angles times the pressure's change across them).
fn short_quadrature(model: FilmModel, m: &FilmMotion, n: usize) -> (f64, f64, f64, f64) {
    let pressure = |theta: f64, z: f64| {
        let h = thickness(m, theta, 0.0);
        kept(model, theta - GAMMA, reynolds_rhs(m, theta) * (z * z - L * L / 4.0) / (2.0 * h.powi(3)))
    };
    let simpson = |f: &dyn Fn(f64) -> f64| L / 6.0 * (f(-L / 2.0) + 4.0 * f(0.0) + f(L / 2.0));
    let d_theta = 2.0 * PI / n as f64;
    let (mut fx, mut fy, mut peak, mut torque) = (0.0, 0.0, 0.0_f64, 0.0);
    // Cells from the eccentricity direction: the pi-film's half ends on cell edges.
    for i in 0..n {
        let theta = GAMMA + (i as f64 + 0.5) * d_theta;
        let line = simpson(&|z| pressure(theta, z));
        fx -= R * line * theta.cos() * d_theta;
        fy -= R * line * theta.sin() * d_theta;
        let (before, after) = (theta - d_theta / 2.0, theta + d_theta / 2.0);
        peak = peak.max(pressure(theta, 0.0)).max(pressure(before, 0.0));
        let h = thickness(m, theta, 0.0);
        let rise = simpson(&|z| pressure(after, z) - pressure(before, z));
        torque +=
            R * R * (MU * R * (m.omega_bearing - m.omega_journal) / h * L * d_theta - h / (2.0 * R) * rise);
    }
    let (along, across) = along_across(fx, fy);
    (along, across, peak, torque)
}

/// Long bearing by finite differences: `(1/R^2) d/dtheta(h^3 dp/dtheta) = rhs` on `n`
/// nodes from the widest film, conservative central differences, `p` periodic and zero at
/// the widest film (full Sommerfeld), solved by the Thomas algorithm. Returns the nodal
/// pressure and the nodes' angles.
fn long_fd(m: &FilmMotion, n: usize) -> (Vec<f64>, Vec<f64>) {
    let d = 2.0 * PI / n as f64;
    let theta: Vec<f64> = (0..=n).map(|i| GAMMA + PI + i as f64 * d).collect();
    let h3 = |t: f64| thickness(m, t, 0.0).powi(3);
    // Unknowns p_1 .. p_{n-1}; p_0 = p_n = 0.
    let k = n - 1;
    let (mut lower, mut diag, mut upper, mut rhs) = (vec![0.0; k], vec![0.0; k], vec![0.0; k], vec![0.0; k]);
    for j in 0..k {
        let t = theta[j + 1];
        let (west, east) = (h3(t - d / 2.0), h3(t + d / 2.0));
        lower[j] = west;
        upper[j] = east;
        diag[j] = -(west + east);
        rhs[j] = R * R * reynolds_rhs(m, t) * d * d;
    }
    for j in 1..k {
        let w = lower[j] / diag[j - 1];
        diag[j] -= w * upper[j - 1];
        rhs[j] -= w * rhs[j - 1];
    }
    let mut p = vec![0.0; n + 1];
    for j in (0..k).rev() {
        p[j + 1] = (rhs[j] - upper[j] * p[j + 2]) / diag[j];
    }
    (theta, p)
}

/// Long bearing's force along and across, peak pressure and shear torque from the
/// finite-difference pressure on `n` nodes: trapezoidal rule over the kept pressure (its
/// positive part all round, or the nodes from the widest film to the thinnest, node
/// `n/2`), dp/dtheta by differences between nodes.
fn long_integrals(model: FilmModel, m: &FilmMotion, n: usize) -> (f64, f64, f64, f64) {
    let (theta, p) = long_fd(m, n);
    let d = 2.0 * PI / n as f64;
    let pi_film = model == FilmModel::LongPi;
    let kept_p: Vec<f64> = (0..=n)
        .map(|i| match () {
            _ if pi_film && i > n / 2 => 0.0,
            _ if pi_film => p[i],
            _ => p[i].max(0.0),
        })
        .collect();
    let weight = |i: usize| if pi_film && (i == 0 || i == n / 2) { d / 2.0 } else { d };
    let (mut fx, mut fy, mut torque) = (0.0, 0.0, 0.0);
    for i in 0..n {
        fx -= R * L * kept_p[i] * theta[i].cos() * weight(i);
        fy -= R * L * kept_p[i] * theta[i].sin() * weight(i);
        let h = thickness(m, theta[i] + d / 2.0, 0.0);
        let couette = MU * R * (m.omega_bearing - m.omega_journal) / h * d;
        torque += R * R * L * (couette - h / (2.0 * R) * (kept_p[i + 1] - kept_p[i]));
    }
    let peak = kept_p.iter().fold(0.0_f64, |a, &b| a.max(b));
    let (along, across) = along_across(fx, fy);
    (along, across, peak, torque)
}

/// `|got - want| <= tol |want|` per component, measured against the force's magnitude.
fn assert_force(what: &str, got: (f64, f64), want: (f64, f64), tol: f64) {
    let size = want.0.hypot(want.1);
    let err = (got.0 - want.0).hypot(got.1 - want.1);
    assert!(err <= tol * size, "{what}: got {got:?}, want {want:?}, relative error {:.3e}", err / size);
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * want.abs(),
        "{what}: got {got}, want {want}, relative error {:.3e}",
        (got - want).abs() / want.abs()
    );
}

#[test]
fn short_bearing_forces_match_a_quadrature_of_the_reynolds_pressure() {
    for model in [FilmModel::Short, FilmModel::ShortPi] {
        for &(eps, eps_rate, gamma_rate, wj, wb) in &CASES {
            let m = motion(eps, eps_rate, gamma_rate, wj, wb);
            let f = film(model).force(&m);
            let (along, across, peak, _) = short_quadrature(model, &m, 1 << 17);
            let what = format!("{model:?} at {:?}", (eps, eps_rate, gamma_rate, wj, wb));
            assert_force(&what, (f.along, f.across), (along, across), 1e-6);
            assert_close(&format!("{what}: peak pressure"), f.peak_pressure, peak, 1e-5);
            assert!(f.peak_pressure >= peak * (1.0 - 1e-9), "{what}: the peak is below a grid value");
        }
    }
}

#[test]
fn short_bearing_torque_matches_a_quadrature_of_the_shear_stress() {
    // Journal and bearing at rest relative to each other: the pressure part alone.
    let cases =
        [(0.6, 20.0, 30.0, 40.0, -10.0), (0.8, -10.0, -20.0, 50.0, 30.0), (0.5, 15.0, 40.0, 0.0, 0.0)];
    for &(eps, eps_rate, gamma_rate, wj, wb) in &cases {
        let m = motion(eps, eps_rate, gamma_rate, wj, wb);
        let f = film(FilmModel::Short).force(&m);
        let (_, _, _, torque) = short_quadrature(FilmModel::Short, &m, 1 << 17);
        assert_close(
            &format!("torque at {:?}", (eps, eps_rate, gamma_rate, wj, wb)),
            f.torque_journal,
            torque,
            1e-6,
        );
    }
}

/// Richardson's extrapolation of a second-order result on `n` and `2n` nodes.
fn richardson(coarse: (f64, f64, f64, f64), fine: (f64, f64, f64, f64)) -> (f64, f64, f64, f64) {
    let x = |c: f64, f: f64| (4.0 * f - c) / 3.0;
    (x(coarse.0, fine.0), x(coarse.1, fine.1), fine.2, x(coarse.3, fine.3))
}

#[test]
fn long_bearing_forces_match_a_finite_difference_reynolds_solution() {
    for model in [FilmModel::Long, FilmModel::LongPi] {
        for &(eps, eps_rate, gamma_rate, wj, wb) in &CASES {
            let m = motion(eps, eps_rate, gamma_rate, wj, wb);
            let f = film(model).force(&m);
            let n = 1 << 15;
            let (along, across, peak, torque) =
                richardson(long_integrals(model, &m, n), long_integrals(model, &m, 2 * n));
            let what = format!("{model:?} at {:?}", (eps, eps_rate, gamma_rate, wj, wb));
            assert_force(&what, (f.along, f.across), (along, across), 1e-6);
            assert_close(&format!("{what}: peak pressure"), f.peak_pressure, peak, 1e-5);
            if model == FilmModel::Long {
                // Measured against the sizes of its two parts: the pure squeeze has none.
                let size = f.torque_journal.abs() + m.eccentricity * f.along.hypot(f.across);
                assert!(
                    (f.torque_journal - torque).abs() <= 1e-6 * size,
                    "{what}: torque {} against {torque}",
                    f.torque_journal
                );
            }
        }
    }
}

/// Ocvirk's steady short bearing (journal spinning at omega in a bearing at rest, fixed
/// load): `W = mu omega R L^3 / (4 c^2) eps / (1 - eps^2)^2 sqrt(16 eps^2 + pi^2 (1 -
/// eps^2))`, attitude `tan(phi) = pi sqrt(1 - eps^2) / (4 eps)` (Hamrock, Schmid &
/// Jacobson, Fundamentals of Fluid Film Lubrication, ch. 10). The load acts on the
/// journal against the film force, the film pushes the journal back (`along < 0`) and
/// forward in the sense of rotation (`across > 0`). omega is the sum `omega_j + omega_b`:
/// a spinning bearing with the journal at rest carries the same load.
#[test]
fn steady_short_bearing_matches_ocvirk() {
    let omega = 150.0;
    for model in [FilmModel::Short, FilmModel::ShortPi] {
        for eps in [0.05, 0.2, 0.5, 0.8, 0.95, 0.99] {
            let w = MU * omega * R * L.powi(3) / (4.0 * C * C) * eps / (1.0 - eps * eps).powi(2)
                * (16.0 * eps * eps + PI * PI * (1.0 - eps * eps)).sqrt();
            let attitude = (PI * (1.0 - eps * eps).sqrt() / (4.0 * eps)).atan();
            for (wj, wb) in [(omega, 0.0), (0.0, omega)] {
                let f = film(model).force(&motion(eps, 0.0, 0.0, wj, wb));
                assert_close(&format!("{model:?} load at eps {eps}"), f.along.hypot(f.across), w, 1e-12);
                assert_close(
                    &format!("{model:?} attitude at eps {eps}"),
                    f.across.atan2(-f.along),
                    attitude,
                    1e-12,
                );
            }
        }
    }
}

/// The steady long bearing with half-Sommerfeld (Gumbel) cavitation: `F_r = -(6 mu omega
/// R^3 L / c^2) 2 eps^2 / ((2 + eps^2)(1 - eps^2))`, `F_t = (6 mu omega R^3 L / c^2) pi eps
/// / ((2 + eps^2) sqrt(1 - eps^2))` (Hamrock, Schmid & Jacobson, ch. 9).
#[test]
fn steady_long_bearing_matches_half_sommerfeld() {
    let omega = 150.0;
    let k = 6.0 * MU * omega * R.powi(3) * L / (C * C);
    for model in [FilmModel::Long, FilmModel::LongPi] {
        for eps in [0.05, 0.2, 0.5, 0.8, 0.95, 0.99] {
            let f = film(model).force(&motion(eps, 0.0, 0.0, omega, 0.0));
            let radial = -k * 2.0 * eps * eps / ((2.0 + eps * eps) * (1.0 - eps * eps));
            let tangential = k * PI * eps / ((2.0 + eps * eps) * (1.0 - eps * eps).sqrt());
            assert_force(
                &format!("{model:?} at eps {eps}"),
                (f.along, f.across),
                (radial, tangential),
                1e-12,
            );
        }
    }
}

/// The pi-film short bearing as printed by Flores, Ambrosio, Claro, Lankarani & Koshy,
/// Mech. Mach. Theory 41 (2006) 247 (after Pinkus & Sternlicht 1961), with omega the
/// journal's speed relative to the bearing and gamma_dot the attitude rate relative to
/// the bearing:
/// `F_r = -(mu R L^3 / (2 c^2)) [2 eps^2 (omega - 2 gamma_dot) / (1 - eps^2)^2 + pi (1 + 2 eps^2) eps_dot / (1 - eps^2)^(5/2)]`,
/// `F_t = (mu R L^3 / (2 c^2)) [pi eps (omega - 2 gamma_dot) / (2 (1 - eps^2)^(3/2)) + 4 eps eps_dot / (1 - eps^2)^2]`.
#[test]
fn pi_film_short_bearing_reproduces_the_published_formula() {
    for &(eps, eps_rate, gamma_rate, wj, wb) in &CASES {
        let f = film(FilmModel::ShortPi).force(&motion(eps, eps_rate, gamma_rate, wj, wb));
        let (omega, gamma_dot) = (wj - wb, gamma_rate - wb);
        let k = MU * R * L.powi(3) / (2.0 * C * C);
        let e2 = 1.0 - eps * eps;
        let f_r = -k
            * (2.0 * eps * eps * (omega - 2.0 * gamma_dot) / e2.powi(2)
                + PI * (1.0 + 2.0 * eps * eps) * eps_rate / e2.powf(2.5));
        let f_t = k
            * (PI * eps * (omega - 2.0 * gamma_dot) / (2.0 * e2.powf(1.5))
                + 4.0 * eps * eps_rate / e2.powi(2));
        assert_force(
            &format!("at {:?}", (eps, eps_rate, gamma_rate, wj, wb)),
            (f.along, f.across),
            (f_r, f_t),
            1e-12,
        );
    }
}

/// Petroff: a concentric journal carries no force and the torque `-2 pi mu R^3 L (omega_j
/// - omega_b) / c`, whatever the model.
#[test]
fn concentric_journal_has_petroffs_torque() {
    for model in [FilmModel::Short, FilmModel::Long, FilmModel::ShortPi, FilmModel::LongPi] {
        let f = film(model).force(&motion(0.0, 0.0, 3.0, 120.0, -30.0));
        let petroff = -2.0 * PI * MU * R.powi(3) * L * 150.0 / C;
        assert_eq!((f.along, f.across, f.peak_pressure), (0.0, 0.0, 0.0), "{model:?}");
        assert_close(&format!("{model:?} torque"), f.torque_journal, petroff, 1e-12);
    }
}

/// The Gumbel forms are mirror-symmetric: reversing the wedge speed (all angular speeds)
/// mirrors the pressure about `n`, so `along` stays and `across` changes sign. The pi
/// forms, with their fixed half, are not.
#[test]
fn gumbel_films_mirror_with_the_wedge_speed() {
    for model in [FilmModel::Short, FilmModel::Long] {
        for &(eps, eps_rate, gamma_rate, wj, wb) in &CASES {
            let f = film(model).force(&motion(eps, eps_rate, gamma_rate, wj, wb));
            let g = film(model).force(&motion(eps, eps_rate, -gamma_rate, -wj, -wb));
            assert_force(&format!("{model:?} mirrored"), (g.along, -g.across), (f.along, f.across), 1e-12);
            assert_close(&format!("{model:?} mirrored peak"), g.peak_pressure, f.peak_pressure, 1e-12);
        }
    }
}

/// No NaN anywhere in the range: at rest, concentric, nearly touching, receding.
#[test]
fn film_is_finite_over_the_whole_range() {
    let finite =
        |f: &FilmForce| [f.along, f.across, f.torque_journal, f.peak_pressure].iter().all(|x| x.is_finite());
    for model in [FilmModel::Short, FilmModel::Long, FilmModel::ShortPi, FilmModel::LongPi] {
        let rest = film(model).force(&motion(0.7, 0.0, 0.0, 0.0, 0.0));
        assert_eq!(
            rest,
            FilmForce { along: 0.0, across: 0.0, torque_journal: 0.0, peak_pressure: 0.0 },
            "{model:?}"
        );
        for eps in [0.0, 1e-12, 1e-6, 0.5, 0.999] {
            for (eps_rate, gamma_rate, wj, wb) in
                [(1.0, 0.0, 0.0, 0.0), (-1.0, 2.0, -50.0, 0.0), (0.0, 0.0, 50.0, 50.0)]
            {
                let f = film(model).force(&motion(eps, eps_rate, gamma_rate, wj, wb));
                assert!(finite(&f), "{model:?} at eps {eps}: {f:?}");
                assert!(f.peak_pressure >= 0.0, "{model:?} at eps {eps}: {f:?}");
            }
        }
    }
}
