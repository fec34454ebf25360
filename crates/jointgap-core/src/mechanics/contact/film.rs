//! The oil film of a lubricated journal bearing: the force and the shear torque it puts
//! on the journal, from the Reynolds equation in its short-bearing (Ocvirk) and
//! long-bearing (Sommerfeld) limits (docs/lubrication.md).
//!
//! **Geometry and signs.** The journal (pin, radius R) sits in the bearing (hole, radial
//! clearance c) with its centre at `e n` from the bearing centre, `n = (cos gamma, sin
//! gamma)`. Angles are counter-clockwise; `phi = theta - gamma` is measured from `n`, where
//! the film is thinnest: `h = c - e cos(theta - gamma) = c H`, `H = 1 - eps cos phi`,
//! `eps = e/c`. The journal and bearing surfaces move counter-clockwise at `R omega_j` and
//! `R omega_b`. The thin-film Reynolds equation (isoviscous, incompressible oil)
//!
//! `(1/R^2) d/dtheta(h^3 dp/dtheta) + d/dz(h^3 dp/dz) = 6 mu (omega_j + omega_b) dh/dtheta + 12 mu dh/dt`
//!
//! with `dh/dt = -e_dot cos phi - e gamma_dot sin phi` at a fixed theta has the right-hand
//! side `-6 mu c N(phi)`, `N = 2 eps_dot cos phi - wbar eps sin phi`, where
//! `wbar = omega_j + omega_b - 2 gamma_dot` is the wedge speed (zero when journal, bearing
//! and load turn together) and `eps_dot = e_dot / c` the squeeze rate (positive: the
//! journal moves towards the wall at `phi = 0`). Pressure pushes the journal towards its
//! centre, so the force on the journal is `-R int int p (cos phi, sin phi) dphi dz` along
//! `n` and `perp(n)`.
//!
//! Every film integral is taken in closed form with Sommerfeld's substitution
//! ([`Sommerfeld`]); nothing is integrated numerically at run time.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::model::FilmModel;
use crate::scalar::{c, Implicit, Real};

/// An oil film between a journal and its bearing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Film {
    /// Journal radius R [m].
    pub radius: f64,
    /// Radial clearance c [m] (bearing radius minus journal radius).
    pub clearance: f64,
    /// Bearing length L [m].
    pub length: f64,
    /// Dynamic viscosity mu [Pa s].
    pub viscosity: f64,
    /// The simplification of the Reynolds equation and the part of the film that carries
    /// pressure.
    pub model: FilmModel,
}

/// Where the journal is in its bearing and how journal and bearing move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmMotion<T: Real = f64> {
    /// Eccentricity e [m]: distance from the bearing centre to the journal centre,
    /// `0 <= e < c`.
    pub eccentricity: T,
    /// Its rate de/dt [m/s]: positive when the journal moves towards the wall.
    pub eccentricity_rate: T,
    /// Rate d gamma/dt [rad/s] of the eccentricity direction `n = (cos gamma, sin gamma)`.
    pub attitude_rate: T,
    /// Journal angular velocity [rad/s], counter-clockwise positive.
    pub omega_journal: T,
    /// Bearing angular velocity [rad/s], counter-clockwise positive.
    pub omega_bearing: T,
}

/// What the film does to the journal. The bearing takes `-F` at its centre and the torque
/// `-torque_journal - e x F`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmForce {
    /// Force on the journal along `n` (bearing centre to journal centre) [N]; negative
    /// pushes the journal back towards the bearing centre.
    pub along: f64,
    /// Force on the journal along `perp(n)` (n turned +90 deg) [N].
    pub across: f64,
    /// Shear torque on the journal about its centre [N m], counter-clockwise positive.
    pub torque_journal: f64,
    /// Largest film pressure [Pa], 0 where the model's film carries no positive pressure.
    pub peak_pressure: f64,
}

/// The fixed half of the film that the pi-film forms integrate, `phi` in `[-pi, 0]` (that
/// is `[pi, 2 pi]`): from the widest film to the thinnest, the half that converges for a
/// counter-clockwise wedge speed.
const FIXED_HALF: (f64, f64) = (-PI, 0.0);

