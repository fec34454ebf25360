//! A spatial rigid body: positions `q = (x, y, z, e0, e1, e2, e3)` (centre of mass and
//! the unit quaternion of its orientation, scalar first), velocities
//! `v = (vx, vy, vz, wx', wy', wz')` (velocity of the centre of mass in global axes and
//! angular velocity in the body's principal frame). The body frame is the principal
//! frame at the centre of mass, so the mass matrix is diagonal `(m, m, m, J1, J2, J3)`
//! and the equations keep the planar engine's diagonal Schur solve; the gyroscopic
//! moment `-w' x (J w')` is an applied load.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::mechanics::layout::BodyShape;

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

/// Position and velocity of one spatial body (the ground: at rest at the origin,
/// unturned), with its rotation matrix computed once: every row and force on the body
/// rotates by it.
#[derive(Debug, Clone, Copy)]
pub struct BodyState {
    /// Centre of mass [m].
    pub r: Vec3,
    /// Orientation (body frame to global axes).
    pub orientation: Orientation,
    /// The rotation matrix `A` of `orientation`.
    pub a: Mat3,
    /// Velocity of the centre of mass, global [m/s].
    pub v: Vec3,
    /// Angular velocity in the body frame `w'` [rad/s].
    pub omega: Vec3,
}

impl BodyState {
    /// The ground.
    pub fn ground() -> Self {
        BodyState::new(Vec3::zeros(), Orientation::identity(), Vec3::zeros(), Vec3::zeros())
    }

    /// The state at centre `r`, orientation, velocity `v` and body-frame angular
    /// velocity `omega`.
    pub fn new(r: Vec3, orientation: Orientation, v: Vec3, omega: Vec3) -> Self {
        BodyState { r, a: orientation.to_rotation_matrix().into_inner(), orientation, v, omega }
    }

    /// The state from a body's positions and velocities. The quaternion is normalised on
    /// reading: an integrator's stage states leave it off unit length by the step's error.
    #[inline]
    pub fn read(q: &[f64], v: &[f64]) -> Self {
        let e = Quaternion::new(q[3], q[4], q[5], q[6]);
        BodyState::new(
            Vec3::new(q[0], q[1], q[2]),
            UnitQuaternion::from_quaternion(e),
            Vec3::new(v[0], v[1], v[2]),
            Vec3::new(v[3], v[4], v[5]),
        )
    }

    /// `A s`: a body-frame vector in global axes.
    #[inline]
    pub fn rotate(&self, s: &Vec3) -> Vec3 {
        self.a * s
    }

    /// The angular velocity in global axes `w = A w'`.
    #[inline]
    pub fn omega_global(&self) -> Vec3 {
        self.a * self.omega
    }

    /// Global velocity of the body's point `s` (body frame): `v + A (w' x s)`.
    #[inline]
    pub fn point_velocity(&self, s: &Vec3) -> Vec3 {
        self.v + self.a * self.omega.cross(s)
    }
}

impl Default for BodyState {
    /// The ground.
    fn default() -> Self {
        BodyState::ground()
    }
}
