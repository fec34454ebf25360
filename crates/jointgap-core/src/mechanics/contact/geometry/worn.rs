//! A worn journal in a worn bearing: each part's profile as data, a wear depth against
//! the angle in its own body frame (docs/wear.md), and the one contact point of the two
//! profiles.
//!
//! A profile is given by its support function: the distance `h(theta)` from the part's
//! centre to the tangent line whose outward normal points along `theta`, `h_B = R_B +
//! w_B(theta)` for the bearing's hole and `h_J = R_J - w_J(theta)` for the journal. A
//! wear depth `w` removed along the surface normal moves that tangent line by `w`, so the
//! support function is how Archard's depth, measured along the normal at the contact,
//! changes the shape; it is the polar radius to first order in the wear's slope (they
//! differ by `w'^2 / (2 R)`). The surface point of normal `u(theta)` is `h u + h' u_perp`
//! (the envelope of the tangent lines), and in direction `u(alpha)` the journal reaches
//! past the bearing's wall by `delta(alpha) = e . u + h_J(alpha) - h_B(alpha)`, `e` the
//! eccentricity: for convex parts the penetration is the largest `delta(alpha)` (the
//! separating-axis theorem), at the angle where `delta'(alpha) = 0`, whose `u` is the
//! contact normal. A journal in a worn pocket may see several local maxima (the pocket's
//! rims): the largest is found by a scan of the angles where it can lie, then Newton's
//! method, so that the penetration stays continuous when the deepest point passes from
//! one rim to the other.

use crate::error::{Error, Named};
use crate::math::{perp, Vec2};
use crate::scalar::Real;
use smallvec::SmallVec;

use crate::mechanics::contact::point::{ContactPoint, ContactPoints, MaterialPoint};
use crate::mechanics::planar_body::BodyState;

use super::JournalBearing;

/// The fewest points a wear table may have: fewer cannot describe a profile worn at one
/// spot (its spline would ring around the whole circumference).
pub const MIN_POINTS: usize = 8;

/// A periodic function of the angle over `[0, 2 pi)` through values at equally spaced
/// angles `2 pi k / N`: the periodic cubic spline (de Boor, A Practical Guide to
/// Splines, chapter IV). It is C2: its value, slope and curvature are continuous, so the
/// penetration, the normal and the penetration rate of a worn joint are continuous in
/// the bodies' states and the penetration's rate is continuous in time, which the
/// location of contact events (a root of the penetration along a step's dense output)
/// and the implicit integrators' Newton iterations (a Jacobian of the forces) rely on.
/// A piecewise linear table would turn the normal with a jump at each table angle.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicSpline {
    /// Values at the angles `2 pi k / N`.
    values: Vec<f64>,
    /// Second derivatives there.
    curvatures: Vec<f64>,
    /// Angle between table points [rad].
    spacing: f64,
}

impl PeriodicSpline {
    /// The spline through `values` (at least 3) at `2 pi k / N`.
    pub fn new(values: &[f64]) -> Self {
        let n = values.len();
        let spacing = std::f64::consts::TAU / n as f64;
        // M_{k-1} + 4 M_k + M_{k+1} = 6 / h^2 (y_{k-1} - 2 y_k + y_{k+1}), cyclic.
        let rhs: Vec<f64> = (0..n)
            .map(|k| {
                6.0 / (spacing * spacing) * (values[(k + n - 1) % n] - 2.0 * values[k] + values[(k + 1) % n])
            })
            .collect();
        PeriodicSpline { values: values.to_vec(), curvatures: solve_cyclic(&rhs), spacing }
    }

    /// `(s, s', s'')` at angle `theta` [rad], any value.
    #[inline]
    pub fn eval(&self, theta: f64) -> (f64, f64, f64) {
        let (k, t) = self.cell(theta);
        self.piece_of(k, theta - t).cubic(self.spacing, t)
    }

    /// The cubic piece that holds angle `theta` [rad], any value, its start unwrapped
    /// as `theta` is.
    pub fn piece(&self, theta: f64) -> Piece<f64> {
        let (k, t) = self.cell(theta);
        self.piece_of(k, theta - t)
    }

    /// The table interval `k` that holds angle `theta` and how far into it `theta` lies
    /// [rad].
    #[inline]
    fn cell(&self, theta: f64) -> (usize, f64) {
        let n = self.values.len();
        let x = within_turn(theta) / self.spacing;
        // `x` is not negative: its truncation is its floor (a call without SSE4.1).
        let k = (x as usize).min(n - 1);
        (k, (x - k as f64) * self.spacing)
    }

    /// The piece of table interval `k`, starting at `start` [rad].
    #[inline]
    fn piece_of(&self, k: usize, start: f64) -> Piece<f64> {
        let n = self.values.len();
        Piece {
            start,
            values: [self.values[k], self.values[(k + 1) % n]],
            curvatures: [self.curvatures[k], self.curvatures[(k + 1) % n]],
        }
    }

    /// The largest and smallest second derivative (the spline's is linear between the
    /// table points, so the extremes are at them).
    fn curvature_range(&self) -> (f64, f64) {
        self.curvatures.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &m| (lo.min(m), hi.max(m)))
    }

    /// A value the spline never goes below: the smallest table value less the most a
    /// cubic piece can sag below its chord, `h^2 max|s''| / 8`.
    fn floor(&self) -> f64 {
        let (lo, hi) = self.curvature_range();
        let lowest = self.values.iter().fold(f64::INFINITY, |a, &v| a.min(v));
        lowest - self.spacing * self.spacing * lo.abs().max(hi.abs()) / 8.0
    }
}

/// `theta.rem_euclid(2 pi)` to the bit, without the division's remainder (a call) for
/// the angles within a turn either side of zero, which the profiles' angles mostly are.
#[inline]
fn within_turn(theta: f64) -> f64 {
    use std::f64::consts::TAU;
    if (0.0..TAU).contains(&theta) {
        theta
    } else if theta > -TAU && theta < 0.0 {
        theta + TAU
    } else {
        theta.rem_euclid(TAU)
    }
}

/// One cubic piece of a [`PeriodicSpline`], in any number type: where it starts, the
/// values and the second derivatives at its two ends. A compiled evaluation reads it as
/// numbers ([`Start`]), so that one code serves every piece.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece<T> {
    /// The angle where it starts [rad].
    pub start: T,
    /// The values at its ends.
    pub values: [T; 2],
    /// The second derivatives at its ends.
    pub curvatures: [T; 2],
}