impl Film {
    /// Film force and torque on the journal for the motion `m` (requires `0 <= e < c`).
    ///
    /// The friction torque is the shear stress `mu R (omega_b - omega_j)/h - (h/2R)
    /// dp/dtheta` on the journal surface. Its Couette part is taken over the full
    /// circumference (the cavitated region is filled with oil streamers that still shear;
    /// the usual choice, Hamrock, Schmid & Jacobson, Fundamentals of Fluid Film
    /// Lubrication, 2nd ed. 2004, ch. 10): `-2 pi mu R^3 L (omega_j - omega_b) / (c
    /// sqrt(1 - eps^2))`, Petroff's torque at `eps = 0`. Its pressure (Poiseuille) part
    /// integrates by parts around the circle to `-e F_across / 2` for any pressure field
    /// that is zero outside its film, so it follows from the force.
    pub fn force(&self, m: &FilmMotion) -> FilmForce {
        debug_assert!(
            (0.0..self.clearance).contains(&m.eccentricity),
            "eccentricity {} outside [0, {})",
            m.eccentricity,
            self.clearance
        );
        let (s, squeeze, wedge) = self.kinematics(m);
        let (along, across, peak_pressure) = match self.model {
            FilmModel::Short => self.short(&s, squeeze, wedge, true),
            FilmModel::ShortPi => self.short(&s, squeeze, wedge, false),
            FilmModel::Long => self.long(&s, squeeze, wedge, true),
            FilmModel::LongPi => self.long(&s, squeeze, wedge, false),
        };
        FilmForce { along, across, torque_journal: self.torque(&s, m, across), peak_pressure }
    }

    /// The film's force along and across `n` and its torque on the journal
    /// ([`Film::force`] less the peak pressure) in any number type.
    pub fn loads<T: Real>(&self, m: &FilmMotion<T>) -> [T; 3] {
        let (s, squeeze, wedge) = self.kinematics(m);
        let zero = c::<T>(0.0);
        let (along, across) = match self.model {
            FilmModel::Short | FilmModel::ShortPi => self
                .short_force(&s, squeeze, wedge, self.model == FilmModel::Short)
                .map_or((zero, zero), |f| (f.0, f.1)),
            FilmModel::Long | FilmModel::LongPi => self
                .long_arc(&s, squeeze, wedge, self.model == FilmModel::Long)
                .map_or((zero, zero), |arc| self.long_force(&s, squeeze, wedge, arc)),
        };
        [along, across, self.torque(&s, m, across)]
    }

    /// The Sommerfeld substitution at the motion's eccentricity ratio, the squeeze rate
    /// `eps_dot` and the wedge speed `wbar`.
    fn kinematics<T: Real>(&self, m: &FilmMotion<T>) -> (Sommerfeld<T>, T, T) {
        let s = Sommerfeld::new(m.eccentricity / self.clearance);
        let squeeze = m.eccentricity_rate / self.clearance;
        let wedge = m.omega_journal + m.omega_bearing - m.attitude_rate * 2.0;
        (s, squeeze, wedge)
    }

    /// The shear torque on the journal, its pressure part from the force `across`.
    fn torque<T: Real>(&self, s: &Sommerfeld<T>, m: &FilmMotion<T>, across: T) -> T {
        let (mu, r, l, c) = (self.viscosity, self.radius, self.length, self.clearance);
        let couette = (m.omega_journal - m.omega_bearing) * (-TAU * mu * r.powi(3) * l) / (s.root * c);
        couette - m.eccentricity * 0.5 * across
    }

