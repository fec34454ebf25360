//! A rectangular block (slider on body j) between the two flat surfaces of a guide
//! (body i): four contact points, one per corner, each against the guide surface on
//! its own side (docs/translational-clearance.md). Flores, Ambrosio, Claro, Lankarani,
//! J. Comput. Nonlinear Dyn. 3 (2008) 011007.

use crate::math::{perp, Vec2};
use crate::mechanics::contact::point::{ContactPoint, ContactPoints, MaterialPoint};
use crate::mechanics::planar_body::BodyState;
use crate::scalar::Real;

/// Where a block and its guide are, and their sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct SliderGuide {
    /// Guide body (`None`: ground).
    pub guide: Option<usize>,
    /// A point of the guide's centreline, in the guide body frame [m].
    pub s_guide: Vec2,
    /// The guide's direction, unit, in the guide body frame.
    pub axis: Vec2,
    /// Block body.
    pub block: Option<usize>,
    /// The block's centre in the block body frame [m].
    pub s_block: Vec2,
    /// The block's long axis, unit, in the block body frame.
    pub block_axis: Vec2,
    /// Half the block's length along its axis [m].
    pub half_length: f64,
    /// Half the block's height across its axis [m].
    pub half_height: f64,
    /// Half the distance between the guide's surfaces [m].
    pub half_width: f64,
}

/// The corners in the block frame as (along, across) signs, in the order of their
/// points: front upper, rear upper, rear lower, front lower. "Upper" is the side of
/// `perp(axis)`; an upper corner meets the upper surface.
pub const CORNERS: [(f64, f64); 4] = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];

impl SliderGuide {
    /// Contact points a block in its guide has: its four corners.
    pub const POINTS: usize = 4;

    /// The guide's point and direction, and the block's centre and direction, global.
    #[inline]
    pub fn frames<T: Real>(
        &self,
        guide: &BodyState<T>,
        block: &BodyState<T>,
    ) -> ([Vec2<T>; 2], [Vec2<T>; 2]) {
        (
            [guide.r + guide.rotate(self.s_guide), guide.rotate(self.axis)],
            [block.r + block.rotate(self.s_block), block.rotate(self.block_axis)],
        )
    }

    /// The block's tilt in the guide [rad] (zero when aligned, counter-clockwise
    /// positive) and its centre's offset from the centreline along `perp(axis)` [m].
    pub fn tilt_and_offset(&self, guide: &BodyState, block: &BodyState) -> (f64, f64) {
        let ([g0, u], [centre, a]) = self.frames(guide, block);
        (f64::atan2(crate::math::cross(u, a), u.dot(&a)), (centre - g0).dot(&perp(u)))
    }
}

/// The corners whose gap is below `reach` [m], pushed onto `out`. Corner `c` on the
/// upper side: penetration `(c - g0) . n - w/2` with `n = perp(u)` (u the guide's
/// direction, g0 its centreline point, w its width); on the lower side `n = -perp(u)`.
/// The normal `n` points the way the corner presses into the surface, the guide's
/// material point is the corner's foot on the surface, and the rate and slip are the
/// corner's velocity relative to the guide's point along `n` and `perp(n)`. The rate is
/// the penetration's derivative: the guide's points along `n` from the foot move alike
/// along `n`.
#[inline]
pub fn contact_slider_guide(
    g: &SliderGuide,
    guide: &BodyState,
    block: &BodyState,
    reach: f64,
    out: &mut ContactPoints,
) {
    let frames = g.frames(guide, block);
    for index in 0..SliderGuide::POINTS {
        if let Some(p) = corner_contact(g, frames, guide, block, index, reach) {
            out.push(p);
        }
    }
}

