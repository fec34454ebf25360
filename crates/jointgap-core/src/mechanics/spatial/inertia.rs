//! A spatial body's inertia about its centre of mass, as a user gives it (principal
//! moments with the orientation of their axes, or a full symmetric tensor in the
//! user's body frame), checked and brought to what the engine uses: principal moments
//! `(J1, J2, J3)` and the turn from the principal frame, which is the engine's body
//! frame, to the user's. In the principal frame the mass matrix is diagonal.

use nalgebra::{Rotation3, SymmetricEigen, UnitQuaternion};

use super::body::{Mat3, Orientation, Vec3};

/// How far, relative to the tensor's largest entry, its entries `J_ab` and `J_ba` may
/// differ: a tensor given in full writes each product of inertia twice, and numbers
/// that differ beyond their rounding are a typing mistake, not a tensor. The two are
/// averaged.
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// How far, relative to the largest moment, `J1 + J2` may fall short of `J3`: a flat
/// plate or disc has `J1 + J2 = J3` exactly, which its numbers keep only up to their
/// rounding (in binary, or through an eigen decomposition of a turned tensor). No
/// rigid body falls short by more.
pub const TRIANGLE_TOLERANCE: f64 = 1e-9;

/// A body's inertia about its centre of mass in its principal frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalInertia {
    /// Principal moments `(J1, J2, J3)` [kg m^2], about the principal frame's x, y, z.
    pub moments: Vec3,
    /// The turn from the principal frame to the frame the user gave the inertia in: a
    /// principal-frame vector `s'` is `frame * s'` in the user's frame.
    pub frame: Orientation,
}

impl PrincipalInertia {
    /// Principal `moments` [kg m^2] about the axes of `frame` (their orientation in the
    /// user's body frame), checked: finite, positive, and the triangle inequality.
    pub fn from_principal(moments: Vec3, frame: Orientation) -> Result<Self, String> {
        if let Some(bad) = moments.iter().find(|j| !(j.is_finite() && **j > 0.0)) {
            return Err(format!(
                "the principal moments of inertia {:?} kg m^2 hold {bad}: each must be positive (a body \
                 with no moment about an axis, a thin rod, turns about it without resistance)",
                moments.as_slice()
            ));
        }
        check_triangle(&moments)?;
        Ok(PrincipalInertia { moments, frame })
    }

    /// The inertia tensor `j` [kg m^2] about the centre of mass in the user's body frame,
    /// checked (symmetric, positive definite, triangle inequality) and split by nalgebra's
    /// symmetric eigen decomposition into principal moments and axes. Each principal axis
    /// is the user's axis it lies closest to, pointing its way, so that a tensor that is
    /// already diagonal keeps the user's frame and its moments' order.
    pub fn from_tensor(j: &Mat3) -> Result<Self, String> {
        let entries = j.as_slice();
        if let Some(bad) = entries.iter().find(|x| !x.is_finite()) {
            return Err(format!("the inertia tensor {} holds {bad}", rows(j)));
        }
        let largest = entries.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            if (j[(a, b)] - j[(b, a)]).abs() > SYMMETRY_TOLERANCE * largest {
                return Err(format!(
                    "the inertia tensor {} is not symmetric: entry ({}, {}) is {} but entry ({}, {}) is {}",
                    rows(j),
                    a + 1,
                    b + 1,
                    j[(a, b)],
                    b + 1,
                    a + 1,
                    j[(b, a)]
                ));
            }
        }
        let eigen = SymmetricEigen::new((j + j.transpose()) * 0.5);
        if eigen.eigenvalues.iter().any(|&m| m <= 0.0) {
            return Err(format!(
                "the inertia tensor {} is not positive definite: its principal moments are {:?} kg m^2",
                rows(j),
                eigen.eigenvalues.as_slice()
            ));
        }
        // Column `order[k]` of the eigenvectors becomes principal axis k.
        let v = eigen.eigenvectors;
        let orders = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        let closeness = |o: &[usize; 3]| (0..3).map(|k| v[(k, o[k])].abs()).sum::<f64>();
        let order = orders.iter().max_by(|a, b| closeness(a).total_cmp(&closeness(b))).expect("six orders");
        let mut axes = Mat3::from_fn(|r, k| v[(r, order[k])] * v[(k, order[k])].signum());
        if axes.determinant() < 0.0 {
            // A left-handed triad: turn round the axis that lies farthest from its own.
            let k = (0..3).min_by(|&a, &b| axes[(a, a)].total_cmp(&axes[(b, b)])).expect("three axes");
            axes.column_mut(k).neg_mut();
        }
        let frame = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(axes));
        let moments = Vec3::from_fn(|k, _| eigen.eigenvalues[order[k]]);
        check_triangle(&moments).map_err(|e| format!("the inertia tensor {}: {e}", rows(j)))?;
        Ok(PrincipalInertia { moments, frame: Orientation::new_normalize(frame.into_inner()) })
    }

    /// The inertia tensor in the user's frame, `R diag(J) R^T` with `R` the frame's
    /// rotation matrix.
    pub fn tensor(&self) -> Mat3 {
        let r = self.frame.to_rotation_matrix().into_inner();
        r * Mat3::from_diagonal(&self.moments) * r.transpose()
    }
}