impl<T: Real> Piece<T> {
    /// The numbers that give a piece.
    const NUMBERS: usize = 5;

    /// A piece of no wear (a part without a table).
    fn zero() -> Self {
        let zero = T::constant(0.0);
        Piece { start: zero, values: [zero; 2], curvatures: [zero; 2] }
    }

    /// `(s, s', s'')` at angle `theta` [rad] of a piece `h` wide: the cubic whose second
    /// derivative runs linearly between the ends'.
    #[inline]
    pub fn at(&self, h: f64, theta: T) -> (T, T, T) {
        self.cubic(h, theta - self.start)
    }

    /// [`Piece::at`] `t` [rad] into the piece.
    #[inline]
    fn cubic(&self, h: f64, t: T) -> (T, T, T) {
        let s = T::constant(h) - t;
        let ([y0, y1], [m0, m1]) = (self.values, self.curvatures);
        let (c0, c1) = (y0 / h - m0 * h / 6.0, y1 / h - m1 * h / 6.0);
        let value = (m0 * s * s * s + m1 * t * t * t) / (6.0 * h) + c0 * s + c1 * t;
        let slope = (-m0 * s * s + m1 * t * t) / (2.0 * h) - c0 + c1;
        let curvature = (m0 * s + m1 * t) / h;
        (value, slope, curvature)
    }

    fn read(x: &[T]) -> Self {
        Piece { start: x[0], values: [x[1], x[2]], curvatures: [x[3], x[4]] }
    }

    fn numbers(&self) -> [T; 5] {
        [self.start, self.values[0], self.values[1], self.curvatures[0], self.curvatures[1]]
    }
}

/// Solves the cyclic system `x_{k-1} + 4 x_k + x_{k+1} = r_k` by the Thomas algorithm
/// with the Sherman-Morrison correction for the corners (Press et al., Numerical
/// Recipes, section 2.7).
fn solve_cyclic(r: &[f64]) -> Vec<f64> {
    let n = r.len();
    // A = T + u v^T with T tridiagonal (diagonal 4 - gamma at the first row, 4 - 1/gamma
    // at the last), u = (gamma, 0, .., 0, 1), v = (1, 0, .., 0, 1/gamma).
    let gamma = -4.0;
    let mut diag = vec![4.0; n];
    diag[0] -= gamma;
    diag[n - 1] -= 1.0 / gamma;
    let tridiagonal = |d: &[f64], b: &[f64]| -> Vec<f64> {
        let (mut c, mut x) = (vec![0.0; n], vec![0.0; n]);
        let mut beta = d[0];
        x[0] = b[0] / beta;
        for k in 1..n {
            c[k] = 1.0 / beta;
            beta = d[k] - c[k];
            x[k] = (b[k] - x[k - 1]) / beta;
        }
        for k in (0..n - 1).rev() {
            x[k] -= c[k + 1] * x[k + 1];
        }
        x
    };
    let x = tridiagonal(&diag, r);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = 1.0;
    let z = tridiagonal(&diag, &u);
    let factor = (x[0] + x[n - 1] / gamma) / (1.0 + z[0] + z[n - 1] / gamma);
    x.iter().zip(&z).map(|(x, z)| x - factor * z).collect()
}

/// The wear of a journal and its bearing: each part's depth against the angle in its own
/// body frame, from the body's x axis about the joint's point.
#[derive(Debug, Clone, PartialEq)]
pub struct Worn {
    /// Bearing wear `w_B(theta)` [m] (zero without a table).
    pub bearing: Option<PeriodicSpline>,
    /// Journal wear `w_J(theta)` [m].
    pub journal: Option<PeriodicSpline>,
    /// A lower bound of `w_B + w_J` at any angles [m]: where the deepest point can lie.
    floor: f64,
    /// The angle between the scan's samples [rad]: a quarter of the finer table's step.
    scan_step: f64,
}

/// Iterations of the refinement of one maximum at most: Newton's converge in two or
/// three from the middle of a bracket; bisections halve it each (2^-45 of it).
const REFINE_ITERATIONS: usize = 45;

/// Pieces of the two scan steps about a sample in which [`Worn::refine`] looks for a
/// maximum.
const BRACKETS: usize = 4;

impl Worn {
    /// Checks the wear tables `bearing_wear` and `journal_wear` [m] of joint `who`, whose
    /// journal has radius `r_journal`:
    /// at least [`MIN_POINTS`] finite depths, none negative, and a journal that stays
    /// convex (a wear deeper than the journal is no journal). `None` without tables.
    /// A profile curved more sharply than the clearance (`|w_B''| + |w_J''|` above it,
    /// a pocket narrower than the journal's path) may touch at several points, each a
    /// contact point ([`contact_worn`]).
    pub fn new(
        who: Named,
        (bearing_wear, journal_wear): (Option<&[f64]>, Option<&[f64]>),
        r_journal: f64,
    ) -> Result<Option<Self>, Error> {
        let table = |key: &str, values: Option<&[f64]>| -> Result<Option<PeriodicSpline>, Error> {
            let Some(values) = values else { return Ok(None) };
            if values.len() < MIN_POINTS {
                return Err(who.error(
                    key,
                    format!(
                        "{key} has {} depths: give at least {MIN_POINTS}, equally spaced over the \
                         circumference",
                        values.len()
                    ),
                ));
            }
            if let Some((k, w)) = values.iter().enumerate().find(|(_, w)| !(w.is_finite() && **w >= 0.0)) {
                return Err(who
                    .error(key, format!("{key}[{k}] = {w} m: a wear depth is finite and zero or positive")));
            }
            Ok(Some(PeriodicSpline::new(values)))
        };
        let (bearing, journal) = (table("bearing_wear", bearing_wear)?, table("journal_wear", journal_wear)?);
        if bearing.is_none() && journal.is_none() {
            return Ok(None);
        }
        let floor = |s: &Option<PeriodicSpline>| s.as_ref().map_or(0.0, PeriodicSpline::floor);
        let step = |s: &Option<PeriodicSpline>| s.as_ref().map_or(f64::INFINITY, |s| s.spacing);
        let worn = Worn {
            floor: floor(&bearing) + floor(&journal),
            scan_step: 0.25 * step(&bearing).min(step(&journal)),
            bearing,
            journal,
        };
        let range =
            |s: &Option<PeriodicSpline>| s.as_ref().map_or((0.0, 0.0), PeriodicSpline::curvature_range);
        let (journal_depth, journal_bend) = match &worn.journal {
            Some(s) => (s.values.iter().fold(0.0f64, |a, &w| a.max(w)), range(&worn.journal).1),
            None => (0.0, 0.0),
        };
        // The journal's radius of curvature, h + h'' = R_J - w_J - w_J'', stays positive.
        if journal_depth + journal_bend >= r_journal {
            return Err(who.error(
                "journal_wear",
                format!(
                    "journal_wear reaches {journal_depth} m (curvature {journal_bend} m/rad^2) against \
                     journal_radius = {r_journal} m: the worn journal is no longer convex (check the units)"
                ),
            ));
        }
        Ok(Some(worn))
    }

