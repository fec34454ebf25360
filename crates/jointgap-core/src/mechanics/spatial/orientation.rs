//! Orientations from what a user writes (an axis and an angle, Euler angles in a named
//! convention, a quaternion), each checked with an error that names the value, and
//! back to Euler angles for the outputs. An orientation turns a frame's vectors into
//! its parent's axes (a body frame into global axes).

use nalgebra::{Quaternion, Unit};

use super::body::{Orientation, Vec3};

/// How far from unit length a quaternion may be and still be taken as meant to be unit
/// (and normalised): 1e-3, so that entries written to four decimals pass
/// (`(0.7071, 0, 0, 0.7071)` is 1e-5 short) while a quaternion that is not one (angles
/// or an axis typed in its place) does not.
pub const QUATERNION_TOLERANCE: f64 = 1e-3;

/// Within this angle [rad] of gimbal lock (the middle angle 0 or pi for a proper
/// sequence, +-pi/2 for a Tait-Bryan one) the first and third axes turn about one line,
/// and only the sum or difference of their angles is defined; [`EulerConvention::angles`]
/// then sets the third angle to zero. Well above the rounding of the angles
/// (`1e-16 rad`), well below any angle a mechanism is meant to hold.
pub const GIMBAL_LOCK: f64 = 1e-12;

/// The orientation that turns by `angle` [rad] about `axis` (of any nonzero length,
/// right-handed).
pub fn from_axis_angle(axis: &Vec3, angle: f64) -> Result<Orientation, String> {
    if !angle.is_finite() {
        return Err(format!("the angle {angle} is not a number"));
    }
    let n = axis.norm();
    if !n.is_finite() || n == 0.0 {
        return Err(format!("the rotation axis {:?} has no direction (length {n})", axis.as_slice()));
    }
    Ok(Orientation::from_axis_angle(&Unit::new_unchecked(axis / n), angle))
}

/// The orientation of the quaternion `e = (e0, e1, e2, e3)`, scalar first (Euler
/// parameters): normalised when within [`QUATERNION_TOLERANCE`] of unit length, an
/// error otherwise.
pub fn from_quaternion(e: [f64; 4]) -> Result<Orientation, String> {
    let q = Quaternion::new(e[0], e[1], e[2], e[3]);
    let n = q.norm();
    if !n.is_finite() || (n - 1.0).abs() > QUATERNION_TOLERANCE {
        return Err(format!(
            "the quaternion {e:?} has length {n}, not 1 (within {QUATERNION_TOLERANCE}): it must be \
             (cos(angle/2), sin(angle/2) axis), scalar first"
        ));
    }
    Ok(Orientation::new_normalize(q))
}

/// Names of the Euler conventions: intrinsic sequences, each axis turning about the
/// frame the turns before it made (`ZYX`: yaw about z, then pitch about the new y, then
/// roll about the newest x; the same as turns about the fixed x, y, z axes by roll, pitch,
/// yaw: URDF's `rpy = (r, p, y)` is `ZYX` with the angles `(y, p, r)`).
pub const EULER_CONVENTIONS: [&str; 12] =
    ["ZYX", "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZXZ", "XYX", "XZX", "YXY", "YZY", "ZYZ"];

/// A sequence of three intrinsic turns `A = R_a(alpha) R_b(beta) R_c(gamma)` about
/// axes `a`, `b`, `c` (x = 0, y = 1, z = 2): Tait-Bryan where all three differ (`ZYX`),
/// proper Euler where the first and the last are one (`ZXZ`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EulerConvention {
    axes: [usize; 3],
}

impl EulerConvention {
    /// Yaw about z, pitch about the turned y, roll about the twice-turned x: the
    /// convention of the outputs (and of URDF's `rpy`, angles reversed).
    pub const ZYX: EulerConvention = EulerConvention { axes: [2, 1, 0] };

    /// The convention named `name`, one of [`EULER_CONVENTIONS`] (capitals: intrinsic).
    pub fn parse(name: &str) -> Result<Self, String> {
        let axis = |c: char| "XYZ".find(c);
        let axes: Vec<Option<usize>> = name.chars().map(axis).collect();
        match axes[..] {
            [Some(a), Some(b), Some(c)] if a != b && b != c => Ok(EulerConvention { axes: [a, b, c] }),
            _ => Err(format!(
                "unknown Euler convention {name:?}: the known ones are the intrinsic sequences {}",
                EULER_CONVENTIONS.join(", ")
            )),
        }
    }

    /// The convention's name (`"ZYX"`).
    pub fn name(&self) -> String {
        self.axes.iter().map(|&k| ['X', 'Y', 'Z'][k]).collect()
    }

