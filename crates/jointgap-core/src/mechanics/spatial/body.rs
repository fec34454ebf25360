//! A spatial rigid body: positions `q = (x, y, z, e0, e1, e2, e3)` (centre of mass and
//! the unit quaternion of its orientation, scalar first), velocities
//! `v = (vx, vy, vz, wx', wy', wz')` (velocity of the centre of mass in global axes and
//! angular velocity in the body's principal frame). The body frame is the principal
//! frame at the centre of mass, so the mass matrix is diagonal `(m, m, m, J1, J2, J3)`
//! and the equations keep the planar engine's diagonal Schur solve; the gyroscopic
//! moment `-w' x (J w')` is an applied load.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3, Vector4};

use crate::mechanics::layout::{self, BodyShape};
use crate::scalar::{norm, Real};

/// A 3-vector [m, m/s, N, rad/s, ...].
pub type Vec3 = Vector3<f64>;

/// A 3x3 matrix (a rotation, an inertia tensor).
pub type Mat3 = Matrix3<f64>;

/// An orientation: the rotation from a body's frame to global axes.
pub type Orientation = UnitQuaternion<f64>;

/// Position coordinates of a spatial body.
pub const NQ: usize = 7;

/// Velocity coordinates of a spatial body (and generalized forces, accelerations).
pub const NV: usize = 6;

/// The spatial body kind's sizes.
pub const SPATIAL_BODY: BodyShape = BodyShape { nq: NQ, nv: NV };

/// A constraint row's Jacobian block over one spatial body's velocities
/// `dC/d(v, w')`.
pub type BodyRow = [f64; NV];

/// One spatial body's positions `(x, y, z, e0, e1, e2, e3)`.
pub type BodyPositions = [f64; NQ];

/// A spatial body's channels: its positions, velocities (angular velocity in the body
/// frame) and accelerations (angular acceleration in the body frame), in the order of
/// its coordinates.
pub const CHANNELS: [&str; NQ + 2 * NV] = [
    "x", "y", "z", "e0", "e1", "e2", "e3", "vx", "vy", "vz", "wx", "wy", "wz", "ax", "ay", "az", "alphax",
    "alphay", "alphaz",
];

/// How far, in ulps, the rounding of a body's quaternion may turn it: rounding each
/// entry of a unit quaternion to nearest moves it by at most half an ulp of its length,
/// a turn of at most one ulp (a turn by `theta` moves it by `theta / 2`); normalising
/// it on reading ([`BodyState::read`]) rounds once more.
const QUATERNION_ROUNDING: f64 = 2.0;

/// One spatial body's block of a vector over all velocity coordinates (`v`, `qe`,
/// `qdd`), from its address `at`.
#[inline]
pub fn block(x: &[f64], at: usize) -> &BodyRow {
    layout::block(x, at)
}

/// [`block`], to write.
#[inline]
pub fn block_mut(x: &mut [f64], at: usize) -> &mut BodyRow {
    layout::block_mut(x, at)
}

/// One spatial body's positions in `q`, from its address `at`: they are 7, one more
/// than its velocities.
#[inline]
pub fn position_block(q: &[f64], at: usize) -> &BodyPositions {
    layout::block(q, at)
}

/// [`position_block`], to write.
#[inline]
pub fn position_block_mut(q: &mut [f64], at: usize) -> &mut BodyPositions {
    layout::block_mut(q, at)
}

/// A spatial body's mass matrix, diagonal because the body frame is its principal
/// frame: `(m, m, m, J1, J2, J3)`, `moments` the principal moments [kg m^2].
#[inline]
pub fn mass_diagonal(mass: f64, moments: Vec3) -> BodyRow {
    [mass, mass, mass, moments.x, moments.y, moments.z]
}

/// The inverse of [`mass_diagonal`], entry by entry.
#[inline]
pub fn inverse_mass(mass: f64, moments: Vec3) -> BodyRow {
    mass_diagonal(mass, moments).map(|m| 1.0 / m)
}