/// Corner `index`'s contact point ([`contact_slider_guide`]) in any number type, the
/// frames being [`SliderGuide::frames`]'; `None` where its gap is `reach` or more.
#[inline]
pub fn corner_contact<T: Real>(
    g: &SliderGuide,
    ([g0, u], [centre, a]): ([Vec2<T>; 2], [Vec2<T>; 2]),
    guide: &BodyState<T>,
    block: &BodyState<T>,
    index: usize,
    reach: f64,
) -> Option<ContactPoint<T>> {
    let (along, across) = CORNERS[index];
    let corner =
        centre + a * T::constant(along * g.half_length) + perp(a) * T::constant(across * g.half_height);
    let n = perp(u) * T::constant(across);
    let penetration = (corner - g0).dot(&n) - g.half_width;
    if penetration <= -reach {
        return None;
    }
    let foot = corner - n * penetration;
    let v = block.velocity_at(corner) - guide.velocity_at(foot);
    let parts = (MaterialPoint { body: g.guide, at: foot }, MaterialPoint { body: g.block, at: corner });
    Some(ContactPoint { index, ..ContactPoint::in_bearing(n, penetration, v, T::constant(1.0), parts) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotate;

    /// A guide along (cos 0.2, sin 0.2) through (10, 5) mm of a body at (0.3, -0.1) m
    /// turned by 0.4 rad; a block 40 x 10 mm in a guide 10.5 mm wide.
    fn joint() -> SliderGuide {
        SliderGuide {
            guide: Some(0),
            s_guide: Vec2::new(0.01, 0.005),
            axis: Vec2::new(f64::cos(0.2), f64::sin(0.2)),
            block: Some(1),
            s_block: Vec2::new(-0.02, 0.003),
            block_axis: Vec2::new(1.0, 0.0),
            half_length: 0.02,
            half_height: 0.005,
            half_width: 0.00525,
        }
    }

    fn guide_state() -> BodyState {
        BodyState::new(Vec2::new(0.3, -0.1), 0.4, Vec2::new(0.2, -0.3), 1.5)
    }

    /// The block body placed with its centre at `along`, `offset` in the guide's frame,
    /// tilted by `tilt` from the guide, moving with centre velocity `v_centre` and spin
    /// `omega`.
    fn block_at(g: &SliderGuide, guide: &BodyState, along: f64, offset: f64, tilt: f64) -> BodyState {
        let ([g0, u], _) = g.frames(guide, guide);
        let centre = g0 + u * along + perp(u) * offset;
        // The block's axis in its frame is (1, 0): its body angle is the guide's direction
        // plus the tilt.
        let phi = f64::atan2(u.y, u.x) + tilt;
        let arm = rotate(phi, g.s_block);
        BodyState::new(centre - arm, phi, Vec2::new(0.7, 0.1) - perp(arm) * -4.0, -4.0)
    }

    fn all(g: &SliderGuide, guide: &BodyState, block: &BodyState) -> ContactPoints {
        let mut out = ContactPoints::new();
        contact_slider_guide(g, guide, block, f64::INFINITY, &mut out);
        out
    }

    /// Aligned and centred: every corner is `(w - h)/2` from its surface; shifted up by
    /// `d`, the upper corners gain `d` and the lower lose it; tilted by `theta`, the front
    /// upper and the rear lower corner gain `L/2 sin(theta)` and the height shrinks by
    /// `h/2 (1 - cos(theta))`, against the closed form of a rotated rectangle.
    #[test]
    fn corners_against_closed_form() {
        let g = joint();
        let guide = guide_state();
        let gap = g.half_width - g.half_height;
        for (offset, tilt) in [(0.0, 0.0), (0.0002, 0.0), (-0.0001, 0.01), (0.00005, -0.02)] {
            let block = block_at(&g, &guide, 0.05, offset, tilt);
            let points = all(&g, &guide, &block);
            assert_eq!(points.len(), 4);
            let (tilt_out, offset_out) = g.tilt_and_offset(&guide, &block);
            assert!((tilt_out - tilt).abs() < 1e-12 && (offset_out - offset).abs() < 1e-15);
            for (p, (along, across)) in points.iter().zip(CORNERS) {
                // The corner's height above the centreline of a rectangle turned by tilt.
                let height =
                    offset + along * g.half_length * f64::sin(tilt) + across * g.half_height * f64::cos(tilt);
                let expected = across * height - g.half_width;
                assert!(
                    (p.penetration - expected).abs() < 1e-15,
                    "offset {offset} tilt {tilt} corner {along},{across}: {} vs {expected}",
                    p.penetration
                );
                if offset == 0.0 && tilt == 0.0 {
                    assert!((p.penetration + gap).abs() < 1e-15);
                }
                // The foot lies on the surface, the normal is across the guide.
                let ([g0, u], _) = g.frames(&guide, &guide);
                assert!(((p.on_i.at - g0).dot(&perp(u)) - across * g.half_width).abs() < 1e-15);
                assert!((p.normal - perp(u) * across).norm() < 1e-15);
                assert_eq!((p.on_i.body, p.on_j.body), (Some(0), Some(1)));
            }
        }
    }

    /// The penetration rate of each corner is the derivative of its penetration, by
    /// central differences of placements moved along the bodies' velocities; the slip is
    /// the corner's velocity relative to the guide surface along it.
    #[test]
    fn rates_are_the_derivatives_of_the_penetrations() {
        let g = joint();
        let guide = guide_state();
        let block = block_at(&g, &guide, 0.05, 0.0001, 0.015);
        let moved =
            |b: &BodyState, dt: f64| BodyState::new(b.r + b.v * dt, b.phi() + b.omega * dt, b.v, b.omega);
        let h = 1e-7;
        let now = all(&g, &guide, &block);
        for k in 0..4 {
            let depth = |dt: f64| all(&g, &moved(&guide, dt), &moved(&block, dt))[k].penetration;
            let fd = (depth(h) - depth(-h)) / (2.0 * h);
            let rate = now[k].penetration_rate;
            assert!((rate - fd).abs() < 1e-7 * rate.abs().max(1.0), "corner {k}: {rate} vs {fd}");
            let v = block.velocity_at(now[k].on_j.at) - guide.velocity_at(now[k].on_i.at);
            assert!((now[k].slip[0] - v.dot(&perp(now[k].normal))).abs() < 1e-15);
        }
    }

    /// A contact law (reach 0) gets only the corners that touch: a block shifted up
    /// past its gap touches with both upper corners; tilted, with one upper and one
    /// lower corner.
    #[test]
    fn reach_selects_the_touching_corners() {
        let g = joint();
        let guide = guide_state();
        let touching = |offset: f64, tilt: f64| {
            let mut out = ContactPoints::new();
            contact_slider_guide(&g, &guide, &block_at(&g, &guide, 0.0, offset, tilt), 0.0, &mut out);
            out.iter().map(|p| p.index).collect::<Vec<_>>()
        };
        assert_eq!(touching(0.0, 0.0), Vec::<usize>::new());
        assert_eq!(touching(0.0003, 0.0), vec![0, 1]);
        assert_eq!(touching(0.0, 0.02), vec![0, 2]);
    }
}
