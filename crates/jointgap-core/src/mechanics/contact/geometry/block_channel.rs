//! A box-shaped block (slider on body j) in a guide channel of rectangular section (body
//! i): the spatial translational clearance joint. Each of the block's eight corners may
//! touch the channel's wall on its side across the height and the wall on its side across
//! the depth: sixteen contact points (docs/translational-clearance.md, "In space"). The
//! planar block in its guide ([`super::SliderGuide`]) is the same geometry without the
//! depth.

use crate::mechanics::contact::point3::{split, ContactPoint3, ContactPoints3, MaterialPoint3};
use crate::mechanics::spatial::body::{constant, BodyState, Vec3};
use crate::scalar::Real;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Where a block and its guide channel are, and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockChannel {
    /// Guide body (`None`: ground).
    pub guide: Option<usize>,
    /// A point of the channel's centreline, in the guide body's frame [m].
    pub s_guide: Vec3,
    /// The channel's directions in the guide body's frame, unit and orthogonal: along
    /// the guide, across its height, across its depth (`along x height`).
    pub axes_guide: [Vec3; 3],
    /// Block body.
    pub block: Option<usize>,
    /// The block's centre in the block body's frame [m].
    pub s_block: Vec3,
    /// The block's edges' directions in the block body's frame: the channel's at the
    /// model's placement.
    pub axes_block: [Vec3; 3],
    /// Half the block's length, height and depth [m].
    pub half_block: Vec3,
    /// Half the channel's width across the height and across the depth [m].
    pub half_channel: [f64; 2],
}

/// The corners in the block frame as (along, height, depth) signs; corner `k` has the
/// points `2k` (against the height wall on its side) and `2k + 1` (against the depth
/// wall on its side).
pub const CORNERS3: [[f64; 3]; 8] = [
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
];

/// The channel's point and axes and the block's centre and axes, global.
#[derive(Debug, Clone, Copy)]
pub struct Frames<T: Real = f64> {
    /// The channel's centreline point.
    pub origin: Vector3<T>,
    /// Along, height, depth of the channel.
    pub guide: [Vector3<T>; 3],
    /// The block's centre.
    pub centre: Vector3<T>,
    /// The block's along, height, depth.
    pub block: [Vector3<T>; 3],
}

/// Where the block is in its channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// The block centre's travel along the channel from its point [m].
    pub travel: f64,
    /// The centre's offset from the centreline across the height and the depth [m].
    pub offset: [f64; 2],
    /// The block's turn from its placement relative to the channel, as a rotation
    /// vector in the channel's axes (about along, height, depth) [rad].
    pub tilt: Vec3,
}

impl BlockChannel {
    /// Contact points a block in its channel has: two per corner.
    pub const POINTS: usize = 16;

    /// The frames at the bodies' states.
    #[inline]
    pub fn frames<T: Real>(&self, guide: &BodyState<T>, block: &BodyState<T>) -> Frames<T> {
        Frames {
            origin: guide.r + guide.rotate(&constant(&self.s_guide)),
            guide: self.axes_guide.map(|a| guide.rotate(&constant(&a))),
            centre: block.r + block.rotate(&constant(&self.s_block)),
            block: self.axes_block.map(|a| block.rotate(&constant(&a))),
        }
    }

    /// Corner `k` of the block ([`CORNERS3`]), global, the frames being `f`.
    #[inline]
    pub fn corner<T: Real>(&self, f: &Frames<T>, k: usize) -> Vector3<T> {
        let signs = CORNERS3[k];
        f.centre
            + (0..3)
                .fold(Vector3::zeros(), |c, d| c + f.block[d] * T::constant(signs[d] * self.half_block[d]))
    }

    /// The block's travel, offset and tilt in its channel.
    pub fn pose(&self, guide: &BodyState, block: &BodyState) -> Pose {
        let f = self.frames(guide, block);
        let d = f.centre - f.origin;
        let g = Matrix3::from_columns(&f.guide);
        let b = Matrix3::from_columns(&f.block);
        Pose {
            travel: d.dot(&f.guide[0]),
            offset: [d.dot(&f.guide[1]), d.dot(&f.guide[2])],
            tilt: Rotation3::from_matrix_unchecked(g.transpose() * b).scaled_axis(),
        }
    }