/// Kinetic energy [J] of a spatial body with velocities `v = (v, w')`:
/// `m |v|^2 / 2 + w' . J w' / 2` (the rotational part in the principal frame, where
/// `J` is diagonal).
#[inline]
pub fn kinetic_energy(mass: f64, moments: Vec3, v: &[f64]) -> f64 {
    let (vc, w) = (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]));
    0.5 * mass * vc.norm_squared() + 0.5 * w.dot(&moments.component_mul(&w))
}

/// Work [J] gravity `g` [m/s^2] has done on a spatial body of mass `mass` at positions
/// `q` since it was at the origin: `m g . r`, the negative of its potential energy.
#[inline]
pub fn gravity_work(mass: f64, gravity: Vec3, q: &[f64]) -> f64 {
    mass * gravity.dot(&Vec3::new(q[0], q[1], q[2]))
}

/// Adds the weight `m g` of a body of mass `mass` [kg] to its generalized forces (at
/// its centre of mass: no moment).
#[inline]
pub fn add_weight<T: Real>(qe: &mut [T], mass: f64, gravity: Vec3) {
    add_to(qe, 0, &constant(&(gravity * mass)));
}

/// Adds force `f` [N] (global axes), whose arm from the centre of mass is `arm` (global
/// axes), to a spatial body's generalized forces `qe = (F, M')`: the force itself, and
/// its moment `arm x f` turned into the body frame, `A^T (arm x f)`, since the body's
/// rotational coordinates are its body-frame rotations (its virtual work
/// `f . (dr + A (dpi' x s))` with `arm = A s`).
#[inline]
pub fn add_force<T: Real>(qe: &mut [T], state: &BodyState<T>, arm: &Vector3<T>, f: &Vector3<T>) {
    add_to(qe, 0, f);
    add_to(qe, 3, &state.a.tr_mul(&arm.cross(f)));
}

/// Adds torque `tau` [N m] (global axes) to a spatial body's generalized forces, turned
/// into the body frame: `A^T tau`.
#[inline]
pub fn add_torque<T: Real>(qe: &mut [T], state: &BodyState<T>, tau: &Vector3<T>) {
    add_to(qe, 3, &state.a.tr_mul(tau));
}

/// Adds the gyroscopic moment `-w' x (J w')` of a body turning at `omega` (body frame)
/// with principal moments `moments` [kg m^2] to its generalized forces: Euler's
/// equations `J dw'/dt + w' x (J w') = M'` written as the diagonal mass times the
/// acceleration equal to a load (Nikravesh 1988; Haug 1989).
#[inline]
pub fn add_gyroscopic<T: Real>(qe: &mut [T], moments: Vec3, omega: &Vector3<T>) {
    add_to(qe, 3, &-omega.cross(&constant(&moments).component_mul(omega)));
}

/// `x[at..at + 3] += y`.
#[inline]
fn add_to<T: Real>(x: &mut [T], at: usize, y: &Vector3<T>) {
    x[at..at + 3].iter_mut().zip(y.iter()).for_each(|(x, y)| *x += *y);
}

/// A vector of the model (a point, an axis) as constants of the number type `T`.
#[inline(always)]
pub fn constant<T: Real>(v: &Vec3) -> Vector3<T> {
    v.map(T::constant)
}

/// Whether velocity coordinate `d` of a spatial body is a rotation (`wx'`, `wy'`, `wz'`).
#[inline]
pub fn is_rotation(d: usize) -> bool {
    d >= 3
}

/// How far the rounding of a spatial body's quaternion moves the point of a row whose
/// block on the body is `entries`, and how much it changes the point's velocity, given
/// the body's positions `q` and velocities `v`; `None` for a row that holds no position
/// of the body (an angle row, whose residual the rounding changes by ulps of 1, which
/// the quaternion's own entries in `q` already bring).
///
/// A point row `u . P` with `P = r + A s` has the rotation entries
/// `dC/dpi' = -u . A [s]x = (s x A^T u)`. A turn of the body by the small angle
/// `dtheta` about any axis moves the residual by at most `|s x A^T u| dtheta`: the
/// length of those entries, times [`QUATERNION_ROUNDING`] ulps of turn. The velocity
/// `u . A (w' x s)` changes by up to `|s| |w'| dtheta`, here with the entries' length for
/// `|s|`, short of it where the row's direction nears the arm, which the margin of ulps
/// the caller applies covers (as for the planar body). Unlike a planar angle, the
/// quaternion's entries stay within 1, so the reach does not grow as the body turns on.
#[inline]
pub fn rotation_reach(entries: &BodyRow, _q: &[f64], v: &[f64]) -> Option<(f64, f64)> {
    entries[..3].iter().any(|&x| x != 0.0).then(|| {
        let reach = QUATERNION_ROUNDING * Vec3::new(entries[3], entries[4], entries[5]).norm();
        (reach, reach * Vec3::new(v[3], v[4], v[5]).norm())
    })
}