    /// Short bearing (Ocvirk, for L/D below about 0.5): the axial flow carries the film,
    /// `h^3 d2p/dz2 = -6 mu c N(phi)` with `p = 0` at the bearing ends `z = +-L/2`, so
    ///
    /// `p = 3 mu (L^2/4 - z^2) N(phi) / (c^2 H^3)`,  `N = a cos phi + b sin phi`,
    /// `a = 2 eps_dot`, `b = -wbar eps`.
    ///
    /// `N` is positive over the half circle centred on `atan2(b, a)`, which turns with the
    /// ratio of squeeze to wedge: the exact positive-pressure (Gumbel) film (`gumbel`).
    /// Otherwise the pressure is taken over [`FIXED_HALF`], negative parts included (the
    /// pi-film). Returns the force along and across `n` and the peak pressure.
    fn short(&self, s: &Sommerfeld, squeeze: f64, wedge: f64, gumbel: bool) -> (f64, f64, f64) {
        let Some((along, across, centre)) = self.short_force(s, squeeze, wedge, gumbel) else {
            return (0.0, 0.0, 0.0);
        };
        let (a, b) = (2.0 * squeeze, -wedge * s.eps);
        let (mu, l, c) = (self.viscosity, self.length, self.clearance);

        // Peak pressure at mid-length (z = 0): the largest value at a stationary point in
        // the positive half circle, or (pi-film) at an end of the fixed half.
        let p = |phi: f64| 0.75 * mu * l * l / (c * c) * (a * phi.cos() + b * phi.sin()) / s.h(phi).powi(3);
        let mut peak = if gumbel { 0.0 } else { p(FIXED_HALF.0).max(p(FIXED_HALF.1)).max(0.0) };
        let mut t = [0.0; 4];
        let n = short_peak_candidates(s.eps, centre, &mut t);
        for &t in &t[..n] {
            let phi = centre + 2.0 * t.atan();
            if gumbel || phi - TAU * (phi / TAU).round() <= 0.0 {
                peak = peak.max(p(phi));
            }
        }
        (along, across, peak)
    }

    /// The short bearing's force along and across `n` ([`Self::short`]) and the centre
    /// `atan2(b, a)` of the half circle where `N` is positive, in any number type; `None`
    /// where `N` is zero everywhere (no squeeze, no wedge).
    fn short_force<T: Real>(
        &self,
        s: &Sommerfeld<T>,
        squeeze: T,
        wedge: T,
        gumbel: bool,
    ) -> Option<(T, T, T)> {
        let (a, b) = (squeeze * 2.0, -wedge * s.eps);
        if a == 0.0 && b == 0.0 {
            return None;
        }
        let centre = b.atan2(a);
        let (lo, hi) = if gumbel {
            (centre - FRAC_PI_2, centre + FRAC_PI_2)
        } else {
            (c(FIXED_HALF.0), c(FIXED_HALF.1))
        };
        let i = s.moments(s.psi(hi)).minus(&s.moments(s.psi(lo)));
        let (mu, r, l, c) = (self.viscosity, self.radius, self.length, self.clearance);
        // z-integral of the pressure: int (L^2/4 - z^2) dz = L^3/6.
        let k = mu * r * l.powi(3) / (2.0 * c * c);
        let along = (a * i.cc3 + b * i.sc3) * -k;
        let across = (a * i.sc3 + b * i.ss3) * -k;
        Some((along, across, centre))
    }