    /// The block centre's speed along the channel relative to the channel's point under
    /// it [m/s].
    pub fn speed(&self, guide: &BodyState, block: &BodyState) -> f64 {
        let f = self.frames(guide, block);
        let on_guide = MaterialPoint3::of(self.guide, guide, f.centre);
        let on_block = MaterialPoint3::of(self.block, block, f.centre);
        (on_block.velocity(block) - on_guide.velocity(guide)).dot(&f.guide[0])
    }
}

/// The contact points whose gap is below `reach` [m], pushed onto `out` in the order of
/// their index. Corner `C` against the wall on its side across direction `d` (height or
/// depth, unit `g_d`, sign `s` of the corner's coordinate along the block's `d` axis):
/// normal `n = s g_d`, penetration `(C - O) . n - w_d/2` (O the channel's centreline
/// point, `w_d` the channel's width across `d`), the guide's material point the corner's
/// foot `C - delta n` on the wall. As in the plane, the rate is the penetration's
/// derivative: the wall's points along `n` from the foot move alike along `n`.
#[inline]
pub fn contact_block_channel(
    g: &BlockChannel,
    guide: &BodyState,
    block: &BodyState,
    reach: f64,
    out: &mut ContactPoints3,
) {
    let f = g.frames(guide, block);
    for k in 0..CORNERS3.len() {
        let corner = g.corner(&f, k);
        for wall in 0..2 {
            if let Some(p) = wall_contact(g, &f, corner, (guide, block), 2 * k + wall, reach) {
                out.push(p);
            }
        }
    }
}

