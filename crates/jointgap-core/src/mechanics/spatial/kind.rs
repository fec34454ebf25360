//! The spatial body kind ([`BodyKind`]): the items of [`body`] and the spatial rows,
//! forces and clearance joints, as the engine instantiates them.

use super::body::{self, BodyRow, BodyState, Vec3, CHANNELS, SPATIAL_BODY};
use super::forces::SpatialForce;
use super::inertia::PrincipalInertia;
use super::joints::SpatialRowKind;
use crate::mechanics::contact::spatial::SpatialClearance;
use crate::mechanics::drivers::Motion;
use crate::mechanics::kind::{BodyKind, RowEval};
use crate::mechanics::layout::BodyShape;

/// The spatial body kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Spatial;

impl BodyKind for Spatial {
    const SHAPE: BodyShape = SPATIAL_BODY;
    const IDENTITY_RATE: bool = false;
    const CHANNELS: &'static [&'static str] = &CHANNELS;
    type Row = BodyRow;
    type State = BodyState;
    type Vector = Vec3;
    /// Principal moments `(J1, J2, J3)` [kg m^2] about the body frame's axes, and that
    /// (principal) frame's turn from the frame the user gave the body in.
    type Inertia = PrincipalInertia;
    type JointKind = crate::model::spatial::JointKind;
    type RowKind = SpatialRowKind;
    type Force = SpatialForce;
    type Clearance = SpatialClearance;

    fn ground() -> BodyState {
        BodyState::ground()
    }

    #[inline]
    fn read(q: &[f64], v: &[f64]) -> BodyState {
        BodyState::read(q, v)
    }

    #[inline]
    fn eval(row: &SpatialRowKind, bi: &BodyState, bj: &BodyState, motion: Motion) -> RowEval<BodyRow> {
        row.eval(bi, bj, motion)
    }

    #[inline]
    fn mass_diagonal(mass: f64, inertia: &PrincipalInertia) -> BodyRow {
        body::mass_diagonal(mass, inertia.moments)
    }

    #[inline]
    fn inverse_mass(mass: f64, inertia: &PrincipalInertia) -> BodyRow {
        body::inverse_mass(mass, inertia.moments)
    }

    #[inline]
    fn add_weight(qe: &mut [f64], mass: f64, gravity: &Vec3) {
        body::add_weight(qe, mass, *gravity)
    }

    #[inline]
    fn add_inertial(qe: &mut [f64], inertia: &PrincipalInertia, state: &BodyState) {
        body::add_gyroscopic(qe, inertia.moments, &state.omega)
    }

    #[inline]
    fn displace(q: &mut [f64], dv: &[f64]) {
        body::displace(q, dv)
    }

    #[inline]
    fn is_rotation(d: usize) -> bool {
        body::is_rotation(d)
    }

    #[inline]
    fn rotation_reach(entries: &BodyRow, q: &[f64], v: &[f64]) -> Option<(f64, f64)> {
        body::rotation_reach(entries, q, v)
    }

    #[inline]
    fn position_rate(q: &[f64], v: &[f64], out: &mut [f64]) {
        body::position_rate(q, v, out)
    }

    #[inline]
    fn position_acceleration(q: &[f64], v: &[f64], a: &[f64], out: &mut [f64]) {
        body::position_acceleration(q, v, a, out)
    }

    fn rate_block(q: &[f64], mut put: impl FnMut(usize, usize, f64)) {
        for (r, row) in body::rate_block(q).iter().enumerate() {
            for (c, &x) in row.iter().enumerate() {
                if x != 0.0 {
                    put(r, c, x);
                }
            }
        }
    }

    #[inline]
    fn normalise(q: &mut [f64]) -> bool {
        body::normalise(q)
    }

    fn norm(v: &Vec3) -> f64 {
        v.norm()
    }

    #[inline]
    fn kinetic_energy(mass: f64, inertia: &PrincipalInertia, v: &[f64]) -> f64 {
        body::kinetic_energy(mass, inertia.moments, v)
    }

    #[inline]
    fn gravity_work(mass: f64, gravity: &Vec3, q: &[f64]) -> f64 {
        body::gravity_work(mass, *gravity, q)
    }
}
