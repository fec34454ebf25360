//! Checks every spatial contact geometry must pass, written apart from the kernels: the
//! rate and slip against differences of placements as the bodies move, and the
//! material points' arms against virtual work along small body motions.

use crate::mechanics::contact::point3::{ContactPoint3, ContactPoints3};
use crate::mechanics::spatial::body::{BodyState, Orientation, Vec3};

/// A geometry's kernel at all reach: the bodies' states (i, j) to their points.
pub type Kernel<'a> = dyn Fn(&BodyState, &BodyState) -> ContactPoints3 + 'a;

/// The body `b` after time `dt` at its constant velocities: `r + v dt`, orientation
/// `e exp(w' dt)` (`w'` in the body frame, so it acts on the right).
pub fn moving(b: &BodyState, dt: f64) -> BodyState {
    BodyState::new(
        b.r + b.v * dt,
        b.orientation() * Orientation::from_scaled_axis(b.omega * dt),
        b.v,
        b.omega,
    )
}

/// The body `b` displaced by `dr` (global) and turned by the small rotation `dpi` (body
/// frame): `e exp(dpi')`.
fn displaced(b: &BodyState, dr: Vec3, dpi: Vec3) -> BodyState {
    BodyState::new(b.r + dr, b.orientation() * Orientation::from_scaled_axis(dpi), b.v, b.omega)
}

/// The point of index `k` among `points`.
fn find(points: &ContactPoints3, k: usize) -> ContactPoint3 {
    *points.iter().find(|p| p.index == k).unwrap_or_else(|| panic!("no point {k}"))
}

/// For each of the `count` points of `kernel` at the states `i`, `j`: its penetration
/// rate against the central difference of its penetration as the bodies move, and its
/// slip against the relative velocity of its two material points (each followed as a
/// point fixed in its body, by differences) less that velocity's normal part. Step 1e-8
/// s: the difference's truncation (`h^2/6` times the third derivative, about `v^3/|e|^2`
/// for speeds `v` of 1 m/s at a quarter-millimetre eccentricity) and round-off (1e-16 of
/// positions of 0.3 m over `2 h`) stay near 1e-9 m/s, far below the 1e-7 m/s
/// tolerance, which a rate of the wrong sign or a missing term of size `w x arm` (here
/// above 1e-3 m/s) would exceed.
pub fn check_rate_and_slip_by_motion(i: &BodyState, j: &BodyState, kernel: &Kernel, count: usize) {
    let h = 1e-8;
    let now = kernel(i, j);
    assert_eq!(now.len(), count);
    let (ahead, behind) = (kernel(&moving(i, h), &moving(j, h)), kernel(&moving(i, -h), &moving(j, -h)));
    for p in now.iter() {
        let k = p.index;
        let fd = (find(&ahead, k).penetration - find(&behind, k).penetration) / (2.0 * h);
        assert!((p.penetration_rate - fd).abs() < 1e-7, "point {k}: rate {} vs {fd}", p.penetration_rate);
        // Each material point fixed in its body, followed by central differences.
        let follow = |b: &BodyState, at: Vec3| {
            let s = b.a.transpose() * (at - b.r);
            let place = |dt: f64| {
                let m = moving(b, dt);
                m.r + m.a * s
            };
            (place(h) - place(-h)) / (2.0 * h)
        };
        let v = follow(j, p.on_j.at) - follow(i, p.on_i.at);
        let slip = v - p.normal * v.dot(&p.normal);
        assert!((p.slip - slip).norm() < 1e-7, "point {k}: slip {:?} vs {slip:?}", p.slip);
        assert!(p.slip.dot(&p.normal).abs() < 1e-12 * v.norm().max(1.0), "point {k}: slip along n");
        assert!((p.normal.norm() - 1.0).abs() < 1e-12, "point {k}: normal not unit");
    }
}

/// For each of the `count` points of `kernel` at the states `i`, `j`: the loads of its
/// normal force against virtual work. A normal force `F` (`-F n` at body j's point,
/// `+F n` at body i's) derives from the potential `U(delta)`, `dU/d delta = F`, only if
/// its generalized force on each body equals `-F` times the penetration's gradient:
/// along body j's translation `-F n`, along its virtual rotation `dpi'` (body frame)
/// `A_j^T (arm_j x (-F n))`, and the opposites with body i's arm for body i. So the
/// gradient, by central differences over each body's `dr` and `dpi'` (1e-8 m, 1e-8
/// rad: the truncation, about `h^2 / (6 |d|^2)` at an offset `|d|` of 50 um, stays
/// below 1e-9), must be `n`, `A_j^T (arm_j x n)`, `-n`, `-A_i^T (arm_i x n)`; the
/// tolerance 1e-7 m/rad is far below the arms (centimetres).
pub fn check_arms_by_virtual_work(i: &BodyState, j: &BodyState, kernel: &Kernel, count: usize) {
    let h = 1e-8;
    let now = kernel(i, j);
    assert_eq!(now.len(), count);
    for p in now.iter() {
        let k = p.index;
        let gradient = |on_j: bool, rotate: bool| -> Vec3 {
            Vec3::from_fn(|axis, _| {
                let depth = |step: f64| {
                    let mut d = Vec3::zeros();
                    d[axis] = step;
                    let (dr, dpi) = if rotate { (Vec3::zeros(), d) } else { (d, Vec3::zeros()) };
                    let points = if on_j {
                        kernel(i, &displaced(j, dr, dpi))
                    } else {
                        kernel(&displaced(i, dr, dpi), j)
                    };
                    find(&points, k).penetration
                };
                (depth(h) - depth(-h)) / (2.0 * h)
            })
        };
        let n = p.normal;
        let expected = [
            (true, false, n),
            (true, true, j.a.transpose() * p.on_j.arm.cross(&n)),
            (false, false, -n),
            (false, true, -(i.a.transpose() * p.on_i.arm.cross(&n))),
        ];
        for (on_j, rotate, want) in expected {
            let got = gradient(on_j, rotate);
            assert!(
                (got - want).norm() < 1e-7,
                "point {k}, body {}, {}: gradient {got:?} vs {want:?}",
                if on_j { "j" } else { "i" },
                if rotate { "rotation" } else { "translation" }
            );
        }
    }
}