    /// `(w, w', w'')` of the bearing at its body angle `theta`.
    #[inline]
    fn bearing_at(&self, theta: f64) -> (f64, f64, f64) {
        self.bearing.as_ref().map_or((0.0, 0.0, 0.0), |s| s.eval(theta))
    }

    /// `(w, w', w'')` of the journal at its body angle `theta`.
    #[inline]
    fn journal_at(&self, theta: f64) -> (f64, f64, f64) {
        self.journal.as_ref().map_or((0.0, 0.0, 0.0), |s| s.eval(theta))
    }
}

impl Worn {
    /// Round parts: no wear on either.
    pub fn round() -> Self {
        Worn { bearing: None, journal: None, floor: 0.0, scan_step: f64::INFINITY }
    }

    /// The overlap `delta(alpha) = e . u(alpha) - c - w_B(alpha - phi_B) - w_J(alpha -
    /// phi_J)` of a journal at eccentricity `e` in a bearing of clearance `c`, the
    /// bodies turned by `(phi_B, phi_J)`, and its first two derivatives in `alpha`.
    #[inline]
    pub fn overlap(
        &self,
        e: Vec2,
        (phi_b, phi_j): (f64, f64),
        clearance: f64,
        alpha: f64,
    ) -> (f64, f64, f64) {
        overlap_of(e, alpha, clearance, self.bearing_at(alpha - phi_b), self.journal_at(alpha - phi_j))
    }

    /// The angles about `e`'s direction `beta` where the overlap can reach `at_least` [m]:
    /// `|alpha - beta| <= acos((at_least + c + floor) / |e|)` (pi: anywhere).
    pub fn window(&self, e: Vec2, clearance: f64, at_least: f64) -> f64 {
        let norm = e.norm();
        if norm < 1e-15 {
            return std::f64::consts::PI;
        }
        ((at_least + clearance + self.floor) / norm).clamp(-1.0, 1.0).acos()
    }

    /// The local maxima of the overlap ([`Worn::overlap`]) as `(alpha, delta, share)`,
    /// the largest first, at most [`RIMS`]: a scan, at a quarter of the finer table's
    /// step, of the angles about the eccentricity's direction where the overlap can
    /// exceed its value there, or `floor` [m] if lower ([`Worn::window`]); each local
    /// maximum of the samples refined by Newton's method on `delta' = 0` within a scan
    /// step of it, and so each lowest sample between two (a dip). Refining each,
    /// not the best sample alone, since the samples' own error can exceed the difference
    /// between a worn pocket's rims: Newton from the eccentricity's direction alone would
    /// take the rim on its side, and the penetration would jump when the journal crossed
    /// the pocket's middle.
    ///
    /// Each maximum takes a share of its law's force ([`merging`]): a rim whose contact
    /// is apart from the deepest one's (the overlap between them below zero) takes all
    /// of it; one whose contact merges into the deepest's gives up the merged part,
    /// shared with the deepest by their heights, so that the force stays continuous when
    /// a maximum appears or vanishes and when two maxima trade places as the deepest.
    fn maxima(&self, e: Vec2, phis: (f64, f64), clearance: f64, floor: f64) -> Maxima {
        let beta = if e.norm() > 1e-15 { e.y.atan2(e.x) } else { 0.0 };
        let at = |alpha: f64| self.overlap(e, phis, clearance, alpha).0;
        let h = self.scan_step;
        let samples = (self.window(e, clearance, at(beta).min(floor)) / h).ceil() as i64;
        // In the scan's order: each maximum with the lowest overlap between it and the
        // one before (minus infinity for the first).
        let mut peaks = [(0.0, 0.0, f64::NEG_INFINITY); PEAKS];
        let mut count = 0;
        let mut best = (beta, at(beta));
        let mut dip = (beta, f64::INFINITY);
        let (mut before, mut here) = (f64::NEG_INFINITY, at(beta - samples as f64 * h));
        for k in -samples..=samples {
            let alpha = beta + k as f64 * h;
            let after = if k < samples { at(alpha + h) } else { f64::NEG_INFINITY };
            if here < dip.1 {
                dip = (alpha, here);
            }
            if here >= before && here >= after {
                if here > best.1 {
                    best = (alpha, here);
                }
                if let (Some((a, d)), true) = (self.refine(e, phis, clearance, alpha, 1.0), count < PEAKS) {
                    let same = count > 0 && (a - peaks[count - 1].0).abs() < 0.5 * h;
                    if same {
                        peaks[count - 1] = if d > peaks[count - 1].1 {
                            (a, d, peaks[count - 1].2)
                        } else {
                            peaks[count - 1]
                        };
                    } else {
                        let saddle = if count == 0 {
                            f64::NEG_INFINITY
                        } else {
                            self.refine(e, phis, clearance, dip.0, -1.0).map_or(dip.1, |(_, s)| s)
                        };
                        peaks[count] = (a, d, saddle);
                        count += 1;
                    }
                    dip = (alpha, f64::INFINITY);
                }
            }
            (before, here) = (here, after);
        }
        let mut found = Maxima { refined: count > 0, ..Maxima::default() };
        // Nothing converged (a flat overlap): the best sample.
        if count == 0 {
            found.add((best.0, best.1, 1.0));
            return found;
        }
        let peaks = &peaks[..count];
        let deepest = (0..count).fold(0, |m, k| if peaks[k].1 > peaks[m].1 { k } else { m });
        let top = peaks[deepest].1;
        let mut top_share = 1.0;
        for (k, &(alpha, delta, _)) in peaks.iter().enumerate() {
            if k == deepest {
                continue;
            }
            // The pass between k and the deepest, the lowest of the dips on the way (those
            // of the peaks after the first of the two): above it their contacts are one.
            let between = if k < deepest { &peaks[k + 1..=deepest] } else { &peaks[deepest + 1..=k] };
            let saddle = between.iter().fold(f64::INFINITY, |m, p| m.min(p.2)).max(0.0);
            let (merged, lower) = merging(delta, saddle, top);
            found.add((alpha, delta, 1.0 - merged * lower));
            top_share -= merged * (1.0 - lower);
        }
        found.add((peaks[deepest].0, top, f64::max(top_share, 0.0)));
        found
    }