    /// Long bearing (Sommerfeld, for L/D above about 2): the circumferential flow carries
    /// the film, `d/dphi(H^3 dp/dphi) = -6 mu (R/c)^2 N(phi)`. Periodic, and zero at the
    /// widest film (`phi = pi`, where oil is supplied; Pinkus & Sternlicht 1961):
    ///
    /// `p = k [-wbar eps sin phi (2 - eps cos phi) / ((2 + eps^2) H^2)
    ///        + eps_dot (cos phi (2 - eps cos phi) / H^2 + (2 + eps)/(1 + eps)^2)]`,
    /// `dp/dphi = k [wbar / H^2 + kappa / H^3 - 2 eps_dot sin phi / H^3]`,
    /// `k = 6 mu R^2 / c^2`, `kappa = -2 wbar (1 - eps^2)/(2 + eps^2)`.
    ///
    /// Gumbel (`gumbel`): the pressure acts where it is positive, one arc from `phi = pi`
    /// to the pressure's other zero ([`Self::long_positive_arc`]); the pi-film takes
    /// [`FIXED_HALF`]. The force integrals go by parts to `int p' (sin, cos)`, closed form
    /// in the Sommerfeld variable.
    fn long(&self, s: &Sommerfeld, squeeze: f64, wedge: f64, gumbel: bool) -> (f64, f64, f64) {
        let eps = s.eps;
        let Some(arc) = self.long_arc(s, squeeze, wedge, gumbel) else {
            return (0.0, 0.0, 0.0);
        };
        let (along, across) = self.long_force(s, squeeze, wedge, arc);
        let p = |phi: f64| self.long_pressure(s, squeeze, wedge, phi);

        // Peak: dp/dphi = 0 where wbar eps cos phi + 2 eps_dot sin phi = wbar + kappa.
        let kappa = self.long_kappa(s, wedge);
        let amp = (wedge * eps).hypot(2.0 * squeeze);
        let turn = ((wedge + kappa) / amp).clamp(-1.0, 1.0).acos();
        let at = (2.0 * squeeze).atan2(wedge * eps);
        let mut peak = if gumbel { 0.0 } else { p(FIXED_HALF.1).max(0.0) };
        for phi in [at - turn, at + turn] {
            if gumbel || phi - TAU * (phi / TAU).round() <= 0.0 {
                peak = peak.max(p(phi));
            }
        }
        (along, across, peak)
    }

    /// The arc in the Sommerfeld variable over which the long bearing's film carries
    /// pressure: the positive-pressure arc (`gumbel`) or the fixed half; `None` where the
    /// film carries none (no squeeze, no wedge; or no positive pressure).
    fn long_arc<T: Real>(&self, s: &Sommerfeld<T>, squeeze: T, wedge: T, gumbel: bool) -> Option<(T, T)> {
        if wedge * s.eps == 0.0 && squeeze == 0.0 {
            return None;
        }
        if gumbel {
            Self::long_positive_arc(s, squeeze, wedge)
        } else {
            Some((s.psi(c(FIXED_HALF.0)), s.psi(c(FIXED_HALF.1))))
        }
    }

    /// The long bearing's force along and across `n` over the arc `(psi_a, psi_b)` (in the
    /// Sommerfeld variable), in any number type ([`Self::long`]).
    fn long_force<T: Real>(&self, s: &Sommerfeld<T>, squeeze: T, wedge: T, (psi_a, psi_b): (T, T)) -> (T, T) {
        let (r, l) = (self.radius, self.length);
        let k = self.long_k();
        let kappa = self.long_kappa(s, wedge);
        let p = |phi: T| self.long_pressure(s, squeeze, wedge, phi);
        let i = s.moments(psi_b).minus(&s.moments(psi_a));
        let (phi_a, phi_b) = (s.phi(psi_a), s.phi(psi_b));
        let dp_sin = (wedge * i.s2 + kappa * i.s3 - squeeze * 2.0 * i.ss3) * k;
        let dp_cos = (wedge * i.c2 + kappa * i.c3 - squeeze * 2.0 * i.sc3) * k;
        let ((sin_a, cos_a), (sin_b, cos_b)) = (phi_a.sin_cos(), phi_b.sin_cos());
        let p_cos = p(phi_b) * sin_b - p(phi_a) * sin_a - dp_sin;
        let p_sin = -(p(phi_b) * cos_b - p(phi_a) * cos_a) + dp_cos;
        (p_cos * (-r * l), p_sin * (-r * l))
    }

    /// `k = 6 mu R^2 / c^2` of the long bearing's pressure ([`Self::long`]).
    fn long_k(&self) -> f64 {
        let (mu, r, c) = (self.viscosity, self.radius, self.clearance);
        6.0 * mu * r * r / (c * c)
    }

    /// `kappa = -2 wbar (1 - eps^2)/(2 + eps^2)` of the long bearing's pressure gradient.
    fn long_kappa<T: Real>(&self, s: &Sommerfeld<T>, wedge: T) -> T {
        wedge * -2.0 * s.root * s.root / (s.eps * s.eps + 2.0)
    }

