//! Measures: the kinematics a run reports beyond the bodies' own coordinates. A marker's
//! position, velocity and acceleration in the ground frame or in a body's frame, and
//! the coordinate of each revolute and prismatic joint with its rate
//! ([outputs](../../../docs/outputs.md)).

use crate::math::{perp, Vec2};
use crate::mechanics::planar_body::BodyState;
use crate::system::{JointInfo, MarkerInfo};

/// A body's position, velocity and acceleration (the ground: all zero).
#[derive(Debug, Clone, Copy, Default)]
pub struct BodyMotion {
    /// Position and velocity.
    pub state: BodyState,
    /// Acceleration of the centre of mass [m/s^2].
    pub acceleration: Vec2,
    /// Angular acceleration [rad/s^2].
    pub alpha: f64,
}

impl BodyMotion {
    /// Position, velocity and acceleration [m, m/s, m/s^2] of the body-frame point `s`,
    /// global axes: `r + A s`, `v + omega perp(A s)`, `a + alpha perp(A s) - omega^2 A s`.
    pub fn point(&self, s: Vec2) -> [Vec2; 3] {
        let b = &self.state;
        let arm = b.rotate(s);
        [
            b.r + arm,
            b.v + perp(arm) * b.omega,
            self.acceleration + perp(arm) * self.alpha - arm * (b.omega * b.omega),
        ]
    }

    /// A global motion `[p, p', p'']` as an observer riding this body sees it: the
    /// coordinates `A^T d` of `d = p - r` in the body's frame and their time derivatives,
    /// `A^T (d' - omega perp(d))` and
    /// `A^T (d'' - alpha perp(d) - 2 omega perp(d') - omega^2 d)`.
    pub fn observe(&self, [p, pd, pdd]: [Vec2; 3]) -> [Vec2; 3] {
        let b = &self.state;
        let (d, dd, ddd) = (p - b.r, pd - b.v, pdd - self.acceleration);
        let w = b.omega;
        let back = |x: Vec2| crate::math::rotate(-b.phi(), x);
        [
            back(d),
            back(dd - perp(d) * w),
            back(ddd - perp(d) * self.alpha - perp(dd) * (2.0 * w) - d * (w * w)),
        ]
    }
}

/// Position, velocity and acceleration of a marker in its frame, from the motion of its
/// body and of its frame's body.
pub fn marker_motion(marker: &MarkerInfo, body: &BodyMotion, frame: &BodyMotion) -> [Vec2; 3] {
    let global = body.point(marker.s);
    match marker.frame {
        None => global,
        Some(_) => frame.observe(global),
    }
}

/// The coordinate of a revolute (also clearance revolute) or prismatic joint and its
/// rate; `None` for a fixed joint. Revolute: the relative angle `phi_j - phi_i` [rad] and
/// `omega_j - omega_i` [rad/s]. Prismatic: the travel `u . d` [m] of point j from point i
/// along the axis `u` (turning with body i) and its rate `u . d' + omega_i perp(u) . d`
/// [m/s]. Both are the coordinates a driver of the joint prescribes.
pub fn joint_coordinate(j: &JointInfo, bi: &BodyState, bj: &BodyState) -> Option<(f64, f64)> {
    match j.kind.coordinate()? {
        true => Some((bj.phi() - bi.phi(), bj.omega - bi.omega)),
        false => {
            let u = bi.rotate(j.axis?);
            let (arm_i, arm_j) = (bi.rotate(j.s_i), bj.rotate(j.s_j));
            let d = bj.r + arm_j - bi.r - arm_i;
            let dd = bj.v + perp(arm_j) * bj.omega - bi.v - perp(arm_i) * bi.omega;
            Some((u.dot(&d), u.dot(&dd) + perp(u).dot(&d) * bi.omega))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::JointKind;

    /// Observed motion against central differences of the observed position, for a
    /// point and a frame both moving with constant acceleration.
    #[test]
    fn observed_rates_are_derivatives_of_observed_position() {
        let motion_at = |t: f64, r0: Vec2, v0: Vec2, a: Vec2, phi0: f64, w0: f64, alpha: f64| BodyMotion {
            state: BodyState::new(
                r0 + v0 * t + a * (0.5 * t * t),
                phi0 + w0 * t + 0.5 * alpha * t * t,
                v0 + a * t,
                w0 + alpha * t,
            ),
            acceleration: a,
            alpha,
        };
        let body = |t| {
            motion_at(t, Vec2::new(0.3, -0.1), Vec2::new(1.2, 0.4), Vec2::new(-2.0, 3.0), 0.7, 5.0, -40.0)
        };
        let frame = |t| {
            motion_at(t, Vec2::new(-0.2, 0.5), Vec2::new(-0.6, 0.9), Vec2::new(4.0, 1.0), -0.4, -3.0, 25.0)
        };
        let s = Vec2::new(0.05, -0.02);
        let seen = |t: f64| frame(t).observe(body(t).point(s));
        let (t, h) = (0.13, 1e-4);
        let [p, pd, pdd] = seen(t);
        let d1 = |k: usize| (seen(t + h)[k] - seen(t - h)[k]) / (2.0 * h);
        let fd_v = (seen(t - 2.0 * h)[0] - seen(t + 2.0 * h)[0] + (seen(t + h)[0] - seen(t - h)[0]) * 8.0)
            / (12.0 * h);
        assert!((fd_v - pd).norm() < 1e-9 * pd.norm(), "{fd_v} vs {pd}");
        assert!((d1(1) - pdd).norm() < 1e-6 * pdd.norm(), "{} vs {pdd}", d1(1));
        // Seen from its own body, a body point stands still.
        let own = body(t).observe(body(t).point(s));
        assert!((own[0] - s).norm() < 1e-15 && own[1].norm() < 1e-13 && own[2].norm() < 1e-11);
        assert!(p.norm() > 0.1);
    }

    /// The rates of a prismatic joint whose body i turns, and of a revolute joint,
    /// against central differences of their coordinates.
    #[test]
    fn joint_rates_are_derivatives_of_joint_coordinates() {
        let at =
            |t: f64, r0: Vec2, v: Vec2, phi0: f64, w: f64| BodyState::new(r0 + v * t, phi0 + w * t, v, w);
        let bi = |t| at(t, Vec2::new(0.1, 0.2), Vec2::new(0.5, -0.3), 0.3, 4.0);
        let bj = |t| at(t, Vec2::new(0.4, 0.1), Vec2::new(-0.2, 0.7), -0.2, -1.5);
        let joint = |kind, axis| JointInfo {
            name: "j".into(),
            kind,
            body_i: Some(0),
            body_j: Some(1),
            s_i: Vec2::new(0.03, -0.01),
            s_j: Vec2::new(-0.02, 0.04),
            axis,
            axis_j: None,
            rows: 0..0,
            clearance: None,
        };
        let (t, h) = (0.07, 1e-5);
        for j in [joint(JointKind::Prismatic, Some(Vec2::new(0.6, 0.8))), joint(JointKind::Revolute, None)] {
            let value = |t: f64| joint_coordinate(&j, &bi(t), &bj(t)).unwrap().0;
            let (_, rate) = joint_coordinate(&j, &bi(t), &bj(t)).unwrap();
            let fd = (value(t + h) - value(t - h)) / (2.0 * h);
            assert!((fd - rate).abs() < 1e-8 * rate.abs().max(1.0), "{:?}: {fd} vs {rate}", j.kind);
        }
        assert!(joint_coordinate(&joint(JointKind::Fixed, None), &bi(t), &bj(t)).is_none());
    }
}