    /// The maximum (`sign` 1) or minimum (-1) of the overlap within a scan step of the
    /// sample `start` that stands at least as high (low) as its two neighbours: its
    /// angle and overlap. The step on either side is cut in [`BRACKETS`] pieces; in each
    /// whose ends' slopes bracket a maximum, Newton's method on `delta' = 0` kept inside
    /// the bracket, bisecting where a Newton step would leave it or the overlap curves
    /// the wrong way (Press et al., Numerical Recipes, `rtsafe`); the highest of those.
    /// Every piece, so that two extrema within one step are told apart and the same one
    /// is found whichever side the sample lies. `None` where no piece brackets one.
    fn refine(&self, e: Vec2, phis: (f64, f64), clearance: f64, start: f64, sign: f64) -> Option<(f64, f64)> {
        let h = self.scan_step.min(0.5);
        let piece = 2.0 * h / BRACKETS as f64;
        let slope = |alpha: f64| {
            let (_, d1, d2) = self.overlap(e, phis, clearance, alpha);
            (sign * d1, sign * d2)
        };
        let mut best: Option<(f64, f64)> = None;
        let mut left = slope(start - h).0;
        for b in 0..BRACKETS {
            let (mut lo, mut hi) = (start - h + b as f64 * piece, start - h + (b + 1) as f64 * piece);
            let right = slope(hi).0;
            if !(left >= 0.0 && right <= 0.0) || (left == 0.0 && b > 0) {
                left = right;
                continue;
            }
            left = right;
            let mut alpha = 0.5 * (lo + hi);
            for _ in 0..REFINE_ITERATIONS {
                let (d1, d2) = slope(alpha);
                if d1 == 0.0 {
                    break;
                }
                let newton = alpha - d1 / d2;
                if d2 < 0.0 && (d1 / d2).abs() < 1e-14 {
                    alpha = newton;
                    break;
                }
                if d1 > 0.0 {
                    lo = alpha;
                } else {
                    hi = alpha;
                }
                alpha = if d2 < 0.0 && newton >= lo && newton <= hi { newton } else { 0.5 * (lo + hi) };
                if hi - lo < 1e-13 {
                    break;
                }
            }
            let value = sign * self.overlap(e, phis, clearance, alpha).0;
            if best.is_none_or(|(_, v)| value > v) {
                best = Some((alpha, value));
            }
        }
        best.map(|(alpha, value)| (alpha, sign * value))
    }
}

/// [`Worn::overlap`] in any number type, `(w_B, w_B', w_B'')` and `(w_J, w_J', w_J'')`
/// the parts' wear at `alpha`.
#[inline]
fn overlap_of<T: Real>(e: Vec2<T>, alpha: T, clearance: f64, wb: (T, T, T), wj: (T, T, T)) -> (T, T, T) {
    let (sin, cos) = alpha.sin_cos();
    let u = Vec2::new(cos, sin);
    let ((wb, db, ddb), (wj, dj, ddj)) = (wb, wj);
    (e.dot(&u) - clearance - wb - wj, e.dot(&perp(u)) - db - dj, -e.dot(&u) - ddb - ddj)
}

/// The most local maxima of the overlap a worn joint takes as contact points: its rims.
pub const RIMS: usize = 4;

/// The largest local maxima of an overlap, `(alpha, delta)`, in decreasing `delta`.
/// How a maximum of overlap `delta` merges with the deepest, of overlap `top`, across
/// the pass `saddle` >= 0 between them (the lowest overlap on the way): `(merged, lower)`. `merged = saddle /
/// delta` is the part of its contact that lies in one region with the deepest's (0 for
/// contacts apart, 1 where the maximum meets the saddle and vanishes); of that part the
/// maximum gives up the fraction `lower` and the deepest the rest, `lower` rising from
/// 1/2 for equal maxima to 1 once the deepest stands higher by the maximum's own height
/// above the saddle. The maximum's share of its force is `1 - merged lower`, the
/// deepest's `1 - merged (1 - lower)`: for two equal maxima each takes `1 - merged / 2`,
/// whichever is called the deepest, and a maximum that vanishes into the saddle takes
/// nothing while the deepest takes all its own.
fn merging(delta: f64, saddle: f64, top: f64) -> (f64, f64) {
    if delta <= 0.0 {
        return (0.0, 1.0);
    }
    let merged = (saddle / delta).clamp(0.0, 1.0);
    let height = delta - saddle;
    let lower = if height > 0.0 { (0.5 + 0.5 * (top - delta) / height).clamp(0.5, 1.0) } else { 0.5 };
    (merged, lower)
}

/// The most local maxima of one scan that are followed (a profile that rings more
/// often within the window is not a worn part).
const PEAKS: usize = 16;

/// The largest local maxima of an overlap, `(alpha, delta, share)`, in decreasing
/// `delta`.
#[derive(Default)]
struct Maxima {
    found: [(f64, f64, f64); RIMS],
    /// Whether they are maxima refined to `delta' = 0` (not a flat overlap's best
    /// sample).
    refined: bool,
    count: usize,
}

impl Maxima {
    /// Adds a maximum unless it is smaller than the [`RIMS`] largest.
    fn add(&mut self, maximum: (f64, f64, f64)) {
        let at = self.found[..self.count].iter().position(|m| maximum.1 > m.1).unwrap_or(self.count);
        if at == RIMS {
            return;
        }
        self.count = (self.count + 1).min(RIMS);
        self.found.copy_within(at..self.count - 1, at + 1);
        self.found[at] = maximum;
    }

    fn iter(&self) -> impl Iterator<Item = &(f64, f64, f64)> {
        self.found[..self.count].iter()
    }
}

/// One rim of a worn joint's section where the parts touch or come nearest: a local
/// maximum of the overlap ([`Worn::rims_from`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rim<T: Real = f64> {
    /// The normal `u(alpha)` in the section's axes, pointing from the bearing's centre
    /// outwards.
    pub normal: Vec2<T>,
    /// The overlap `delta(alpha)` [m]: the penetration.
    pub penetration: T,
    /// The part of the joint's law it carries ([`merging`]).
    pub share: T,
    /// The bearing's wear and its slope at the normal, `(w_B, w_B')`.
    pub bearing: (T, T),
    /// The journal's, `(w_J, w_J')`.
    pub journal: (T, T),
}