    /// The long bearing's pressure at `phi` ([`Self::long`]).
    fn long_pressure<T: Real>(&self, s: &Sommerfeld<T>, squeeze: T, wedge: T, phi: T) -> T {
        let eps = s.eps;
        let (sn, cs) = phi.sin_cos();
        let h = -(eps * cs) + 1.0;
        let two = c::<T>(2.0);
        (-wedge * eps * sn * (two - eps * cs) / ((eps * eps + 2.0) * h * h)
            + squeeze * (cs * (two - eps * cs) / (h * h) + (eps + 2.0) / ((eps + 1.0) * (eps + 1.0))))
            * self.long_k()
    }

    /// The long bearing's positive-pressure arc as `(psi_a, psi_b)` in the Sommerfeld
    /// variable, `None` where the pressure is nowhere positive. In `psi` the pressure is
    /// `2 cos(psi/2) F(psi) k / (1 - eps^2)^2` with
    /// `F = eps_dot cos(psi/2) (2 - eps + eps cos psi) + w sin(psi/2) (2 - eps^2 + eps cos psi)`,
    /// `w = -wbar eps sqrt(1 - eps^2)/(2 + eps^2)`; on `(-pi, pi)` the sign of `F` is that
    /// of `2 eps_dot + w r(t)`, `t = tan(psi/2)`, so the pressure has exactly one zero
    /// besides `psi = pi`, at `r(t) = q = -2 eps_dot / w` ([`LONG_ARC_END`]).
    fn long_positive_arc<T: Real>(s: &Sommerfeld<T>, squeeze: T, wedge: T) -> Option<(T, T)> {
        let eps = s.eps;
        let w = -wedge * eps * s.root / (eps * eps + 2.0);
        if w == 0.0 {
            // Pure squeeze: positive all round when approaching, nowhere when receding.
            return (squeeze > 0.0).then_some((c(-PI), c(PI)));
        }
        let q = squeeze * -2.0 / w;
        let zero = eps.implicit(q, &LONG_ARC_END);
        Some(if w > 0.0 { (zero, c(PI)) } else { (c(-PI), zero) })
    }
}

/// The end `psi = 2 atan(t)` of the long bearing's positive-pressure arc
/// ([`Film::long_positive_arc`]) as a function of `(eps, q)`: `t` is the one real root of
/// `G(t) = t (A + B t^2) - q (1 + D t^2)`, `A = (1 + eps)(2 - eps)`,
/// `B = (1 - eps)(2 + eps)`, `D = 1 - eps`. `G/(1 + D t^2) = r(t) - q` with
/// `r = t (A + B t^2)/(1 + D t^2)` increasing (`r'` has positive coefficients) and `r/t`
/// between `A` and `B/D`, so the root lies within `t` in `q / [max, min](A, B/D)`, where
/// Newton's steps in a bracket find it. Its slopes follow from `G = 0`: `dt = -(G_eps
/// deps + G_q dq) / G_t`.
static LONG_ARC_END: Implicit =
    Implicit { name: "jg_long_arc_end", value: long_arc_end, slopes: long_arc_end_slopes };

/// `(A, B, D)` of [`LONG_ARC_END`] at `eps`.
fn long_arc_coefficients(eps: f64) -> (f64, f64, f64) {
    ((1.0 + eps) * (2.0 - eps), (1.0 - eps) * (2.0 + eps), 1.0 - eps)
}

/// The value of [`LONG_ARC_END`].
extern "C" fn long_arc_end(eps: f64, q: f64) -> f64 {
    let (a, b, d) = long_arc_coefficients(eps);
    // r(t) = q times (1 + D t^2): a cubic with one real root.
    let cubic = |t: f64| (t * (a + b * t * t) - q * (1.0 + d * t * t), a + 3.0 * b * t * t - 2.0 * q * d * t);
    let (t1, t2) = (q / a, q * d / b);
    2.0 * root(cubic, t1.min(t2), t1.max(t2)).atan()
}