/// The acceleration of a spatial body's centre of mass (global axes) and its angular
/// acceleration in the body frame and in global axes, from its accelerations
/// `a = (a, dw'/dt)` at state `state`: `d/dt (A w') = A (w' x w') + A dw'/dt = A dw'/dt`.
#[inline]
pub fn read_acceleration(a: &[f64], state: &BodyState) -> (Vec3, Vec3, Vec3) {
    let alpha = Vec3::new(a[3], a[4], a[5]);
    (Vec3::new(a[0], a[1], a[2]), alpha, state.a * alpha)
}

/// Writes the rate of a spatial body's positions `q` at velocities `v` into `out` (7
/// entries): `dr/dt = v` and `de/dt = e (x) (0, w') / 2`, the quaternion product with
/// the body-frame angular velocity as a pure quaternion (Nikravesh 1988, Euler parameters).
/// It takes `e` as it stands, off unit length inside a step: the rate is then still
/// orthogonal to `e`, so it keeps the length `e` has.
#[inline]
pub fn position_rate(q: &[f64], v: &[f64], out: &mut [f64]) {
    out[..3].copy_from_slice(&v[..3]);
    let e = Quaternion::new(q[3], q[4], q[5], q[6]);
    let rate = e * Quaternion::from_imag(Vec3::new(v[3], v[4], v[5])) * 0.5;
    out[3] = rate.w;
    out[4..7].copy_from_slice(rate.imag().as_slice());
}

/// A spatial body's `q''` from its positions `q`, velocities `v` and accelerations `a`:
/// `r'' = a` and, differentiating [`position_rate`],
/// `e'' = 1/2 (e' (x) (0, w') + e (x) (0, w''))` with `e' = 1/2 e (x) (0, w')`; the
/// dense output's positions take it at the ends of a step.
pub fn position_acceleration(q: &[f64], v: &[f64], a: &[f64], out: &mut [f64]) {
    out[..3].copy_from_slice(&a[..3]);
    let e = Quaternion::new(q[3], q[4], q[5], q[6]);
    let w = Quaternion::from_imag(Vec3::new(v[3], v[4], v[5]));
    let w_dot = Quaternion::from_imag(Vec3::new(a[3], a[4], a[5]));
    let e_dot = e * w * 0.5;
    let e_ddot = (e_dot * w + e * w_dot) * 0.5;
    out[3] = e_ddot.w;
    out[4..7].copy_from_slice(e_ddot.imag().as_slice());
}

/// The 7 x 6 matrix `G(q)` with `dq/dt = G v` (rows: positions; columns: velocities),
/// [`position_rate`] as a matrix: the identity on the centre of mass and
/// `(1/2) [-e_v^T; e0 I + [e_v]x]` on the quaternion `e = (e0, e_v)`: the implicit
/// methods' Jacobian block `d(dq/dt)/dv`.
pub fn rate_block(q: &[f64]) -> [[f64; NV]; NQ] {
    let (e0, e1, e2, e3) = (0.5 * q[3], 0.5 * q[4], 0.5 * q[5], 0.5 * q[6]);
    let mut g = [[0.0; NV]; NQ];
    for k in 0..3 {
        g[k][k] = 1.0;
    }
    g[3][3..].copy_from_slice(&[-e1, -e2, -e3]);
    g[4][3..].copy_from_slice(&[e0, -e3, e2]);
    g[5][3..].copy_from_slice(&[e3, e0, -e1]);
    g[6][3..].copy_from_slice(&[-e2, e1, e0]);
    g
}