/// Point `index` ([`contact_block_channel`]) in any number type: its corner (at `corner`,
/// global) against the wall on its side, the frames being `f`; `None` where its gap is
/// `reach` or more.
#[inline]
pub fn wall_contact<T: Real>(
    g: &BlockChannel,
    f: &Frames<T>,
    corner: Vector3<T>,
    (guide, block): (&BodyState<T>, &BodyState<T>),
    index: usize,
    reach: f64,
) -> Option<ContactPoint3<T>> {
    let (signs, wall) = (CORNERS3[index / 2], index % 2);
    let n = f.guide[wall + 1] * T::constant(signs[wall + 1]);
    let penetration = (corner - f.origin).dot(&n) - g.half_channel[wall];
    if penetration <= -reach {
        return None;
    }
    let foot = corner - n * penetration;
    Some(split(
        index,
        n,
        penetration,
        T::constant(1.0),
        (MaterialPoint3::of(g.guide, guide, foot), guide),
        (MaterialPoint3::of(g.block, block, corner), block),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::contact::geometry::spatial_checks::{
        check_arms_by_virtual_work, check_rate_and_slip_by_motion,
    };
    use crate::mechanics::spatial::body::Orientation;

    /// A channel 10.5 mm wide across the height and 20.4 mm across the depth on a
    /// turned, moving guide body; a block 40 x 10 x 20 mm.
    fn joint() -> BlockChannel {
        let turn = Orientation::from_scaled_axis(Vec3::new(0.1, -0.3, 0.2));
        BlockChannel {
            guide: Some(0),
            s_guide: Vec3::new(0.01, 0.005, -0.02),
            axes_guide: [turn * Vec3::x(), turn * Vec3::y(), turn * Vec3::z()],
            block: Some(1),
            s_block: Vec3::new(-0.02, 0.003, 0.001),
            axes_block: [Vec3::x(), Vec3::y(), Vec3::z()],
            half_block: Vec3::new(0.02, 0.005, 0.01),
            half_channel: [0.00525, 0.0102],
        }
    }

    fn guide_body() -> BodyState {
        BodyState::new(
            Vec3::new(0.3, -0.1, 0.05),
            Orientation::from_scaled_axis(Vec3::new(0.0, 0.0, 0.4)),
            Vec3::new(0.2, -0.1, 0.3),
            Vec3::new(0.5, -1.5, 2.0),
        )
    }

    /// The block placed with its centre at `offset` (height, depth, from the channel's
    /// point, travel `x`) and turned by `tilt` (rotation vector in the channel's axes)
    /// from alignment.
    fn block_at(g: &BlockChannel, guide: &BodyState, x: f64, offset: [f64; 2], tilt: Vec3) -> BodyState {
        let f = g.frames(guide, &BodyState::ground());
        let gm = Matrix3::from_columns(&f.guide);
        // Block frame: axes_block = identity, so the block body's rotation is G R.
        let rot = gm * Rotation3::from_scaled_axis(tilt).into_inner();
        let e = Orientation::from_matrix(&rot);
        let centre = f.origin + f.guide[0] * x + f.guide[1] * offset[0] + f.guide[2] * offset[1];
        BodyState::new(centre - e * g.s_block, e, Vec3::new(1.0, 0.3, -0.2), Vec3::new(-3.0, 4.0, 1.5))
    }

    fn all(g: &BlockChannel, guide: &BodyState, block: &BodyState) -> ContactPoints3 {
        let mut out = ContactPoints3::new();
        contact_block_channel(g, guide, block, f64::INFINITY, &mut out);
        out
    }

    /// Each corner's penetration against its coordinates written out by hand in the
    /// channel's axes: a block turned by a small angle `t` about the depth axis has its
    /// corners at `(+-L/2 cos t -+ H/2 sin t, +-L/2 sin t +- H/2 cos t, +-D/2)` from its
    /// centre.
    #[test]
    fn corners_against_hand_geometry() {
        let g = joint();
        let guide = guide_body();
        let t = 0.004;
        let (y0, z0) = (1e-4, -2e-4);
        let block = block_at(&g, &guide, 0.03, [y0, z0], Vec3::new(0.0, 0.0, t));
        let points = all(&g, &guide, &block);
        assert_eq!(points.len(), BlockChannel::POINTS);
        let [l, h, d] = [g.half_block.x, g.half_block.y, g.half_block.z];
        for p in points.iter() {
            let [sa, sh, sd] = CORNERS3[p.index / 2];
            let height = y0 + sa * l * t.sin() + sh * h * t.cos();
            let depth = z0 + sd * d;
            let expected = if p.index % 2 == 0 {
                sh * height - g.half_channel[0]
            } else {
                sd * depth - g.half_channel[1]
            };
            assert!(
                (p.penetration - expected).abs() < 1e-15,
                "point {}: {} vs {expected}",
                p.index,
                p.penetration
            );
        }
        let pose = g.pose(&guide, &block);
        assert!((pose.travel - 0.03).abs() < 1e-15);
        assert!((pose.offset[0] - y0).abs() < 1e-15 && (pose.offset[1] - z0).abs() < 1e-15);
        // The angle comes back from a rotation matrix: round-off near 1e-13 rad.
        assert!((pose.tilt - Vec3::new(0.0, 0.0, t)).norm() < 1e-12, "{:?}", pose.tilt);
    }

    #[test]
    fn rates_slips_and_arms_against_differences() {
        let g = joint();
        let guide = guide_body();
        let block = block_at(&g, &guide, -0.01, [2e-4, -1e-4], Vec3::new(0.002, -0.003, 0.001));
        let kernel = |i: &BodyState, j: &BodyState| all(&g, i, j);
        check_rate_and_slip_by_motion(&guide, &block, &kernel, BlockChannel::POINTS);
        check_arms_by_virtual_work(&guide, &block, &kernel, BlockChannel::POINTS);
    }

    /// The speed along the channel against the travel's central difference.
    #[test]
    fn speed_is_the_travel_rate() {
        use crate::mechanics::contact::geometry::spatial_checks::moving;
        let g = joint();
        let guide = guide_body();
        let block = block_at(&g, &guide, 0.01, [1e-4, 1e-4], Vec3::new(0.001, 0.002, -0.001));
        let h = 1e-7;
        let travel = |dt: f64| g.pose(&moving(&guide, dt), &moving(&block, dt)).travel;
        let fd = (travel(h) - travel(-h)) / (2.0 * h);
        assert!((g.speed(&guide, &block) - fd).abs() < 1e-7, "{} vs {fd}", g.speed(&guide, &block));
    }

    /// Only the points nearer than the reach come back.
    #[test]
    fn reach_selects_the_points() {
        let g = joint();
        let guide = guide_body();
        let block = block_at(&g, &guide, 0.0, [2e-4, 0.0], Vec3::zeros());
        let mut out = ContactPoints3::new();
        contact_block_channel(&g, &guide, &block, 1e-4, &mut out);
        // Upper corners are 0.25 mm - 0.2 mm = 50 um from the upper wall; the others far.
        let indices: Vec<usize> = out.iter().map(|p| p.index).collect();
        assert_eq!(indices, vec![0, 2, 8, 10]);
    }
}