impl<T: Real> Rim<T> {
    /// The material points `(bearing, journal)` of a bearing of radius `r_bearing`
    /// centred at `centre_b` and a journal of radius `r_journal` at `centre_j`, both in
    /// the section's axes: `c + h u + h' u_perp` of each part's support function `h`.
    /// Their difference is `delta u`, since `delta' = 0` at the rim.
    #[inline]
    pub fn points(
        &self,
        (centre_b, r_bearing): (Vec2<T>, f64),
        (centre_j, r_journal): (Vec2<T>, f64),
    ) -> (Vec2<T>, Vec2<T>) {
        let t = perp(self.normal);
        (
            centre_b + self.normal * (T::constant(r_bearing) + self.bearing.0) + t * self.bearing.1,
            centre_j + self.normal * (T::constant(r_journal) - self.journal.0) - t * self.journal.1,
        )
    }
}

/// The rims a section can have at once.
pub type Rims<T = f64> = SmallVec<[Rim<T>; RIMS]>;

/// Where the search over the profiles ([`Worn::search`]) found a rim: the numbers that
/// [`Worn::rims_from`] starts from, in any number type, so that a compiled evaluation
/// reads them as inputs while the search runs interpreted (its scan and its iterations
/// branch at every sample).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start<T> {
    /// 0: no rim; 1: the best sample of a flat overlap; 2: a maximum refined to
    /// `delta' = 0`.
    pub kind: T,
    /// Its angle `alpha` [rad].
    pub alpha: T,
    /// The part of the joint's law it carries ([`merging`]).
    pub share: T,
    /// The bearing's piece at `alpha - phi_B` (zeros without a table).
    pub bearing: Piece<T>,
    /// The journal's piece at `alpha - phi_J`.
    pub journal: Piece<T>,
}

/// What the search found: a start for each rim, the first the deepest.
pub type Found<T = f64> = [Start<T>; RIMS];

/// The numbers that give a [`Found`].
pub const FOUND: usize = RIMS * (3 + 2 * Piece::<f64>::NUMBERS);

impl<T: Real> Start<T> {
    /// No rim.
    fn none() -> Self {
        let zero = T::constant(0.0);
        Start { kind: zero, alpha: zero, share: zero, bearing: Piece::zero(), journal: Piece::zero() }
    }
}

/// Appends the [`FOUND`] numbers of `found` to `x`.
pub fn write_found(found: &Found, x: &mut Vec<f64>) {
    for s in found {
        x.extend([s.kind, s.alpha, s.share]);
        x.extend(s.bearing.numbers());
        x.extend(s.journal.numbers());
    }
}

/// The [`Found`] whose numbers are `x` ([`write_found`]).
pub fn read_found<T: Real>(x: &[T]) -> Found<T> {
    let n = Piece::<T>::NUMBERS;
    std::array::from_fn(|k| {
        let x = &x[k * (3 + 2 * n)..];
        Start {
            kind: x[0],
            alpha: x[1],
            share: x[2],
            bearing: Piece::read(&x[3..]),
            journal: Piece::read(&x[3 + n..]),
        }
    })
}

impl Worn {
    /// Where the rims lie of a worn journal at eccentricity `e` in its worn bearing of
    /// clearance `c`, the bodies turned by `phis`, whose overlap is above `-reach` [m]
    /// ([`Worn::rims_from`] takes them from there): the first the deepest, the normal
    /// angle `alpha` where the overlap `delta(alpha) = e . u + R_J - w_J(alpha - phi_J) -
    /// R_B - w_B(alpha - phi_B)` is largest; for a finite reach the other local maxima
    /// follow, the rims of a worn pocket on which the journal rests at once
    /// ([`Worn::maxima`]).
    pub fn search(&self, e: Vec2, phis: (f64, f64), clearance: f64, reach: f64) -> Found {
        let mut found = [Start::none(); RIMS];
        // No angle overlaps by more than |e| - c - (w_B + w_J)'s floor.
        if e.norm() - clearance - self.floor <= -reach {
            return found;
        }
        // The rims beyond the deepest only for the forces (a finite reach): the contact
        // state, its events and channels follow the deepest point.
        let rims = if reach.is_finite() { RIMS } else { 1 };
        let floor = if reach.is_finite() { -reach } else { f64::INFINITY };
        let maxima = self.maxima(e, phis, clearance, floor);
        let kind = if maxima.refined { 2.0 } else { 1.0 };
        let piece = |s: &Option<PeriodicSpline>, theta: f64| match s {
            Some(s) => s.piece(theta),
            None => Piece::zero(),
        };
        for (slot, &(alpha, _, share)) in found.iter_mut().zip(maxima.iter().take(rims)) {
            let (bearing, journal) =
                (piece(&self.bearing, alpha - phis.0), piece(&self.journal, alpha - phis.1));
            *slot = Start { kind, alpha, share, bearing, journal };
        }
        found
    }

    /// The rims in any number type from where the search found them (`found`,
    /// [`Worn::search`]):
    /// each refined maximum takes one more Newton step on `delta' = 0` in `T`, so that
    /// its angle moves with the state as the implicit function theorem says, and the
    /// compiled Jacobians are exact through it. Each rim's share is the search's.
    pub fn rims_from<T: Real>(
        &self,
        e: Vec2<T>,
        (phi_b, phi_j): (T, T),
        clearance: f64,
        reach: f64,
        found: &Found<T>,
    ) -> Rims<T> {
        let wear = |s: &Option<PeriodicSpline>, piece: &Piece<T>, theta: T| match s {
            Some(s) => piece.at(s.spacing, theta),
            None => (T::constant(0.0), T::constant(0.0), T::constant(0.0)),
        };
        let mut out = Rims::new();
        for s in found {
            if s.kind < 0.5 {
                break;
            }
            let at = |alpha: T| {
                (
                    wear(&self.bearing, &s.bearing, alpha - phi_b),
                    wear(&self.journal, &s.journal, alpha - phi_j),
                )
            };
            let mut alpha = s.alpha;
            if s.kind > 1.5 {
                let (wb, wj) = at(alpha);
                let (_, d1, d2) = overlap_of(e, alpha, clearance, wb, wj);
                if d2 < 0.0 {
                    alpha -= d1 / d2;
                }
            }
            let (sin, cos) = alpha.sin_cos();
            let normal = Vec2::new(cos, sin);
            let ((wb, db, _), (wj, dj, _)) = at(alpha);
            let penetration = e.dot(&normal) - clearance - wb - wj;
            if penetration <= -reach {
                break;
            }
            out.push(Rim { normal, penetration, share: s.share, bearing: (wb, db), journal: (wj, dj) });
        }
        out
    }
}