/// Brings a spatial body's quaternion back to unit length (the integrators' position
/// update after a step, which leaves it off by the step's error); returns whether that
/// changed it.
pub fn normalise(q: &mut [f64]) -> bool {
    let e = Quaternion::new(q[3], q[4], q[5], q[6]).normalize();
    let unit = [e.w, e.i, e.j, e.k];
    let changed = q[3..7] != unit;
    q[3..7].copy_from_slice(&unit);
    changed
}

/// Moves a spatial body's positions `q` by `dv`, a displacement in its velocity
/// coordinates (a Newton or projection correction): `r += dr` and the body turned by the
/// body-frame rotation vector `dpi'`, `e = e (x) exp(dpi' / 2)` (the exact turn, not
/// its first order `e + G dpi'`, so that a large correction stays a rotation), then to
/// unit length.
pub fn displace(q: &mut [f64], dv: &[f64]) {
    q[..3].iter_mut().zip(&dv[..3]).for_each(|(q, d)| *q += d);
    let e = Quaternion::new(q[3], q[4], q[5], q[6]);
    let turn = UnitQuaternion::from_scaled_axis(Vec3::new(dv[3], dv[4], dv[5]));
    let e = (e * turn.into_inner()).normalize();
    q[3..7].copy_from_slice(&[e.w, e.i, e.j, e.k]);
}

/// A spatial body's positions and velocities from its placement: centre of mass `r`,
/// `orientation` (body frame to global axes), velocity of the centre of mass `v` and
/// angular velocity `omega`, both in global axes as a user gives them; the angular
/// velocity is turned into the body frame, `w' = A^T w`. The starting guess of assembly.
pub fn placement_coordinates(
    r: &Vec3,
    orientation: &Orientation,
    v: &Vec3,
    omega: &Vec3,
) -> (BodyPositions, BodyRow) {
    let e = orientation.quaternion();
    let w = orientation.inverse_transform_vector(omega);
    ([r.x, r.y, r.z, e.w, e.i, e.j, e.k], [v.x, v.y, v.z, w.x, w.y, w.z])
}

/// Position and velocity of one spatial body (the ground: at rest at the origin,
/// unturned), with its rotation matrix computed once: every row and force on the body
/// rotates by it.
#[derive(Debug, Clone, Copy)]
pub struct BodyState<T: Real = f64> {
    /// Centre of mass [m].
    pub r: Vector3<T>,
    /// The unit quaternion of its orientation, `(e1, e2, e3, e0)` (nalgebra's order).
    e: Vector4<T>,
    /// The rotation matrix `A` (body frame to global axes).
    pub a: Matrix3<T>,
    /// Velocity of the centre of mass, global [m/s].
    pub v: Vector3<T>,
    /// Angular velocity in the body frame `w'` [rad/s].
    pub omega: Vector3<T>,
}

impl BodyState {
    /// The ground.
    pub fn ground() -> Self {
        BodyState::new(Vec3::zeros(), Orientation::identity(), Vec3::zeros(), Vec3::zeros())
    }

    /// The state at centre `r`, orientation, velocity `v` and body-frame angular
    /// velocity `omega`.
    pub fn new(r: Vec3, orientation: Orientation, v: Vec3, omega: Vec3) -> Self {
        let e = orientation.into_inner().coords;
        BodyState { r, e, a: rotation_matrix(&e), v, omega }
    }

    /// Its orientation (body frame to global axes).
    #[inline]
    pub fn orientation(&self) -> Orientation {
        Orientation::new_unchecked(Quaternion::from(self.e))
    }
}

impl<T: Real> BodyState<T> {
    /// The state from a body's positions and velocities. The quaternion is normalised on
    /// reading: an integrator's stage states leave it off unit length by the step's error.
    /// On `f64` it gives the bits of nalgebra's `UnitQuaternion::from_quaternion` and
    /// `to_rotation_matrix`, which it repeats operation for operation.
    #[inline]
    pub fn read(q: &[T], v: &[T]) -> Self {
        let e = Vector4::new(q[4], q[5], q[6], q[3]);
        let length = norm(&e);
        let e = e.map(|x| x / length);
        BodyState {
            r: Vector3::new(q[0], q[1], q[2]),
            e,
            a: rotation_matrix(&e),
            v: Vector3::new(v[0], v[1], v[2]),
            omega: Vector3::new(v[3], v[4], v[5]),
        }
    }