    /// The orientation of Euler angles `angles = (alpha, beta, gamma)` [rad] in this
    /// convention: `R_a(alpha) R_b(beta) R_c(gamma)`.
    pub fn orientation(&self, angles: [f64; 3]) -> Result<Orientation, String> {
        if let Some(bad) = angles.iter().find(|a| !a.is_finite()) {
            return Err(format!("the {} Euler angles {angles:?} hold {bad}, not a number", self.name()));
        }
        let turn = |k: usize| Orientation::from_axis_angle(&Vec3::ith_axis(self.axes[k]), angles[k]);
        Ok(turn(0) * turn(1) * turn(2))
    }

    /// The Euler angles `(alpha, beta, gamma)` [rad] of `orientation` in this
    /// convention: `alpha`, `gamma` in `[-pi, pi]`; `beta` in `[0, pi]` (proper) or
    /// `[-pi/2, pi/2]` (Tait-Bryan). At gimbal lock (within [`GIMBAL_LOCK`]) `gamma`
    /// is zero and `alpha` carries the turn.
    ///
    /// The quaternion route of Bernardes and Viollet, "Quaternion to Euler angles
    /// conversion: a direct, general and computationally efficient method", PLoS ONE
    /// 17(11), 2022: the intrinsic sequence read as the extrinsic one backwards, a
    /// Tait-Bryan sequence as a proper one by a turn of pi/2, and the middle angle and
    /// the half sum and difference of the outer ones from two `atan2`, which hold no
    /// square root of a difference and no division, so no NaN near the lock.
    pub fn angles(&self, orientation: &Orientation) -> [f64; 3] {
        // Extrinsic order: the last intrinsic axis first.
        let (i, j) = (self.axes[2], self.axes[1]);
        let proper = self.axes[0] == self.axes[2];
        let k = if proper { 3 - i - j } else { self.axes[0] };
        // +1 where (i, j, k) is an even permutation of (x, y, z), -1 where odd.
        let sign = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
        let e = orientation.quaternion();
        let v = [e.i, e.j, e.k];
        let (a, b, c, d) = if proper {
            (e.w, v[i], v[j], sign * v[k])
        } else {
            (e.w - v[j], v[i] + sign * v[k], v[j] + e.w, sign * v[k] - v[i])
        };
        let (ab, cd) = (a.hypot(b), c.hypot(d));
        let middle = 2.0 * cd.atan2(ab);
        let beta = if proper { middle } else { middle - std::f64::consts::FRAC_PI_2 };
        if cd <= GIMBAL_LOCK * ab || ab <= GIMBAL_LOCK * cd {
            // gamma = 0: alpha is the turn left about the first axis once beta is undone.
            let rest = orientation * Orientation::from_axis_angle(&Vec3::ith_axis(j), -beta);
            let r = rest.quaternion();
            let alpha = 2.0 * [r.i, r.j, r.k][self.axes[0]].atan2(r.w);
            return [wrap(alpha), beta, 0.0];
        }
        let (half_sum, half_difference) = (b.atan2(a), d.atan2(c));
        let first = half_sum - half_difference;
        let mut third = half_sum + half_difference;
        if !proper {
            third *= sign;
        }
        [wrap(third), beta, wrap(first)]
    }
}