/// The slopes of [`LONG_ARC_END`] at `(eps, q)`, its value `psi` there.
fn long_arc_end_slopes(eps: f64, q: f64, psi: f64) -> (f64, f64) {
    let (a, b, d) = long_arc_coefficients(eps);
    let t = (0.5 * psi).tan();
    let g_t = a + 3.0 * b * t * t - 2.0 * q * d * t;
    // dA/deps = 1 - 2 eps, dB/deps = -1 - 2 eps, dD/deps = -1.
    let g_eps = t * ((1.0 - 2.0 * eps) - (1.0 + 2.0 * eps) * t * t) + q * t * t;
    let g_q = -(1.0 + d * t * t);
    // psi = 2 atan(t): dpsi = 2 dt / (1 + t^2).
    let dpsi_dt = 2.0 / (1.0 + t * t);
    (-g_eps / g_t * dpsi_dt, -g_q / g_t * dpsi_dt)
}

/// The stationary points of the short bearing's mid-length pressure `N/H^3` inside its
/// positive half circle `phi = centre + u`, `|u| < pi/2`, as `t = tan(u/2)` in `(-1, 1)`
/// (written to `out`, their number returned). With `(a, b) = |N| (cos centre, sin
/// centre)`, `(N/H^3)' = 0` reads `-sin u - eps sin(centre + 2u) - 2 eps sin(centre) = 0`,
/// a quartic in `t`. The pressure can have two maxima there (squeeze away from the wall
/// at `eps` above about 0.5 puts a peak either side of the widest film), so all are
/// returned.
fn short_peak_candidates(eps: f64, centre: f64, out: &mut [f64; 4]) -> usize {
    let (sc, cc) = centre.sin_cos();
    let quartic =
        [-3.0 * eps * sc, -(2.0 + 4.0 * eps * cc), 2.0 * eps * sc, 4.0 * eps * cc - 2.0, -3.0 * eps * sc];
    poly_roots(&quartic, -1.0, 1.0, out)
}

/// The real roots in `(lo, hi)` of the polynomial with coefficients `p` (constant first,
/// degree at most 4), in increasing order, written to `out`; returns their number.
/// Between consecutive roots of its derivative a polynomial is monotone, so each such
/// piece holds at most one root, which [`root`] finds. Roots where the polynomial keeps
/// its sign (even multiplicity) are not reported.
fn poly_roots(p: &[f64], lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
    if p.len() < 2 {
        return 0;
    }
    let mut dp = [0.0; 4];
    for k in 1..p.len() {
        dp[k - 1] = k as f64 * p[k];
    }
    let dp = &dp[..p.len() - 1];
    let mut knots = [0.0; 4];
    let n_knots = poly_roots(dp, lo, hi, &mut knots);
    let eval = |q: &[f64], x: f64| q.iter().rev().fold(0.0, |acc, &c| acc * x + c);
    let mut n = 0;
    let mut a = lo;
    for &b in knots[..n_knots].iter().chain([hi].iter()) {
        if (eval(p, a) < 0.0) != (eval(p, b) < 0.0) {
            out[n] = root(|x| (eval(p, x), eval(dp, x)), a, b);
            n += 1;
        }
        a = b;
    }
    n
}

/// The root in `[lo, hi]` of a function `f` (value and slope) that changes sign there
/// (or is zero at an end): Newton's steps, replaced by bisection when one would leave the
/// shrinking bracket (a step that ends within rounding beyond it stops at its edge, so that
/// a root at an edge is reached at Newton's pace).
fn root(f: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64) -> f64 {
    let low_negative = f(lo).0 < 0.0;
    let mut x = 0.5 * (lo + hi);
    for _ in 0..100 {
        let (value, slope) = f(x);
        if value == 0.0 {
            return x;
        }
        if (value < 0.0) == low_negative {
            lo = x;
        } else {
            hi = x;
        }
        let tol = 1e-15 * (1.0 + x.abs());
        let newton = x - value / slope;
        if (newton - x).abs() <= tol {
            return newton.clamp(lo, hi);
        }
        let next = match newton.clamp(lo, hi) {
            inside if newton > lo - 1e3 * tol && newton < hi + 1e3 * tol && inside != x => inside,
            _ => 0.5 * (lo + hi),
        };
        if hi - lo <= tol {
            return next;
        }
        x = next;
    }
    x
}