    /// `A s`: a body-frame vector in global axes.
    #[inline]
    pub fn rotate(&self, s: &Vector3<T>) -> Vector3<T> {
        self.a * s
    }

    /// The angular velocity in global axes `w = A w'`.
    #[inline]
    pub fn omega_global(&self) -> Vector3<T> {
        self.a * self.omega
    }

    /// Global velocity of the body's point `s` (body frame): `v + A (w' x s)`.
    #[inline]
    pub fn point_velocity(&self, s: &Vector3<T>) -> Vector3<T> {
        self.v + self.a * self.omega.cross(s)
    }
}

/// The rotation matrix of the unit quaternion `e = (e1, e2, e3, e0)`, written as
/// nalgebra's `UnitQuaternion::to_rotation_matrix` computes it (the same operations in
/// the same order), so that on `f64` it gives its bits.
#[inline]
fn rotation_matrix<T: Real>(e: &Vector4<T>) -> Matrix3<T> {
    let (i, j, k, w) = (e[0], e[1], e[2], e[3]);
    let (ww, ii, jj, kk) = (w * w, i * i, j * j, k * k);
    let two = T::constant(2.0);
    let (ij, wk, wj) = (i * j * two, w * k * two, w * j * two);
    let (ik, jk, wi) = (i * k * two, j * k * two, w * i * two);
    Matrix3::new(
        ww + ii - jj - kk,
        ij - wk,
        wj + ik,
        wk + ij,
        ww - ii + jj - kk,
        jk - wi,
        ik - wj,
        wi + jk,
        ww - ii - jj + kk,
    )
}