/// The contact points of a worn journal in its worn bearing, pushed onto `out` unless
/// the gap is `reach` [m] or more: its rims ([`Worn::rims_from`]) in the global plane.
pub fn contact_worn(
    g: &JournalBearing,
    worn: &Worn,
    bearing: &BodyState,
    journal: &BodyState,
    reach: f64,
    out: &mut ContactPoints,
) {
    let found = search_worn(g, worn, bearing, journal, reach);
    contact_worn_from(g, worn, &found, bearing, journal, reach, out);
}

/// Where the search over the profiles finds the rims of a worn journal in its worn
/// bearing at the bodies' states ([`Worn::search`]).
pub fn search_worn(
    g: &JournalBearing,
    worn: &Worn,
    bearing: &BodyState,
    journal: &BodyState,
    reach: f64,
) -> Found {
    let (centre_b, centre_j) = g.centres(bearing, journal);
    worn.search(centre_j - centre_b, (bearing.phi(), journal.phi()), g.clearance, reach)
}

/// [`contact_worn`] in any number type from where the search found the rims (`found`),
/// all sharing the joint's one contact state (index 0). Each has the penetration
/// `delta(alpha)`, the material points of each part ([`Rim::points`]), and the relative
/// velocity of the journal's point to the bearing's along `n` and the tangent. Since
/// `delta' = 0` there, the penetration's time derivative is its partial one at fixed
/// `alpha`, which is the relative velocity of the two material points along `n`.
pub fn contact_worn_from<T: Real>(
    g: &JournalBearing,
    worn: &Worn,
    found: &Found<T>,
    bearing: &BodyState<T>,
    journal: &BodyState<T>,
    reach: f64,
    out: &mut ContactPoints<T>,
) {
    let (centre_b, centre_j) = g.centres(bearing, journal);
    let phis = (bearing.phi(), journal.phi());
    for rim in worn.rims_from(centre_j - centre_b, phis, g.clearance, reach, found) {
        let (point_bearing, point_journal) = rim.points((centre_b, g.r_bearing), (centre_j, g.r_journal));
        let v = journal.velocity_at(point_journal) - bearing.velocity_at(point_bearing);
        out.push(ContactPoint::in_bearing(
            rim.normal,
            rim.penetration,
            v,
            rim.share,
            (
                MaterialPoint { body: g.bearing, at: point_bearing },
                MaterialPoint { body: g.journal, at: point_journal },
            ),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::super::journal_bearing::tests::{joint, journal_at};
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// Depths `f(theta)` at `n` equally spaced angles.
    fn table(n: usize, f: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..n).map(|k| f(TAU * k as f64 / n as f64)).collect()
    }

    fn point(g: &JournalBearing, w: &Worn, b: &BodyState, j: &BodyState) -> ContactPoint {
        let mut out = ContactPoints::new();
        contact_worn(g, w, b, j, f64::INFINITY, &mut out);
        out[0]
    }

    fn worn(bearing: Option<Vec<f64>>, journal: Option<Vec<f64>>) -> Worn {
        Worn::new(Named::joint("c"), (bearing.as_deref(), journal.as_deref()), 0.0095)
            .expect("valid tables")
            .expect("some table")
    }

    /// The shortcut of the angle's remainder gives `rem_euclid`'s bits, at the turn's
    /// ends and zeros of either sign too.
    #[test]
    fn within_turn_is_rem_euclid() {
        let mut angles =
            vec![0.0, -0.0, TAU, -TAU, PI, -PI, 1e-300, -1e-300, 3.0 * TAU + 0.1, -7.5, f64::NAN];
        angles.extend([TAU, -TAU].iter().flat_map(|&a: &f64| [a.next_up(), a.next_down()]));
        angles.extend((0..2000).map(|k| -20.0 + 0.02 * k as f64 + 1e-9));
        for a in angles {
            assert_eq!(within_turn(a).to_bits(), a.rem_euclid(TAU).to_bits(), "{a}");
        }
    }

    /// The spline of `a cos 2 theta + a` from 64 points against the function, its slope
    /// and its curvature, between the table points too: within the cubic spline's error
    /// bounds (`5/384 h^4 |f''''|` for the value, de Boor chapter IV), and exact at
    /// the table points.
    #[test]
    fn spline_follows_a_smooth_function() {
        let a = 1e-5;
        let s = PeriodicSpline::new(&table(64, |t| a * (2.0 * t).cos() + a));
        let h = TAU / 64.0;
        for k in 0..640 {
            let t = -PI + TAU * k as f64 / 640.0 + 1e-3;
            let (v, d, dd) = s.eval(t);
            assert!((v - (a * (2.0 * t).cos() + a)).abs() < 5.0 / 384.0 * h.powi(4) * 16.0 * a * 1.01, "{t}");
            assert!((d + 2.0 * a * (2.0 * t).sin()).abs() < h.powi(3) * 16.0 * a, "{t}: {d}");
            assert!((dd + 4.0 * a * (2.0 * t).cos()).abs() < h.powi(2) * 16.0 * a, "{t}: {dd}");
        }
        for k in 0..64 {
            let t = TAU * k as f64 / 64.0;
            assert!((s.eval(t).0 - (a * (2.0 * t).cos() + a)).abs() < 1e-19);
        }
        // A constant is kept exactly (to rounding), slope and curvature zero.
        let c = PeriodicSpline::new(&[3e-6; 12]);
        for t in [0.0, 0.3, 2.0, 6.2] {
            let (v, d, dd) = c.eval(t);
            assert!((v - 3e-6).abs() < 1e-21 && d.abs() < 1e-18 && dd.abs() < 1e-15, "{v} {d} {dd}");
        }
    }

    /// An oval bearing `w_B = a cos 2 theta + a` on a turned bearing body: at an
    /// eccentricity along the oval's axes the normal is the eccentricity's direction and
    /// the penetration `|e| - c - w_B` in closed form (2a along the bearing's x axis, 0
    /// along its y axis); elsewhere the penetration and normal are the maximum of the
    /// closed-form overlap `|e| cos(alpha - beta) + R_J - R_B - w_B(alpha - phi_B)`,
    /// found by a fine search and golden sections. The material points lie on the
    /// normal at the penetration's distance, and each on its own surface's tangent line.
    #[test]
    fn oval_bearing_against_closed_form() {
        let g = joint();
        let a = 2e-5;
        let w = worn(Some(table(72, |t| a * (2.0 * t).cos() + a)), None);
        let phi_b = 0.3;
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), phi_b, Vec2::zeros(), 0.0);
        let exact = |alpha: f64| a * (2.0 * (alpha - phi_b)).cos() + a;
        let spline_error = 5.0 / 384.0 * (TAU / 72.0f64).powi(4) * 16.0 * a;
        for (ecc, beta, closed) in [
            (0.00055, phi_b, Some(0.00055 - g.clearance - 2.0 * a)),
            (0.00051, phi_b + PI / 2.0, Some(0.00051 - g.clearance)),
            (0.00054, phi_b + PI, Some(0.00054 - g.clearance - 2.0 * a)),
            (0.00056, 1.0, None),
            (0.00052, -2.2, None),
            (0.00060, 2.9, None),
        ] {
            let e = Vec2::new(beta.cos(), beta.sin()) * ecc;
            let journal = journal_at(&g, &bearing, e, 1.1, Vec2::zeros(), 0.0);
            let p = point(&g, &w, &bearing, &journal);
            let overlap = |alpha: f64| ecc * (alpha - beta).cos() + g.r_journal - g.r_bearing - exact(alpha);
            // The maximum of the overlap: the best of 20 000 angles, then golden sections.
            let mut best = (0..20_000).map(|k| beta - 1.0 + 2.0 * k as f64 / 20_000.0).fold(beta, |b, x| {
                if overlap(x) > overlap(b) {
                    x
                } else {
                    b
                }
            });
            let (mut lo, mut hi) = (best - 2e-4, best + 2e-4);
            for _ in 0..100 {
                let (x1, x2) = (hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo));
                if overlap(x1) > overlap(x2) {
                    hi = x2;
                } else {
                    lo = x1;
                }
            }
            best = 0.5 * (lo + hi);
            let depth = closed.unwrap_or(overlap(best));
            assert!(
                (p.penetration - depth).abs() < 2.0 * spline_error,
                "{beta}: {} vs {depth}",
                p.penetration
            );
            let n = Vec2::new(best.cos(), best.sin());
            assert!((p.normal - n).norm() < 1e-6, "{beta}: normal {:?} vs {n:?}", p.normal);
            if closed.is_some() {
                assert!((p.normal - e / ecc).norm() < 1e-9, "{beta}: normal {:?}", p.normal);
            }
            assert!(((p.on_j.at - p.on_i.at).dot(&p.normal) - p.penetration).abs() < 1e-15);
            // Each material point on its tangent line: h(alpha) from its centre along n.
            let (centre_b, centre_j) = g.centres(&bearing, &journal);
            let alpha = p.normal.y.atan2(p.normal.x);
            let h_b = g.r_bearing + w.bearing.as_ref().unwrap().eval(alpha - phi_b).0;
            assert!(((p.on_i.at - centre_b).dot(&p.normal) - h_b).abs() < 1e-15);
            assert!(((p.on_j.at - centre_j).dot(&p.normal) - g.r_journal).abs() < 1e-15);
        }
    }

    /// The penetration rate is the time derivative of the penetration, by central
    /// differences of placements along the bodies' velocities, both parts worn and both
    /// bodies moving and turning; and the contact's slip is the material points' relative
    /// velocity along the tangent.
    #[test]
    fn rate_is_the_derivative_of_the_penetration() {
        let g = joint();
        let w = worn(
            Some(table(36, |t| 1e-5 * (1.0 + (2.0 * t).cos()) + 4e-6 * (1.0 + (3.0 * t + 0.4).sin()))),
            Some(table(48, |t| 8e-6 * (1.0 + (t - 0.5).cos()))),
        );
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::new(0.2, 0.1), 4.0);
        for (e, omega) in [(Vec2::new(0.0004, 0.0003), 12.0), (Vec2::new(-0.0005, 0.0001), -30.0)] {
            let journal = journal_at(&g, &bearing, e, 1.1, Vec2::new(-0.5, 0.9), omega);
            let moved =
                |b: &BodyState, dt: f64| BodyState::new(b.r + b.v * dt, b.phi() + b.omega * dt, b.v, b.omega);
            let h = 1e-7;
            let depth = |dt: f64| point(&g, &w, &moved(&bearing, dt), &moved(&journal, dt)).penetration;
            let fd = (depth(h) - depth(-h)) / (2.0 * h);
            let rate = point(&g, &w, &bearing, &journal).penetration_rate;
            assert!((rate - fd).abs() < 1e-6 * rate.abs().max(1e-3), "{rate} vs {fd}");
        }
    }

    /// A constant wear on both parts is a round joint of larger clearance: the same
    /// point as [`super::super::contact_journal_bearing`]'s with `R_B + w_B`, `R_J - w_J`.
    #[test]
    fn constant_wear_is_a_larger_round_clearance() {
        let g = joint();
        let (wb, wj) = (3e-5, 1e-5);
        let w = worn(Some(vec![wb; 16]), Some(vec![wj; 8]));
        let round = JournalBearing {
            r_bearing: g.r_bearing + wb,
            r_journal: g.r_journal - wj,
            clearance: g.clearance + wb + wj,
            ..g.clone()
        };
        let bearing = BodyState::new(Vec2::new(0.1, 0.2), 0.3, Vec2::new(0.2, 0.1), 4.0);
        for (e, omega) in [(Vec2::new(0.0004, 0.0004), 12.0), (Vec2::new(-0.0005, 0.0001), -30.0)] {
            let journal = journal_at(&g, &bearing, e, 1.1, Vec2::new(-0.5, 0.9), omega);
            let p = point(&g, &w, &bearing, &journal);
            let mut out = ContactPoints::new();
            super::super::contact_journal_bearing(&round, &bearing, &journal, f64::INFINITY, &mut out);
            let q = out[0];
            // To a few ulps of the radii (1.7e-18 m at 10 mm).
            assert!((p.penetration - q.penetration).abs() < 1e-17, "{} vs {}", p.penetration, q.penetration);
            assert!((p.normal - q.normal).norm() < 1e-14, "{:?} {:?}", p.normal, q.normal);
            assert!((p.penetration_rate - q.penetration_rate).abs() < 1e-13);
            assert!((p.slip - q.slip).norm() < 1e-13);
            assert!((p.on_i.at - q.on_i.at).norm() < 1e-17 && (p.on_j.at - q.on_j.at).norm() < 1e-17);
        }
    }

    /// A journal swept across a pocket narrower than itself (20 um deep over 8 degrees,
    /// uneven: one rim 2 um lower): at every direction the penetration is the largest
    /// overlap of a fine search, also where the deepest point passes from one rim to the
    /// other, so that it never jumps.
    #[test]
    fn penetration_is_the_global_largest_overlap_across_a_pocket() {
        let g = joint();
        let pocket = |t: f64| {
            let d = (t - PI / 2.0) / (4.0 * PI / 180.0);
            if d.abs() < 1.0 {
                2e-5 * (1.0 - d * d) + if d > 0.0 { 2e-6 * d } else { 0.0 }
            } else {
                0.0
            }
        };
        let w = worn(Some(table(360, pocket)), None);
        let bearing = BodyState::new(Vec2::zeros(), 0.0, Vec2::zeros(), 0.0);
        let spline = w.bearing.as_ref().unwrap();
        let mut last = f64::NAN;
        for k in 0..=200 {
            let beta = PI / 2.0 + (k as f64 - 100.0) * 1e-4 * 8.0;
            let ecc = 0.000503;
            let e = Vec2::new(beta.cos(), beta.sin()) * ecc;
            let journal = journal_at(&g, &bearing, e, 0.0, Vec2::zeros(), 0.0);
            let p = point(&g, &w, &bearing, &journal);
            let overlap = |alpha: f64| ecc * (alpha - beta).cos() - g.clearance - spline.eval(alpha).0;
            let best = (0..40_000)
                .map(|i| beta - 0.3 + 0.6 * i as f64 / 40_000.0)
                .map(overlap)
                .fold(f64::MIN, f64::max);
            assert!(
                p.penetration >= best - 1e-13 && p.penetration < best + 1e-10,
                "{beta}: {} vs {best}",
                p.penetration
            );
            // Turning e by d_beta changes any direction's overlap by |e| sin(alpha - beta)
            // d_beta, below 4e-8 m within 0.1 rad; the rims' heights differ by 2 um.
            if k > 0 {
                assert!(
                    (p.penetration - last).abs() < 4e-8,
                    "{beta}: jumps from {last} to {}",
                    p.penetration
                );
            }
            last = p.penetration;
        }
    }

    /// A journal pressed into a pocket narrower than itself (20 um deep over 8 degrees)
    /// rests on both rims: two contact points, mirror images about the pocket's axis,
    /// each taking its whole force (the pocket's bottom is apart). Swept across the
    /// pocket and across a shallow double top, the resultant of `share delta^1.5 n` over
    /// the points never jumps, where the deepest point alone would leap from rim to rim.
    #[test]
    fn a_journal_rests_on_both_rims_of_a_narrow_pocket() {
        let g = joint();
        let pocket = |centre: f64, depth: f64, half: f64| {
            move |t: f64| {
                let d = (t - centre) / half;
                if d.abs() < 1.0 {
                    depth * (1.0 - d * d)
                } else {
                    0.0
                }
            }
        };
        let bearing = BodyState::new(Vec2::zeros(), 0.0, Vec2::zeros(), 0.0);
        let narrow = worn(Some(table(360, pocket(PI / 2.0, 2e-5, 4.0 * PI / 180.0))), None);
        let points = |w: &Worn, beta: f64, ecc: f64| {
            let e = Vec2::new(beta.cos(), beta.sin()) * ecc;
            let journal = journal_at(&g, &bearing, e, 0.0, Vec2::zeros(), 0.0);
            let mut out = ContactPoints::new();
            contact_worn(&g, w, &bearing, &journal, 0.0, &mut out);
            out
        };
        let p = points(&narrow, PI / 2.0, 0.000503);
        assert_eq!(p.len(), 2);
        assert!((p[0].penetration - p[1].penetration).abs() < 1e-12);
        assert!((p[0].share, p[1].share) == (1.0, 1.0));
        let sum = p[0].normal + p[1].normal;
        assert!(sum.x.abs() < 1e-9 && sum.y > 1.9, "{sum:?}");
        assert!(p.iter().all(|q| (q.normal.y.atan2(q.normal.x) - PI / 2.0).abs() > 2.0 * PI / 180.0));
        // A double top: two shallow bumps 1 nm apart in height, on a wide worn pocket.
        let double = worn(
            Some(table(360, |t| pocket(PI / 2.0, 1e-5, 0.5)(t) - pocket(PI / 2.0, 2e-8, 0.03)(t))),
            None,
        );
        for (w, ecc) in [(&narrow, 0.000503), (&double, 0.000512)] {
            let resultant = |beta: f64| {
                points(w, beta, ecc)
                    .iter()
                    .map(|q| q.normal * q.share * q.penetration.max(0.0).powf(1.5))
                    .fold(Vec2::zeros(), |a, b| a + b)
            };
            let (dbeta, mut last) = (2e-5, resultant(PI / 2.0 - 0.02));
            let scale = last.norm();
            for k in 1..=2000 {
                let now = resultant(PI / 2.0 - 0.02 + k as f64 * dbeta);
                assert!((now - last).norm() < 0.01 * scale, "step {k}: {last:?} -> {now:?}");
                last = now;
            }
        }
    }

    /// Bad tables are errors naming the key: too few points, a negative or NaN depth, a
    /// journal worn through.
    #[test]
    fn bad_tables_name_the_key() {
        let check = |b: Option<Vec<f64>>, j: Option<Vec<f64>>, key: &str, says: &str| {
            let e =
                Worn::new(Named::joint("pin"), (b.as_deref(), j.as_deref()), 0.0095).unwrap_err().to_string();
            assert!(e.contains("pin") && e.contains(key) && e.contains(says), "{e}");
        };
        check(Some(vec![0.0; 7]), None, "bearing_wear", "at least 8");
        check(
            None,
            Some(vec![0.0, 1e-6, -1e-6, 0.0, 0.0, 0.0, 0.0, 0.0]),
            "journal_wear[2]",
            "zero or positive",
        );
        check(Some(vec![f64::NAN; 8]), None, "bearing_wear[0]", "finite");
        check(None, Some(vec![0.01; 8]), "journal_wear", "convex");
        assert!(Worn::new(Named::joint("pin"), (None, None), 0.0095).unwrap().is_none());
    }
}