/// Sommerfeld's substitution `1 - eps cos phi = (1 - eps^2)/(1 + eps cos psi)`, with
/// `cos phi = (cos psi + eps)/(1 + eps cos psi)`, `sin phi = sqrt(1 - eps^2) sin psi /
/// (1 + eps cos psi)`, `dphi = sqrt(1 - eps^2) dpsi / (1 + eps cos psi)`: it turns each film
/// integrand `cos^i phi sin^j phi / H^n` into a trigonometric polynomial in `psi`.
struct Sommerfeld<T: Real = f64> {
    /// Eccentricity ratio.
    eps: T,
    /// `sqrt(1 - eps^2)`.
    root: T,
    /// `eps / (1 + sqrt(1 - eps^2))`, the `(k - 1)/(k + 1)` of `k = sqrt((1 + eps)/(1 - eps))`.
    beta: T,
}

/// Antiderivatives in `phi`, written in `psi`, of the film integrands (`H = 1 - eps cos
/// phi`): `cc3 = int cos^2/H^3`, `sc3 = int sin cos/H^3`, `ss3 = int sin^2/H^3`, `s2 = int
/// sin/H^2`, `s3 = int sin/H^3`, `c2 = int cos/H^2`, `c3 = int cos/H^3`.
struct Moments<T: Real = f64> {
    cc3: T,
    sc3: T,
    ss3: T,
    s2: T,
    s3: T,
    c2: T,
    c3: T,
}

impl<T: Real> Moments<T> {
    /// The definite integrals from `other`'s end to this one's.
    fn minus(&self, other: &Moments<T>) -> Moments<T> {
        Moments {
            cc3: self.cc3 - other.cc3,
            sc3: self.sc3 - other.sc3,
            ss3: self.ss3 - other.ss3,
            s2: self.s2 - other.s2,
            s3: self.s3 - other.s3,
            c2: self.c2 - other.c2,
            c3: self.c3 - other.c3,
        }
    }
}

impl<T: Real> Sommerfeld<T> {
    fn new(eps: T) -> Self {
        let root = (c::<T>(1.0) - eps * eps).sqrt();
        Sommerfeld { eps, root, beta: eps / (root + 1.0) }
    }

    /// `psi` of `phi`: `tan(psi/2) = k tan(phi/2)` jumps at `phi = pi`; written as
    /// `psi = phi + 2 atan(beta sin phi / (1 - beta cos phi))` it is continuous and
    /// increasing for every `phi`, so an arc needs no splitting.
    fn psi(&self, phi: T) -> T {
        let (s, c) = phi.sin_cos();
        phi + (self.beta * s).atan2(T::constant(1.0) - self.beta * c) * 2.0
    }

    /// `phi` of `psi`, the inverse of [`Self::psi`] (`beta` changes sign).
    fn phi(&self, psi: T) -> T {
        let (s, c) = psi.sin_cos();
        psi - (self.beta * s).atan2(self.beta * c + 1.0) * 2.0
    }

    /// The antiderivatives at `psi`.
    fn moments(&self, psi: T) -> Moments<T> {
        let (e, r) = (self.eps, self.root);
        let (s, c) = psi.sin_cos();
        let (r2, r3) = (r * r, r * r * r);
        let (r4, r5) = (r2 * r2, r2 * r3);
        Moments {
            // (cos psi + eps)^2 / r^5
            cc3: ((psi + s * c) * 0.5 + e * 2.0 * s + e * e * psi) / r5,
            // sin psi (cos psi + eps) / r^4
            sc3: -(c * 0.5 * c + e * c) / r4,
            // sin^2 psi / r^3
            ss3: (psi - s * c) * 0.5 / r3,
            // sin psi / r^2
            s2: -c / r2,
            // sin psi (1 + eps cos psi) / r^4
            s3: -(c + e * 0.5 * c * c) / r4,
            // (cos psi + eps) / r^3
            c2: (s + e * psi) / r3,
            // (cos psi + eps)(1 + eps cos psi) / r^5
            c3: ((e * e + 1.0) * s + e * 0.5 * (psi * 3.0 + s * c)) / r5,
        }
    }
}