impl Default for BodyState {
    /// The ground.
    fn default() -> Self {
        BodyState::ground()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body away from every special orientation, moving and turning about all axes.
    fn sample() -> (BodyPositions, BodyRow) {
        let e = Orientation::from_scaled_axis(Vec3::new(0.7, -1.1, 0.4)).into_inner();
        ([0.3, -0.2, 0.5, e.w, e.i, e.j, e.k], [1.1, -0.4, 0.8, 2.3, -1.7, 3.1])
    }

    fn point(q: &[f64], s: &Vec3) -> Vec3 {
        BodyState::read(q, &[0.0; NV]).r + BodyState::read(q, &[0.0; NV]).rotate(s)
    }

    /// `q` displaced by `dv * h`.
    fn displaced(q: &BodyPositions, dv: &BodyRow, h: f64) -> BodyPositions {
        let mut q = *q;
        displace(&mut q, &dv.map(|d| d * h));
        q
    }

    /// The matrix `G` times `v` is the rate the quaternion product gives, for a unit
    /// quaternion and for one off unit length (a stage state), where both scale with it.
    #[test]
    fn rate_block_times_v_is_the_position_rate() {
        let (q, v) = sample();
        for scale in [1.0, 1.3] {
            let mut q = q;
            q[3..].iter_mut().for_each(|e| *e *= scale);
            let mut rate = [0.0; NQ];
            position_rate(&q, &v, &mut rate);
            let g = rate_block(&q);
            for i in 0..NQ {
                let gv: f64 = (0..NV).map(|j| g[i][j] * v[j]).sum();
                assert!((gv - rate[i]).abs() < 1e-15, "row {i}: G v {gv} vs {}", rate[i]);
            }
            let e = Quaternion::new(q[3], q[4], q[5], q[6]);
            let along: f64 = e.coords.dot(&Quaternion::new(rate[3], rate[4], rate[5], rate[6]).coords);
            assert!(along.abs() < 1e-15, "the rate changes |e|: e . de/dt = {along}");
        }
    }

    /// Displacing by `v h` is moving along the position rate for a time `h`: central
    /// differences of [`displace`] agree with [`position_rate`] to `h^2`.
    /// `q''` against the central difference of the position rate along a motion whose
    /// positions move at that rate and whose velocities move at `a`.
    #[test]
    fn position_acceleration_is_the_rate_of_the_position_rate() {
        let (q, v) = sample();
        let a: BodyRow = [0.3, -1.2, 0.7, 4.0, -2.5, 1.5];
        let mut qdd = [0.0; NQ];
        position_acceleration(&q, &v, &a, &mut qdd);
        let h = 1e-6;
        let rate_at = |s: f64| {
            let mut rate = [0.0; NQ];
            position_rate(&q, &v, &mut rate);
            let qs: BodyPositions = std::array::from_fn(|k| q[k] + s * rate[k]);
            let vs: BodyRow = std::array::from_fn(|k| v[k] + s * a[k]);
            let mut out = [0.0; NQ];
            position_rate(&qs, &vs, &mut out);
            out
        };
        let (plus, minus) = (rate_at(h), rate_at(-h));
        for k in 0..NQ {
            let fd = (plus[k] - minus[k]) / (2.0 * h);
            assert!((fd - qdd[k]).abs() < 1e-7 * (1.0 + fd.abs()), "q''[{k}]: {} vs {fd}", qdd[k]);
        }
    }

    #[test]
    fn displace_follows_the_position_rate() {
        let (q, v) = sample();
        let h = 1e-5;
        let (plus, minus) = (displaced(&q, &v, h), displaced(&q, &v, -h));
        let mut rate = [0.0; NQ];
        position_rate(&q, &v, &mut rate);
        for i in 0..NQ {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            assert!((fd - rate[i]).abs() < 1e-9, "entry {i}: difference {fd} vs rate {}", rate[i]);
        }
        let norm = Quaternion::new(plus[3], plus[4], plus[5], plus[6]).norm();
        assert!((norm - 1.0).abs() < 2.0 * f64::EPSILON, "|e| = 1 + {:e}", norm - 1.0);
    }

    /// The generalized forces of a force and of a torque do the work they do on a
    /// virtual displacement: moving the body by `dv h`, the force's point moves by `dP`
    /// and the body turns by `dtheta` (global), and `qe . dv h = f . dP + tau . dtheta`.
    /// A moment left in global axes, or of the wrong sign, misses by its size.
    #[test]
    fn force_and_torque_do_their_virtual_work() {
        let (q, v) = sample();
        let state = BodyState::read(&q, &v);
        let s = Vec3::new(0.12, -0.3, 0.07);
        let (f, tau) = (Vec3::new(3.0, -5.0, 2.0), Vec3::new(-0.4, 0.9, 1.3));
        let mut qe = [0.0; NV];
        add_force(&mut qe, &state, &state.rotate(&s), &f);
        let mut torque = [0.0; NV];
        add_torque(&mut torque, &state, &tau);
        let h = 1e-6;
        for dv in
            [[0.2, -0.7, 0.4, 1.3, 0.5, -0.9], [0.0, 0.0, 0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
        {
            let (plus, minus) = (displaced(&q, &dv, h), displaced(&q, &dv, -h));
            let work = f.dot(&(point(&plus, &s) - point(&minus, &s))) / (2.0 * h);
            let power: f64 = qe.iter().zip(&dv).map(|(a, b)| a * b).sum();
            assert!((work - power).abs() < 1e-8 * f.norm(), "force: f . dP {work} vs qe . dv {power}");
            let (a, b) =
                (BodyState::read(&plus, &v).orientation(), BodyState::read(&minus, &v).orientation());
            let turn = (a * b.inverse()).scaled_axis() / (2.0 * h);
            let power: f64 = torque.iter().zip(&dv).map(|(a, b)| a * b).sum();
            assert!(
                (tau.dot(&turn) - power).abs() < 1e-8 * tau.norm(),
                "torque: tau . dtheta {} vs qe . dv {power}",
                tau.dot(&turn)
            );
        }
    }

    /// A body made of six point masses on its axes (`m_k` at `+-a_k` along axis k, so
    /// `J1 = 2 (m2 a2^2 + m3 a3^2)` and so on) has the kinetic energy of its points,
    /// `sum m_i |v_i|^2 / 2` with each point's velocity from [`BodyState::point_velocity`];
    /// and the weight's generalized forces are the rate of gravity's work along any
    /// displacement.
    #[test]
    fn kinetic_energy_and_weight_agree_with_point_masses() {
        let (q, v) = sample();
        let state = BodyState::read(&q, &v);
        let (m, a) = ([0.5, 1.2, 0.8], [0.3, 0.1, 0.25]);
        let mass = 2.0 * (m[0] + m[1] + m[2]);
        let moment = |k: usize| 2.0 * (0..3).filter(|&i| i != k).map(|i| m[i] * a[i] * a[i]).sum::<f64>();
        let moments = Vec3::new(moment(0), moment(1), moment(2));
        let points: f64 = (0..3)
            .flat_map(|k| [1.0, -1.0].map(|side| (k, side)))
            .map(|(k, side)| 0.5 * m[k] * state.point_velocity(&Vec3::ith(k, side * a[k])).norm_squared())
            .sum();
        let energy = kinetic_energy(mass, moments, &v);
        assert!((energy - points).abs() < 1e-14 * points, "{energy} vs the points' {points}");

        let g = Vec3::new(0.3, -9.81, 1.2);
        let mut qe = [0.0; NV];
        add_weight(&mut qe, mass, g);
        let dv = [0.2, -0.7, 0.4, 1.3, 0.5, -0.9];
        let h = 1e-3;
        let work = (gravity_work(mass, g, &displaced(&q, &dv, h))
            - gravity_work(mass, g, &displaced(&q, &dv, -h)))
            / (2.0 * h);
        let power: f64 = qe.iter().zip(&dv).map(|(a, b)| a * b).sum();
        assert!((work - power).abs() < 1e-12 * mass * g.norm(), "{work} vs {power}");
    }

    /// With the gyroscopic moment as its only load, a body keeps its angular momentum
    /// `A J w'` in global axes: its rate, by central differences along the motion, is
    /// zero to `h^2`, where a gyroscopic moment of the wrong sign gives `2 A (w' x J w')`.
    #[test]
    fn gyroscopic_moment_keeps_the_angular_momentum() {
        let (q, v) = sample();
        let moments = Vec3::new(0.02, 0.05, 0.06);
        let mut qe = [0.0; NV];
        add_gyroscopic(&mut qe, moments, &Vec3::new(v[3], v[4], v[5]));
        let a: Vec<f64> = qe.iter().zip(inverse_mass(4.0, moments)).map(|(f, m)| f * m).collect();
        let h = 1e-5;
        let momentum = |sign: f64| {
            let state = BodyState::read(&displaced(&q, &v, sign * h), &v);
            let omega = Vec3::new(v[3] + sign * h * a[3], v[4] + sign * h * a[4], v[5] + sign * h * a[5]);
            state.a * moments.component_mul(&omega)
        };
        let rate = (momentum(1.0) - momentum(-1.0)) / (2.0 * h);
        let w = Vec3::new(v[3], v[4], v[5]);
        let scale = w.cross(&moments.component_mul(&w)).norm();
        assert!(scale > 0.1, "the sample turns off its principal axes");
        assert!(rate.norm() < 1e-8 * scale, "d/dt (A J w') = {rate:?}");
    }

    /// The rounding of the quaternion moves a point row's residual by no more than the
    /// reach: each entry moved by one ulp (up to the rounding, plus the normalising on
    /// reading), in every sign pattern, on rows along each axis and along a slant. The
    /// moves are scaled up by `2^20` (and the bound with them, the turn being linear in
    /// them) so that the rounding of the residual's own evaluation, which the caller
    /// counts apart, does not blur them.
    #[test]
    fn rotation_reach_bounds_the_rounding_of_the_quaternion() {
        let (q, v) = sample();
        const SCALE: f64 = (1 << 20) as f64;
        let s = Vec3::new(0.4, -0.25, 0.6);
        let state = BodyState::read(&q, &v);
        let mut largest = 0.0f64;
        for u in [Vec3::x(), Vec3::y(), Vec3::z(), Vec3::new(0.6, 0.0, 0.8)] {
            // the row u . (r + A s): d/dr = u, d/dpi' = -u . A [s]x = s x A^T u
            let rot = s.cross(&state.a.tr_mul(&u));
            let entries = [u.x, u.y, u.z, rot.x, rot.y, rot.z];
            let (reach, changed) = rotation_reach(&entries, &q, &v).expect("a point row");
            let residual = |q: &[f64]| u.dot(&point(q, &s));
            for pattern in 0..16 {
                let mut rounded = q;
                for (k, e) in rounded[3..].iter_mut().enumerate() {
                    let ulp = e.abs() * f64::EPSILON * SCALE;
                    *e += if pattern >> k & 1 == 1 { ulp } else { -ulp };
                }
                let moved = (residual(&rounded) - residual(&q)).abs();
                let bound = reach * f64::EPSILON * SCALE;
                assert!(moved <= bound, "{u:?}: moved {moved:e} > reach {bound:e}");
                largest = largest.max(moved / bound);
            }
            let w = Vec3::new(v[3], v[4], v[5]);
            assert!((changed - reach * w.norm()).abs() < 1e-15 * changed);
        }
        assert!(largest > 0.2, "the bound is not loose by more than 5: {largest}");
        assert_eq!(rotation_reach(&[0.0, 0.0, 0.0, 0.3, 0.1, 0.0], &q, &v), None, "an angle row");
    }

    /// A placement given in global axes reads back as given: the body-frame angular
    /// velocity turned back, the angular acceleration turned out.
    #[test]
    fn placement_reads_back_in_global_axes() {
        let orientation = Orientation::from_scaled_axis(Vec3::new(-0.3, 0.9, 1.4));
        let (r, v, omega) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(-0.5, 0.2, 0.1), Vec3::new(0.0, 0.0, 4.0));
        let (q, vel) = placement_coordinates(&r, &orientation, &v, &omega);
        let state = BodyState::read(&q, &vel);
        assert!((state.r - r).norm() == 0.0 && (state.v - v).norm() == 0.0);
        assert!((state.omega_global() - omega).norm() < 1e-14, "{:?}", state.omega_global());
        assert!(state.omega.z.abs() < 3.9, "w' is in the body frame: {:?}", state.omega);
        let (a, alpha, alpha_global) = read_acceleration(&[1.0, 2.0, 3.0, 0.5, -0.2, 0.7], &state);
        assert_eq!((a, alpha), (Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.5, -0.2, 0.7)));
        assert!((alpha_global - orientation * alpha).norm() < 1e-15);
    }

    /// Reading a state gives the bits of nalgebra's normalising and rotation matrix, for
    /// quaternions off unit length (a stage state) in every sign pattern, as the
    /// compiled evaluation, which repeats the generic reading, relies on.
    #[test]
    fn reading_gives_nalgebras_bits() {
        let mut x = 0.3f64;
        let mut next = || {
            x = (x * 3.7 + 0.123).fract();
            2.0 * x - 1.0
        };
        for _ in 0..1000 {
            let q = [0.0, 0.0, 0.0, next(), next(), next(), next()];
            let state = BodyState::read(&q, &[0.0; NV]);
            let unit = UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[4], q[5], q[6]));
            let a = unit.to_rotation_matrix().into_inner();
            assert!(state.a.iter().zip(a.iter()).all(|(x, y)| x.to_bits() == y.to_bits()), "{q:?}");
            assert_eq!(state.orientation().coords.map(f64::to_bits), unit.coords.map(f64::to_bits));
        }
    }

    /// Normalising brings `e` to unit length, and a second time changes nothing.
    #[test]
    fn normalise_brings_the_quaternion_to_unit_length() {
        let (mut q, _) = sample();
        q[3..].iter_mut().for_each(|e| *e *= 1.0 + 1e-9);
        assert!(normalise(&mut q));
        let norm = Quaternion::new(q[3], q[4], q[5], q[6]).norm();
        assert!((norm - 1.0).abs() <= f64::EPSILON, "|e| = 1 + {:e}", norm - 1.0);
        assert!(!normalise(&mut q) || !normalise(&mut q), "normalising settles");
        assert_eq!((q[0], q[1], q[2]), (0.3, -0.2, 0.5), "the centre stays");
    }
}