/// `angle` brought into `[-pi, pi]`.
fn wrap(angle: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if angle > PI {
        angle - TAU
    } else if angle < -PI {
        angle + TAU
    } else {
        angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// The turn between two orientations [rad].
    fn apart(a: &Orientation, b: &Orientation) -> f64 {
        a.angle_to(b)
    }

    /// Every convention reads back the angles it was built from, and the orientation
    /// from the angles it reads, over a spread of angles (the outer ones beyond pi/2,
    /// negative middle angles for Tait-Bryan): each check against nalgebra's product of
    /// the three axis turns, written apart from the quaternion route of `angles`.
    #[test]
    fn every_convention_round_trips() {
        let samples: [[f64; 3]; 5] =
            [[0.3, 0.4, -0.5], [2.9, 1.2, -2.4], [-1.7, 0.05, 3.0], [0.0, 2.5, 1.0], [-3.0, -1.1, 0.2]];
        for name in EULER_CONVENTIONS {
            let convention = EulerConvention::parse(name).unwrap();
            assert_eq!(convention.name(), name);
            let proper = name.as_bytes()[0] == name.as_bytes()[2];
            for angles in samples {
                // the angles in the convention's range
                let angles = if proper {
                    [angles[0], angles[1].abs(), angles[2]]
                } else {
                    [angles[0], angles[1].clamp(-1.5, 1.5), angles[2]]
                };
                let o = convention.orientation(angles).unwrap();
                let back = convention.angles(&o);
                for k in 0..3 {
                    assert!((back[k] - angles[k]).abs() < 1e-12, "{name} {angles:?}: read {back:?}");
                }
                let again = convention.orientation(back).unwrap();
                assert!(apart(&o, &again) < 1e-14, "{name} {angles:?}");
            }
        }
    }

    /// At gimbal lock and a hair from it the angles give back the orientation, hold no
    /// NaN, and at the lock set the third angle to zero.
    #[test]
    fn gimbal_lock_gives_angles_without_nan() {
        for name in EULER_CONVENTIONS {
            let convention = EulerConvention::parse(name).unwrap();
            let proper = name.as_bytes()[0] == name.as_bytes()[2];
            let locks = if proper { [0.0, PI] } else { [FRAC_PI_2, -FRAC_PI_2] };
            for lock in locks {
                for off in [0.0, 1e-13, -1e-13, 1e-9, -1e-9] {
                    let beta = if proper { (lock + off).abs().min(PI) } else { lock + off };
                    let o = convention.orientation([0.7, beta, -0.4]).unwrap();
                    let back = convention.angles(&o);
                    assert!(back.iter().all(|a| a.is_finite()), "{name} at {beta}: {back:?}");
                    let again = convention.orientation(back).unwrap();
                    assert!(
                        apart(&o, &again) < 1e-12,
                        "{name} at {beta}: {back:?} turn {:e}",
                        apart(&o, &again)
                    );
                    if off == 0.0 {
                        assert_eq!(back[2], 0.0, "{name} at the lock {beta}: {back:?}");
                    }
                }
            }
        }
    }

    /// A quarter turn about z given each way is one orientation, and turns x into y;
    /// one of the ways is a quaternion written to four decimals, as a user would.
    #[test]
    #[allow(clippy::approx_constant)]
    fn a_quarter_turn_about_z_agrees_in_every_form() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let forms = [
            from_axis_angle(&Vec3::new(0.0, 0.0, 2.0), FRAC_PI_2).unwrap(),
            from_quaternion([s, 0.0, 0.0, s]).unwrap(),
            from_quaternion([0.7071, 0.0, 0.0, 0.7071]).unwrap(),
            EulerConvention::parse("ZYX").unwrap().orientation([FRAC_PI_2, 0.0, 0.0]).unwrap(),
            EulerConvention::parse("XYZ").unwrap().orientation([0.0, 0.0, FRAC_PI_2]).unwrap(),
            EulerConvention::parse("ZXZ").unwrap().orientation([0.5, 0.0, FRAC_PI_2 - 0.5]).unwrap(),
        ];
        for (k, o) in forms.iter().enumerate() {
            let x = o * Vec3::x();
            assert!((x - Vec3::y()).norm() < 1e-4, "form {k}: x goes to {x:?}");
            assert!(apart(o, &forms[0]) < if k == 2 { 1e-4 } else { 1e-15 }, "form {k}");
        }
        assert_eq!(EulerConvention::parse("ZYX").unwrap().angles(&forms[0]), [FRAC_PI_2, 0.0, 0.0]);
        // yaw-pitch-roll: yaw about z first, then pitch about the new y, which is the old -x
        let ypr = EulerConvention::parse("ZYX").unwrap().orientation([FRAC_PI_2, FRAC_PI_2, 0.0]).unwrap();
        assert!((ypr * Vec3::x() - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-15, "pitch turns the nose down");
    }

    /// Each bad value is an error that names it.
    #[test]
    fn bad_orientations_are_errors_naming_the_value() {
        let expect = |r: Result<Orientation, String>, what: &str| {
            let e = r.expect_err(what);
            assert!(e.contains(what), "{e:?} names {what:?}");
        };
        expect(from_axis_angle(&Vec3::zeros(), 1.0), "[0.0, 0.0, 0.0]");
        expect(from_axis_angle(&Vec3::z(), f64::NAN), "NaN");
        expect(from_quaternion([0.0; 4]), "length 0");
        expect(from_quaternion([0.0, 0.0, 0.0, 90.0]), "90.0");
        expect(from_quaternion([1.0, 0.0, 0.1, 0.0]), "1.00498");
        expect(EulerConvention::parse("zyx").map(|_| Orientation::identity()), "\"zyx\"");
        expect(EulerConvention::parse("ZZX").map(|_| Orientation::identity()), "ZYX, XYZ");
        expect(EulerConvention::parse("ZYXZ").map(|_| Orientation::identity()), "ZXZ");
        expect(EulerConvention::parse("XYZ").unwrap().orientation([0.0, f64::INFINITY, 0.0]), "inf");
    }
}