impl Sommerfeld {
    /// Dimensionless film thickness `H = h/c` at `phi`.
    fn h(&self, phi: f64) -> f64 {
        1.0 - self.eps * phi.cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// psi and phi are inverse maps, continuous through phi = pi, and psi keeps the
    /// thinnest and widest film (0 and pi) in place.
    #[test]
    fn sommerfeld_variable_is_continuous_and_inverts() {
        for eps in [0.0, 0.3, 0.9, 0.999] {
            let s = Sommerfeld::new(eps);
            assert!(s.psi(0.0).abs() < 1e-15 && (s.psi(PI) - PI).abs() < 1e-13);
            let mut last = s.psi(-4.0);
            for k in 0..=800 {
                let phi = -4.0 + 8.0 * k as f64 / 800.0;
                let psi = s.psi(phi);
                assert!(psi >= last, "psi decreases at phi {phi}, eps {eps}");
                assert!((s.phi(psi) - phi).abs() < 1e-12, "eps {eps} phi {phi}");
                // 1 - eps cos phi = (1 - eps^2) / (1 + eps cos psi)
                assert!((s.h(phi) - (1.0 - eps * eps) / (1.0 + eps * psi.cos())).abs() < 1e-12);
                last = psi;
            }
        }
    }

    /// The roots of (t - 0.5)(t + 0.3)(t - 0.9)(t + 0.95) in (-1, 1), and a double root
    /// (no sign change) left out.
    #[test]
    fn polynomial_roots_are_all_found() {
        let mut out = [0.0; 4];
        // Expanded with the roots r: coefficients of prod (t - r), constant first.
        let product = |roots: &[f64]| {
            let mut c = vec![1.0];
            for &r in roots {
                let mut next = vec![0.0; c.len() + 1];
                for (k, &ck) in c.iter().enumerate() {
                    next[k + 1] += ck;
                    next[k] -= r * ck;
                }
                c = next;
            }
            c
        };
        let n = poly_roots(&product(&[0.5, -0.3, 0.9, -0.95]), -1.0, 1.0, &mut out);
        assert_eq!(n, 4);
        for (got, want) in out.iter().zip([-0.95, -0.3, 0.5, 0.9]) {
            assert!((got - want).abs() < 1e-14, "{out:?}");
        }
        let n = poly_roots(&product(&[0.2, 0.2, -0.6]), -1.0, 1.0, &mut out);
        assert_eq!((n, (out[0] + 0.6).abs() < 1e-14), (1, true), "{out:?}");
    }

    /// The end of the long bearing's positive-pressure arc solves its cubic, and its
    /// slopes (from the implicit function theorem) equal central differences of the
    /// iteration's values, for squeeze both ways and a range of eccentricities.
    #[test]
    fn long_arc_end_slopes_match_differences() {
        for eps in [0.05, 0.4, 0.8, 0.97] {
            for q in [-3.0, -0.2, 0.0, 0.7, 5.0] {
                let psi = long_arc_end(eps, q);
                let t = (0.5 * psi).tan();
                let (a, b, d) = long_arc_coefficients(eps);
                let g = t * (a + b * t * t) - q * (1.0 + d * t * t);
                assert!(g.abs() < 1e-12 * (1.0 + q.abs()) * (1.0 + t.abs().powi(3)), "G = {g} at {eps}, {q}");
                let (d_eps, d_q) = long_arc_end_slopes(eps, q, psi);
                let h = 1e-6;
                let by_eps = (long_arc_end(eps + h, q) - long_arc_end(eps - h, q)) / (2.0 * h);
                let by_q = (long_arc_end(eps, q + h) - long_arc_end(eps, q - h)) / (2.0 * h);
                assert!(
                    (d_eps - by_eps).abs() < 1e-7 * (1.0 + by_eps.abs()),
                    "{eps}, {q}: {d_eps} vs {by_eps}"
                );
                assert!((d_q - by_q).abs() < 1e-7 * (1.0 + by_q.abs()), "{eps}, {q}: {d_q} vs {by_q}");
            }
        }
    }
}