/// Checks that each principal moment is at most the sum of the other two (within
/// [`TRIANGLE_TOLERANCE`]): `J3 = integral of (x^2 + y^2) dm <= J1 + J2 = integral of
/// (x^2 + y^2 + 2 z^2) dm`, true of any mass distribution. Moments that break it belong to
/// no rigid body: a typing mistake or moments about different points.
fn check_triangle(moments: &Vec3) -> Result<(), String> {
    let largest = moments.max();
    for k in 0..3 {
        let others = moments[(k + 1) % 3] + moments[(k + 2) % 3];
        if moments[k] - others > TRIANGLE_TOLERANCE * largest {
            return Err(format!(
                "the principal moments of inertia {:?} kg m^2 break the triangle inequality: J{} = {} \
                 is more than the sum {others} of the other two, which no rigid body has",
                moments.as_slice(),
                k + 1,
                moments[k]
            ));
        }
    }
    Ok(())
}

/// A tensor's rows, for an error message.
fn rows(j: &Mat3) -> String {
    let row = |r: usize| format!("[{}, {}, {}]", j[(r, 0)], j[(r, 1)], j[(r, 2)]);
    format!("[{}, {}, {}] kg m^2", row(0), row(1), row(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tensor built from known moments and a known turn splits into those moments
    /// and a frame that rebuilds it; each principal axis found is one of the turn's axes
    /// (up to order and sign), the one with the same moment.
    #[test]
    fn a_turned_tensor_gives_its_moments_and_axes_back() {
        let moments = Vec3::new(0.4, 1.1, 1.3);
        let turn = Orientation::from_scaled_axis(Vec3::new(0.5, -0.8, 1.9));
        let j = PrincipalInertia { moments, frame: turn }.tensor();
        let found = PrincipalInertia::from_tensor(&j).unwrap();
        let mut sorted = found.moments;
        sorted.as_mut_slice().sort_by(f64::total_cmp);
        assert!((sorted - moments).norm() < 1e-14, "moments {:?}", found.moments);
        assert!((found.tensor() - j).norm() < 1e-14, "rebuilt {}", found.tensor());
        for k in 0..3 {
            let axis = found.frame * Vec3::ith(k, 1.0);
            let m = (0..3).find(|&m| (moments[m] - found.moments[k]).abs() < 1e-12).unwrap();
            let along = (turn * Vec3::ith(m, 1.0)).dot(&axis);
            assert!((along.abs() - 1.0).abs() < 1e-13, "axis {k} lies along the turn's axis {m}: {along}");
        }
        let norm = found.frame.quaternion().norm();
        assert!((norm - 1.0).abs() <= f64::EPSILON);
        // two moments equal: any axes in their plane are principal; the tensor rebuilds
        let j = PrincipalInertia { moments: Vec3::new(0.7, 0.7, 1.2), frame: turn }.tensor();
        let found = PrincipalInertia::from_tensor(&j).unwrap();
        assert!((found.tensor() - j).norm() < 1e-14, "rebuilt {}", found.tensor());
    }

    /// A diagonal tensor keeps the user's frame and order, also where two moments are
    /// one (a symmetric body) and after a slight turn (principal axes near the user's).
    #[test]
    fn a_diagonal_tensor_keeps_the_users_frame() {
        for moments in [Vec3::new(3.0, 2.0, 1.5), Vec3::new(2.0, 2.0, 1.0)] {
            let found = PrincipalInertia::from_tensor(&Mat3::from_diagonal(&moments)).unwrap();
            assert_eq!(found.moments, moments);
            assert!(found.frame.angle() < 1e-15, "{:?}", found.frame);
        }
        let slight = Orientation::from_scaled_axis(Vec3::new(0.01, -0.02, 0.03));
        let j = PrincipalInertia { moments: Vec3::new(3.0, 2.0, 1.5), frame: slight }.tensor();
        let found = PrincipalInertia::from_tensor(&j).unwrap();
        assert!((found.moments - Vec3::new(3.0, 2.0, 1.5)).norm() < 1e-14, "{:?}", found.moments);
        assert!(found.frame.angle_to(&slight) < 1e-14, "{:?}", found.frame);
    }

    /// A thin disc (`J1 + J2 = J3` exactly), turned so that its numbers are rounded,
    /// passes; a rod with no moment about its axis does not.
    #[test]
    fn a_flat_disc_passes_and_a_thin_rod_does_not() {
        let (m, r) = (2.0, 0.3);
        let disc = Vec3::new(m * r * r / 4.0, m * r * r / 4.0, m * r * r / 2.0);
        let turn = Orientation::from_scaled_axis(Vec3::new(0.3, 1.2, -0.7));
        assert!(PrincipalInertia::from_principal(disc, turn).is_ok());
        let j = PrincipalInertia { moments: disc, frame: turn }.tensor();
        let found = PrincipalInertia::from_tensor(&j).unwrap();
        assert!((found.moments.sum() - disc.sum()).abs() < 1e-15);
        let rod = Vec3::new(0.0, 0.1, 0.1);
        let e = PrincipalInertia::from_principal(rod, Orientation::identity()).unwrap_err();
        assert!(e.contains("[0.0, 0.1, 0.1]") && e.contains("positive"), "{e}");
    }

    /// Each bad tensor is an error naming its values.
    #[test]
    fn bad_tensors_are_errors_naming_the_values() {
        let expect = |j: Mat3, what: &[&str]| {
            let e = PrincipalInertia::from_tensor(&j).unwrap_err();
            for w in what {
                assert!(e.contains(w), "{e:?} names {w:?}");
            }
        };
        let asymmetric = Mat3::new(1.0, 0.1, 0.0, 0.2, 1.0, 0.0, 0.0, 0.0, 1.0);
        expect(asymmetric, &["not symmetric", "(1, 2) is 0.1", "(2, 1) is 0.2"]);
        // positive diagonal, but principal moments -1, 3, 1
        let indefinite = Mat3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        expect(indefinite, &["not positive definite", "[[1, 2, 0], [2, 1, 0], [0, 0, 1]]"]);
        let too_large = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 2.5));
        expect(too_large, &["triangle inequality", "J3 = 2.5", "sum 2"]);
        expect(Mat3::from_diagonal(&Vec3::new(1.0, f64::NAN, 1.0)), &["NaN"]);
        let e =
            PrincipalInertia::from_principal(Vec3::new(0.5, 2.0, 1.0), Orientation::identity()).unwrap_err();
        assert!(e.contains("J2 = 2") && e.contains("sum 1.5"), "{e}");
    }
}
