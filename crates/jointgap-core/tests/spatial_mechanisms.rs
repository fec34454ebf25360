//! Spatial mechanisms through the whole engine (model -> system -> run), each against an
//! independent computation written in this file: a free asymmetric body against the
//! closed-form (Jacobi elliptic) torque-free motion, given once by its principal moments
//! and once by its turned inertia tensor; a spatial four-bar RSSR against its loop
//! closure and the virtual work of its motor; drivers of prismatic, cylindrical and
//! revolute joints against their profiles and Newton's and Euler's laws; bad input
//! named by element and key.
#![allow(clippy::needless_range_loop)]

use jointgap_core::model::spatial::SpatialModel;
use jointgap_core::simulate::{simulate_spatial, Silent};
use jointgap_core::{SimOptions, SimResult, Status};
use serde_json::json;
use std::f64::consts::PI;

type V3 = [f64; 3];
type M3 = [[f64; 3]; 3];

fn run(model: serde_json::Value, t_end: f64, rate: f64, rtol: f64) -> SimResult {
    run_with(model, t_end, rate, rtol, None)
}

/// [`run`] with steps no longer than `max_step` [s].
fn run_with(model: serde_json::Value, t_end: f64, rate: f64, rtol: f64, max_step: Option<f64>) -> SimResult {
    let model = SpatialModel::from_json(&model.to_string()).expect("a valid model");
    let mut opts = SimOptions::new(t_end);
    opts.rate = Some(rate);
    opts.rtol = rtol;
    opts.atol = rtol * 1e-2;
    opts.max_step = max_step;
    let res = simulate_spatial(&model, &opts, &mut Silent).expect("a run");
    assert_eq!(res.status, Status::Finished, "{:?}", res.status);
    res
}

fn channel<'a>(res: &'a SimResult, name: &str) -> &'a [f64] {
    res.channel(name).unwrap_or_else(|| panic!("no channel {name} in {:?}", res.names))
}

/// A vector channel triple `<element>.<a>`, `.<b>`, `.<c>` at sample `k`.
fn vector(res: &SimResult, element: &str, quantities: [&str; 3], k: usize) -> V3 {
    quantities.map(|q| channel(res, &format!("{element}.{q}"))[k])
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: V3, s: f64) -> V3 {
    a.map(|x| x * s)
}

fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

fn unit(a: V3) -> V3 {
    scale(a, 1.0 / norm(a))
}

fn mat_vec(m: &M3, v: V3) -> V3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

fn transpose(m: &M3) -> M3 {
    [[m[0][0], m[1][0], m[2][0]], [m[0][1], m[1][1], m[2][1]], [m[0][2], m[1][2], m[2][2]]]
}

fn mat_mul(a: &M3, b: &M3) -> M3 {
    let bt = transpose(b);
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| dot(a[r], bt[c])))
}

/// The turn by `angle` about the unit `axis` (Rodrigues:
/// `R = cos I + sin [n]x + (1 - cos) n n^T`).
fn rodrigues(axis: V3, angle: f64) -> M3 {
    let n = unit(axis);
    let (s, c) = angle.sin_cos();
    let skew = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]];
    [0, 1, 2]
        .map(|r| [0, 1, 2].map(|k| (if r == k { c } else { 0.0 }) + s * skew[r][k] + (1.0 - c) * n[r] * n[k]))
}

/// The rotation matrix of the Euler parameters `e = (e0, e1, e2, e3)` (Nikravesh 1988,
/// eq. 6.19: `A = (2 e0^2 - 1) I + 2 (e e^T + e0 [e]x)`, vector part `e`).
fn rotation_of(e: [f64; 4]) -> M3 {
    let (e0, v) = (e[0], [e[1], e[2], e[3]]);
    let skew = [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
    [0, 1, 2].map(|r| {
        [0, 1, 2]
            .map(|k| (if r == k { 2.0 * e0 * e0 - 1.0 } else { 0.0 }) + 2.0 * (v[r] * v[k] + e0 * skew[r][k]))
    })
}

/// The Euler parameters of a body at sample `k`.
fn quaternion(res: &SimResult, body: &str, k: usize) -> [f64; 4] {
    ["e0", "e1", "e2", "e3"].map(|q| channel(res, &format!("{body}.{q}"))[k])
}

/// The quaternion `(cos(angle/2), sin(angle/2) n)` of a turn, scalar first.
fn quaternion_of(axis: V3, angle: f64) -> [f64; 4] {
    let n = unit(axis);
    let (s, c) = (0.5 * angle).sin_cos();
    [c, s * n[0], s * n[1], s * n[2]]
}

/// The Hamilton product `p q` of two quaternions, scalar first.
fn quaternion_product(p: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    let (p0, pv, q0, qv) = (p[0], [p[1], p[2], p[3]], q[0], [q[1], q[2], q[3]]);
    let v = add(add(scale(qv, p0), scale(pv, q0)), cross(pv, qv));
    [p0 * q0 - dot(pv, qv), v[0], v[1], v[2]]
}

/// The complete elliptic integral of the first kind of the complementary modulus
/// `k' = sqrt(1 - k^2)`: `K(k) = pi / (2 agm(1, k'))`.
fn complete_integral_of_complement(k_prime: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, k_prime);
    for _ in 0..60 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// `K(k)`.
fn complete_integral(k: f64) -> f64 {
    complete_integral_of_complement((1.0 - k * k).sqrt())
}

/// Jacobi's elliptic functions `(sn, cn, dn)` of `u`, modulus `k`, as ratios of theta
/// functions of nome `q = exp(-pi K'/K)` at `v = pi u / (2 K)` (DLMF 22.2.4-6, the
/// series 20.2.1-4), a route apart from the Landen transformation that
/// tests/spatial_body.rs takes.
fn jacobi_theta(u: f64, k: f64) -> (f64, f64, f64) {
    let (kk, kk_prime) = (complete_integral(k), complete_integral_of_complement(k));
    let q = (-PI * kk_prime / kk).exp();
    let v = PI * u / (2.0 * kk);
    let terms = 30;
    let theta1 = |v: f64| {
        2.0 * (0..terms)
            .map(|n| {
                let m = n as f64 + 0.5;
                (if n % 2 == 0 { 1.0 } else { -1.0 }) * q.powf(m * m) * ((2.0 * m) * v).sin()
            })
            .sum::<f64>()
    };
    let theta2 = |v: f64| {
        2.0 * (0..terms)
            .map(|n| {
                let m = n as f64 + 0.5;
                q.powf(m * m) * ((2.0 * m) * v).cos()
            })
            .sum::<f64>()
    };
    let theta3_4 = |v: f64, sign: f64| {
        1.0 + 2.0 * (1..terms).map(|n| sign.powi(n) * q.powi(n * n) * ((2 * n) as f64 * v).cos()).sum::<f64>()
    };
    let (t2_0, t3_0, t4_0) = (theta2(0.0), theta3_4(0.0, 1.0), theta3_4(0.0, -1.0));
    let (t1, t2, t3, t4) = (theta1(v), theta2(v), theta3_4(v, 1.0), theta3_4(v, -1.0));
    (t3_0 * t1 / (t2_0 * t4), t4_0 * t2 / (t2_0 * t4), t4_0 * t3 / (t3_0 * t4))
}

/// The theta-function route against the identities the functions obey: the modulus
/// back from the thetas (`k = theta2(0)^2 / theta3(0)^2`, through sn at the quarter
/// period), `sn^2 + cn^2 = 1`, `dn^2 + k^2 sn^2 = 1`, the quarter-period values, and
/// `d sn / du = cn dn`.
#[test]
fn theta_functions_give_jacobis_functions() {
    for k in [0.2, 0.9, 0.997_66] {
        let kk = complete_integral(k);
        let (sn, cn, dn) = jacobi_theta(kk, k);
        let k_prime = (1.0 - k * k).sqrt();
        assert!((sn - 1.0).abs() < 1e-13 && cn.abs() < 1e-13 && (dn - k_prime).abs() < 1e-13, "at K({k})");
        for u in [0.1, 0.8, 2.3, -1.4, 5.0] {
            let (sn, cn, dn) = jacobi_theta(u, k);
            assert!((sn * sn + cn * cn - 1.0).abs() < 1e-13, "sn^2 + cn^2 at {u}, {k}");
            assert!((dn * dn + k * k * sn * sn - 1.0).abs() < 1e-13, "dn^2 + k^2 sn^2 at {u}, {k}");
            let h = 1e-5;
            let derivative = (jacobi_theta(u + h, k).0 - jacobi_theta(u - h, k).0) / (2.0 * h);
            assert!((derivative - cn * dn).abs() < 1e-9, "sn' = cn dn at {u}, {k}");
        }
    }
    // Small k: sn = sin u - k^2 / 4 (u - sin u cos u) cos u + O(k^4) (Abramowitz and
    // Stegun 16.13.1), the correction 4e-8 here.
    let (k, u) = (1e-3, 0.7f64);
    let (sn, _, _) = jacobi_theta(u, k);
    let series = u.sin() - k * k / 4.0 * (u - u.sin() * u.cos()) * u.cos();
    assert!((sn - series).abs() < 1e-12, "sn({u}, {k}) = {sn} against the series {series}");
}

/// A free asymmetric body (no joints, no gravity; principal moments 0.010, 0.020,
/// 0.025 kg m^2) set spinning near its intermediate axis, `w' = (0, 6, 0.3)` rad/s in its
/// principal frame, turned and moving: over one period of its body rates (two flips) the
/// engine's body rates follow the closed form (Landau and Lifshitz, Mechanics, section
/// 37)
///
/// ```text
/// w1 = sqrt((2 E J3 - M^2) / (J1 (J3 - J1))) cn(tau)
/// w2 = sqrt((2 E J3 - M^2) / (J2 (J3 - J2))) sn(tau)
/// w3 = sqrt((M^2 - 2 E J1) / (J3 (J3 - J1))) dn(tau)
/// tau = K + sqrt((J3 - J2) (M^2 - 2 E J1) / (J1 J2 J3)) t
/// k^2 = (J2 - J1) (2 E J3 - M^2) / ((J3 - J2) (M^2 - 2 E J1))
/// ```
///
/// and the angular momentum in ground axes, `A J w'`, stays constant to 1e-10 relative,
/// the quaternion unit to 1e-12, the centre of mass on its straight line.
///
/// The same physical body is given a second time, beside it in the same model, by its
/// full inertia tensor in a user frame turned by a known `R` from the principal frame
/// (`J_user = R diag(J) R^T`, the body placed at `A0 R^T`, its points at `R p`): its
/// points (markers) move as the first body's, its global angular velocity is the first's,
/// and its angular momentum, from its markers' frame and its tensor, is as constant.
///
/// Measured at rtol 1e-13 (atol 1e-15): body rates within 2.0e-11 of `w2` of the closed
/// form, angular momentum drift 4.1e-11 (2.6e-10 at rtol 1e-12: the integrator's error,
/// hence the tighter tolerance), `|e| - 1` 2.2e-16, the twin's points within 5.4e-13 of
/// the arm and its angular velocity within 1.2e-13 of `w2`.
#[test]
fn a_free_body_flips_as_the_closed_form_says_whichever_way_its_inertia_is_given() {
    let (mass, j) = (3.0, [0.010, 0.020, 0.025]);
    let (w2, w3) = (6.0, 0.3);
    let turn_axis = [0.4, -0.3, 0.8];
    let a0 = rodrigues(turn_axis, norm(turn_axis));
    let e_a0 = quaternion_of(turn_axis, norm(turn_axis));
    // The user's frame of the second body: principal vectors s' are R s' there.
    let (user_axis, user_angle) = ([1.0, 2.0, -0.5], 1.1);
    let r = rodrigues(user_axis, user_angle);
    let tensor =
        mat_mul(&mat_mul(&r, &[[j[0], 0.0, 0.0], [0.0, j[1], 0.0], [0.0, 0.0, j[2]]]), &transpose(&r));
    let mut e_user = quaternion_of(user_axis, user_angle);
    e_user[1..].iter_mut().for_each(|x| *x = -*x);
    let e_b0 = quaternion_product(e_a0, e_user);
    let omega_global = mat_vec(&a0, [0.0, w2, w3]);
    let (r0, v0) = ([0.1, 0.2, -0.3], [0.5, -0.2, 0.3]);
    let arm = 0.1;
    let points: [V3; 3] = [[arm, 0.0, 0.0], [0.0, arm, 0.0], [0.0, 0.0, arm]];
    let user_points: Vec<V3> = points.iter().map(|p| mat_vec(&r, *p)).collect();
    let user_markers: Vec<V3> =
        (0..3).map(|c| scale([0, 1, 2].map(|k| (k == c) as u8 as f64), arm)).collect();
    let model = json!({
        "dimension": 3,
        "gravity": [0.0, 0.0, 0.0],
        "bodies": [
            {"name": "principal", "mass": mass, "inertia": {"principal": {"moments": j}},
             "position": r0, "velocity": v0, "orientation": {"quaternion": e_a0},
             "angular_velocity": omega_global},
            {"name": "tensor", "mass": mass, "inertia": {"tensor": tensor},
             "position": r0, "velocity": v0, "orientation": {"quaternion": e_b0},
             "angular_velocity": omega_global}
        ],
        "markers": [
            {"name": "p1", "body": "principal", "point": points[0]},
            {"name": "p2", "body": "principal", "point": points[1]},
            {"name": "p3", "body": "principal", "point": points[2]},
            {"name": "t1", "body": "tensor", "point": user_points[0]},
            {"name": "t2", "body": "tensor", "point": user_points[1]},
            {"name": "t3", "body": "tensor", "point": user_points[2]},
            {"name": "u1", "body": "tensor", "point": user_markers[0]},
            {"name": "u2", "body": "tensor", "point": user_markers[1]},
            {"name": "u3", "body": "tensor", "point": user_markers[2]}
        ]
    });

    // The closed form.
    let energy = 0.5 * (j[1] * w2 * w2 + j[2] * w3 * w3);
    let m2 = (j[1] * w2).powi(2) + (j[2] * w3).powi(2);
    assert!(m2 > 2.0 * energy * j[1], "the closed form's case: near the intermediate axis");
    let amplitude = [
        ((2.0 * energy * j[2] - m2) / (j[0] * (j[2] - j[0]))).sqrt(),
        ((2.0 * energy * j[2] - m2) / (j[1] * (j[2] - j[1]))).sqrt(),
        ((m2 - 2.0 * energy * j[0]) / (j[2] * (j[2] - j[0]))).sqrt(),
    ];
    let rate = ((j[2] - j[1]) * (m2 - 2.0 * energy * j[0]) / (j[0] * j[1] * j[2])).sqrt();
    let k =
        ((j[1] - j[0]) * (2.0 * energy * j[2] - m2) / ((j[2] - j[1]) * (m2 - 2.0 * energy * j[0]))).sqrt();
    let kk = complete_integral(k);
    let exact = |t: f64| {
        let (sn, cn, dn) = jacobi_theta(kk + rate * t, k);
        [amplitude[0] * cn, amplitude[1] * sn, amplitude[2] * dn]
    };
    assert!(norm(sub(exact(0.0), [0.0, w2, w3])) < 1e-12, "the start is the closed form's");
    let period = 4.0 * kk / rate;

    let res = run(model, period, 200.0, 1e-13);
    let n = res.time.len();
    let body_rates = |body: &str, k: usize| vector(&res, body, ["wx", "wy", "wz"], k);
    let h0 = mat_vec(&a0, [j[0] * 0.0, j[1] * w2, j[2] * w3]);
    let (mut rates_off, mut momentum_off, mut norm_off, mut line_off) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut twin_points_off, mut twin_omega_off, mut twin_momentum_off) = (0.0f64, 0.0f64, 0.0f64);
    let mut flipped = false;
    for k in 0..n {
        let t = res.time[k];
        let w = body_rates("principal", k);
        rates_off = rates_off.max(norm(sub(w, exact(t))) / w2);
        flipped |= w[1] < -0.9 * w2;
        let e = quaternion(&res, "principal", k);
        let a = rotation_of(e);
        let h = mat_vec(&a, [j[0] * w[0], j[1] * w[1], j[2] * w[2]]);
        momentum_off = momentum_off.max(norm(sub(h, h0)) / norm(h0));
        for body in ["principal", "tensor"] {
            let e = quaternion(&res, body, k);
            norm_off = norm_off.max((e.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs());
            let centre = vector(&res, body, ["x", "y", "z"], k);
            line_off = line_off.max(norm(sub(centre, add(r0, scale(v0, t)))));
        }
        // The twin: its points where the first body's are, its global angular velocity
        // the first's, and its angular momentum from its own frame (read off the markers
        // at the user's axes) and its tensor.
        for (p, q) in [("p1", "t1"), ("p2", "t2"), ("p3", "t3")] {
            let (x, y) = (vector(&res, p, ["x", "y", "z"], k), vector(&res, q, ["x", "y", "z"], k));
            twin_points_off = twin_points_off.max(norm(sub(x, y)) / arm);
        }
        let omega = mat_vec(&a, w);
        let twin_omega = mat_vec(&rotation_of(quaternion(&res, "tensor", k)), body_rates("tensor", k));
        twin_omega_off = twin_omega_off.max(norm(sub(omega, twin_omega)) / w2);
        let centre = vector(&res, "tensor", ["x", "y", "z"], k);
        let columns: Vec<V3> = ["u1", "u2", "u3"]
            .iter()
            .map(|m| scale(sub(vector(&res, m, ["x", "y", "z"], k), centre), 1.0 / arm))
            .collect();
        let user_frame = transpose(&[columns[0], columns[1], columns[2]]);
        let global_tensor = mat_mul(&mat_mul(&user_frame, &tensor), &transpose(&user_frame));
        let twin_h = mat_vec(&global_tensor, twin_omega);
        twin_momentum_off = twin_momentum_off.max(norm(sub(twin_h, h0)) / norm(h0));
    }
    println!(
        "k = {k}, period {period} s, {} steps: body rates off the closed form by {rates_off:.2e} of w2; \
         angular momentum drift {momentum_off:.2e}; |e| - 1 up to {norm_off:.2e}; centre off its line by \
         {line_off:.2e} m; the tensor twin's points off by {twin_points_off:.2e} of the arm, its angular \
         velocity by {twin_omega_off:.2e} of w2, its angular momentum drifts {twin_momentum_off:.2e}",
        res.stats.accepted_steps
    );
    assert!(flipped, "the body turns over within the period");
    assert!(rates_off < 1e-9, "body rates off the closed form by {rates_off:e} of w2");
    assert!(momentum_off < 1e-10, "angular momentum in ground axes drifts by {momentum_off:e}");
    assert!(norm_off < 1e-12, "|e| - 1 = {norm_off:e}");
    assert!(line_off < 1e-12, "the centre leaves its line by {line_off:e} m");
    assert!(twin_points_off < 1e-10, "the tensor twin's points are off by {twin_points_off:e}");
    assert!(twin_omega_off < 1e-10, "the tensor twin's angular velocity is off by {twin_omega_off:e}");
    assert!(twin_momentum_off < 1e-10, "the tensor twin's angular momentum drifts by {twin_momentum_off:e}");
}

/// The Euler parameters of the rotation matrix whose columns are the unit, right-handed
/// `x`, `y`, `z` (nalgebra's conversion, for placing bodies only).
fn quaternion_of_axes(x: V3, y: V3, z: V3) -> [f64; 4] {
    let m = nalgebra::Matrix3::from_columns(&[x.into(), y.into(), z.into()]);
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
    [q.w, q.i, q.j, q.k]
}

/// An angle brought into (-pi, pi].
fn wrapped(angle: f64) -> f64 {
    PI - (PI - angle).rem_euclid(2.0 * PI)
}

/// The spatial four-bar RSSR of the tests, solved by the test: a crank of length `A`
/// turning about the global z axis at the origin, a coupler of length `B` held by a ball
/// joint at each end, a rocker of length `C` turning about the skew axis `U` through
/// `D`. The rocker's tip is `D + C (cos psi e1 + sin psi e2)`, with `(e1, e2, U)` the
/// test's own right-handed triad.
struct Rssr {
    e1: V3,
    e2: V3,
}

const RSSR_A: f64 = 0.04;
const RSSR_B: f64 = 0.16;
const RSSR_C: f64 = 0.10;
const RSSR_D: V3 = [-0.03, 0.12, 0.05];
const RSSR_U: V3 = [0.8, -0.3, 0.5];
/// Masses [kg] of crank, coupler, rocker.
const RSSR_MASS: [f64; 3] = [0.3, 0.4, 0.5];
/// Principal moments [kg m^2]: the crank's and rocker's axes along the arm (x), across it
/// in the plane of turning (y) and along their pin (z); the coupler's z along its line.
const CRANK_J: V3 = [1.0e-5, 6.0e-5, 6.5e-5];
const COUPLER_J: V3 = [8.5e-4, 8.5e-4, 2.0e-6];
const ROCKER_J: V3 = [2.0e-5, 4.2e-4, 4.4e-4];

impl Rssr {
    fn new() -> Self {
        let u = unit(RSSR_U);
        let e1 = unit(cross(u, [0.0, 0.0, 1.0]));
        Rssr { e1, e2: cross(u, e1) }
    }

    fn crank_tip(&self, theta: f64) -> V3 {
        [RSSR_A * theta.cos(), RSSR_A * theta.sin(), 0.0]
    }

    fn rocker_tip(&self, psi: f64) -> V3 {
        add(RSSR_D, add(scale(self.e1, RSSR_C * psi.cos()), scale(self.e2, RSSR_C * psi.sin())))
    }

    /// `d(rocker tip)/d psi`.
    fn rocker_tip_rate(&self, psi: f64) -> V3 {
        add(scale(self.e1, -RSSR_C * psi.sin()), scale(self.e2, RSSR_C * psi.cos()))
    }

    /// The loop's residual `|C(psi) - B(theta)|^2 - B^2`.
    fn closure(&self, theta: f64, psi: f64) -> f64 {
        let d = sub(self.rocker_tip(psi), self.crank_tip(theta));
        dot(d, d) - RSSR_B * RSSR_B
    }

    /// The rocker angle at crank angle `theta`, by Newton's method on the closure from
    /// `guess`.
    fn rocker_angle(&self, theta: f64, guess: f64) -> f64 {
        let mut psi = guess;
        for _ in 0..50 {
            let d = sub(self.rocker_tip(psi), self.crank_tip(theta));
            let step = self.closure(theta, psi) / (2.0 * dot(d, self.rocker_tip_rate(psi)));
            psi -= step;
            if step.abs() < 1e-15 {
                return psi;
            }
        }
        panic!("Newton's method found no rocker angle at crank angle {theta}");
    }

    /// The rocker angle at crank angle 0, of the branch the tests run: `p cos psi + q sin psi
    /// = r`, solved as `psi = atan2(q, p) + acos(r / |(p, q)|)`.
    fn first_rocker_angle(&self) -> f64 {
        let db = sub(RSSR_D, self.crank_tip(0.0));
        let (p, q) = (2.0 * RSSR_C * dot(db, self.e1), 2.0 * RSSR_C * dot(db, self.e2));
        let r = RSSR_B * RSSR_B - RSSR_C * RSSR_C - dot(db, db);
        q.atan2(p) + (r / p.hypot(q)).acos()
    }

    /// The configuration at crank angle `theta` (rocker angle `psi`) and its rates per
    /// unit crank rate: the centres of mass of crank, coupler and rocker and their
    /// derivatives in `theta`, the coupler's line and its derivative, and `dpsi/dtheta`.
    fn configuration(&self, theta: f64, psi: f64) -> Configuration {
        let (b, c) = (self.crank_tip(theta), self.rocker_tip(psi));
        let b_rate = [-RSSR_A * theta.sin(), RSSR_A * theta.cos(), 0.0];
        // Implicit differentiation of the closure: (C - B) . (C' psi' - B') = 0.
        let psi_rate = dot(sub(c, b), b_rate) / dot(sub(c, b), self.rocker_tip_rate(psi));
        let c_rate = scale(self.rocker_tip_rate(psi), psi_rate);
        Configuration {
            centres: [scale(b, 0.5), scale(add(b, c), 0.5), scale(add(RSSR_D, c), 0.5)],
            centre_rates: [scale(b_rate, 0.5), scale(add(b_rate, c_rate), 0.5), scale(c_rate, 0.5)],
            line: scale(sub(c, b), 1.0 / RSSR_B),
            line_rate: scale(sub(c_rate, b_rate), 1.0 / RSSR_B),
            psi_rate,
        }
    }

    /// Twice the kinetic energy per squared crank rate, `I(theta)` (the spin of the
    /// coupler about its own line left out: it stays constant).
    fn generalized_inertia(&self, theta: f64, psi: f64) -> f64 {
        let s = self.configuration(theta, psi);
        let crank = CRANK_J[2] + RSSR_MASS[0] * (RSSR_A / 2.0).powi(2);
        let rocker = ROCKER_J[2] + RSSR_MASS[2] * (RSSR_C / 2.0).powi(2);
        crank
            + RSSR_MASS[1] * dot(s.centre_rates[1], s.centre_rates[1])
            + COUPLER_J[0] * dot(s.line_rate, s.line_rate)
            + rocker * s.psi_rate * s.psi_rate
    }

    /// The driving torque at constant crank rate `omega` from the virtual work of the
    /// inertia and gravity `g`: `tau omega = dT/dt + dV/dt` with `T = I(theta) omega^2 / 2`
    /// gives `tau = I'(theta) omega^2 / 2 + V'(theta)`, `I'` by central differences.
    fn driving_torque(&self, theta: f64, psi: f64, omega: f64, g: V3) -> f64 {
        let h = 1e-5;
        let inertia_at = |t: f64| self.generalized_inertia(t, self.rocker_angle(t, psi));
        let inertia_rate = (inertia_at(theta + h) - inertia_at(theta - h)) / (2.0 * h);
        let s = self.configuration(theta, psi);
        let potential_rate: f64 = (0..3).map(|b| -RSSR_MASS[b] * dot(g, s.centre_rates[b])).sum();
        0.5 * omega * omega * inertia_rate + potential_rate
    }
}

/// A configuration of the four-bar and its rates per unit crank rate.
struct Configuration {
    centres: [V3; 3],
    centre_rates: [V3; 3],
    line: V3,
    line_rate: V3,
    psi_rate: f64,
}

/// The spatial four-bar RSSR (crank revolute to ground about z, driven at constant
/// speed; a coupler between two ball joints; a rocker revolute to ground about a skew
/// axis), under gravity with components along and across the crank's axis, over one
/// turn of the crank. Each check against the loop solved by the test ([`Rssr`]):
///
/// - the rocker's angle (its joint's `angle` channel, from its value at t = 0) and the
///   rocker's tip (a marker) against the closure `|C(psi) - B(theta)| = coupler length`
///   solved by Newton's method;
/// - the motor's torque against the virtual work of the inertia and gravity computed
///   from that solution, `tau = I'(theta) omega^2 / 2 + V'(theta)`, and against the
///   engine's own energy channels, `tau omega = d(T + V)/dt` (fourth-order central
///   differences).
///
/// A coupler between two ball joints may spin about its own line, a motion that no
/// load drives: the coupler is given an axisymmetric inertia about that line (principal
/// frame along it), so the spin, whatever the assembly starts it at, stays constant
/// (`J3 dw3/dt = (J1 - J2) w1 w2 = 0`) and carries no load; the test checks that it does.
///
/// Measured at rtol 1e-12 (410 steps; the rocker swings 41.5 degrees): rocker angle within
/// 1.8e-10 rad of the closure, its tip within 1.9e-11 m, the torque (peak 0.249 N m)
/// within 1.3e-10 of its peak of the virtual work and 5.1e-8 of the power balance (the
/// differences of the dense output's rounding; 1.7e-6 at rtol 1e-10), the coupler's spin
/// constant to 2.5e-13 rad/s.
#[test]
fn a_spatial_four_bar_follows_its_loop_closure_and_its_motor_does_the_virtual_work() {
    let rssr = Rssr::new();
    let omega = 3.0 * PI;
    let g = [0.0, -9.81 * 0.6, -9.81 * 0.8];
    let u = unit(RSSR_U);
    let psi0 = rssr.first_rocker_angle();
    assert!(rssr.closure(0.0, psi0).abs() < 1e-15, "the start closes the loop");
    let s0 = rssr.configuration(0.0, psi0);
    let (b0, c0) = (rssr.crank_tip(0.0), rssr.rocker_tip(psi0));
    let arm0 = add(scale(rssr.e1, psi0.cos()), scale(rssr.e2, psi0.sin()));
    let coupler_spin = cross(s0.line, s0.line_rate);
    let model = json!({
        "dimension": 3,
        "gravity": g,
        "bodies": [
            {"name": "crank", "mass": RSSR_MASS[0], "inertia": {"principal": {"moments": CRANK_J}},
             "position": s0.centres[0], "velocity": scale(s0.centre_rates[0], omega),
             "angular_velocity": [0.0, 0.0, omega],
             "points": {"O": [-RSSR_A / 2.0, 0.0, 0.0], "B": [RSSR_A / 2.0, 0.0, 0.0]}},
            {"name": "coupler", "mass": RSSR_MASS[1], "inertia": {"principal": {"moments": COUPLER_J}},
             "position": s0.centres[1], "velocity": scale(s0.centre_rates[1], omega),
             "orientation": {"axis_angle": {"axis": cross([0.0, 0.0, 1.0], s0.line), "angle": s0.line[2].acos()}},
             "angular_velocity": scale(coupler_spin, omega),
             "points": {"B": [0.0, 0.0, -RSSR_B / 2.0], "C": [0.0, 0.0, RSSR_B / 2.0]}},
            {"name": "rocker", "mass": RSSR_MASS[2], "inertia": {"principal": {"moments": ROCKER_J}},
             "position": s0.centres[2], "velocity": scale(s0.centre_rates[2], omega),
             "orientation": {"quaternion": quaternion_of_axes(arm0, cross(u, arm0), u)},
             "angular_velocity": scale(u, s0.psi_rate * omega),
             "points": {"D": [-RSSR_C / 2.0, 0.0, 0.0], "C": [RSSR_C / 2.0, 0.0, 0.0]}}
        ],
        "joints": [
            {"name": "crank_pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
             "body_j": "crank", "point_j": "O", "axis": [0.0, 0.0, 1.0]},
            {"name": "ball_b", "type": "spherical", "body_i": "crank", "point_i": "B",
             "body_j": "coupler", "point_j": "B"},
            {"name": "ball_c", "type": "spherical", "body_i": "coupler", "point_i": "C",
             "body_j": "rocker", "point_j": "C"},
            {"name": "rocker_pin", "type": "revolute", "body_i": "ground", "point_i": RSSR_D,
             "body_j": "rocker", "point_j": "D", "axis": RSSR_U}
        ],
        "drivers": [{"name": "motor", "joint": "crank_pin", "profile": {"type": "constant_speed", "speed": omega}}],
        "markers": [{"name": "tip", "body": "rocker", "point": "C"}]
    });
    assert!(norm(sub(b0, c0)) - RSSR_B < 1e-15);
    let rate = 2000.0;
    let res = run(model, 2.0 * PI / omega, rate, 1e-12);
    let n = res.time.len();
    let (angle, torque) = (channel(&res, "rocker_pin.angle"), channel(&res, "motor.torque"));
    let crank_angle = channel(&res, "crank_pin.angle");
    let (kinetic, potential) =
        (channel(&res, "system.kinetic_energy"), channel(&res, "system.potential_energy"));
    let spin = channel(&res, "coupler.wz");
    let (mut psi, mut swing) = (psi0, (f64::INFINITY, f64::NEG_INFINITY));
    let (mut angle_off, mut tip_off, mut crank_off, mut torque_off, mut spin_off) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut peak_torque = 0.0f64;
    let mut expected = Vec::with_capacity(n);
    for k in 0..n {
        let theta = omega * res.time[k];
        psi = rssr.rocker_angle(theta, psi);
        swing = (swing.0.min(psi - psi0), swing.1.max(psi - psi0));
        angle_off = angle_off.max(wrapped((angle[k] - angle[0]) - (psi - psi0)).abs());
        crank_off = crank_off.max(wrapped(crank_angle[k] - crank_angle[0] - theta).abs());
        tip_off = tip_off.max(norm(sub(vector(&res, "tip", ["x", "y", "z"], k), rssr.rocker_tip(psi))));
        let tau = rssr.driving_torque(theta, psi, omega, g);
        peak_torque = peak_torque.max(tau.abs());
        expected.push(tau);
        spin_off = spin_off.max((spin[k] - spin[0]).abs());
    }
    for k in 0..n {
        torque_off = torque_off.max((torque[k] - expected[k]).abs() / peak_torque);
    }
    // The power balance from the engine's energy channels, at the samples spaced 1 /
    // rate (the last sample, at the end time, is closer).
    let h = 1.0 / rate;
    let energy: Vec<f64> = (0..n).map(|k| kinetic[k] + potential[k]).collect();
    let mut balance_off = 0.0f64;
    for k in (2..n - 2).filter(|&k| (res.time[k + 2] - res.time[k - 2] - 4.0 * h).abs() < 1e-12) {
        let rate_of_energy =
            (-energy[k + 2] + 8.0 * energy[k + 1] - 8.0 * energy[k - 1] + energy[k - 2]) / (12.0 * h);
        balance_off = balance_off.max((torque[k] * omega - rate_of_energy).abs() / (peak_torque * omega));
    }
    println!(
        "{n} samples, {} steps: rocker swings {:.2} to {:.2} degrees, its angle off the closure by {angle_off:.2e} rad, \
         its tip by {tip_off:.2e} m; crank angle off by {crank_off:.2e} rad; torque peak {peak_torque:.4} N m, off \
         the virtual work by {torque_off:.2e} and off the power balance by {balance_off:.2e} of the peak; \
         coupler spin {:.2e} rad/s, changed by {spin_off:.2e}",
        res.stats.accepted_steps,
        swing.0.to_degrees(),
        swing.1.to_degrees(),
        spin[0]
    );
    assert!(swing.1 - swing.0 > 0.5, "the rocker swings visibly");
    assert!(angle_off < 1e-8, "the rocker's angle is off the loop closure by {angle_off:e} rad");
    assert!(tip_off < 1e-9, "the rocker's tip is off the loop closure by {tip_off:e} m");
    assert!(crank_off < 1e-8, "the crank's angle is off its drive by {crank_off:e} rad");
    assert!(torque_off < 1e-8, "the motor's torque is off the virtual work by {torque_off:e} of its peak");
    assert!(balance_off < 1e-6, "the motor's power is off d(T + V)/dt by {balance_off:e} of its peak");
    assert!(spin_off < 1e-10, "the coupler's spin about its line changed by {spin_off:e} rad/s");
}

/// The smooth ramp of a driver as the test reads its definition: the speed rises from
/// rest to `speed` by the cubic STEP `3 s^2 - 2 s^3` (`s = t / ramp_time`), then stays;
/// the displacement is the speed's integral (Simpson's rule, exact on the cubic) and the
/// acceleration its derivative. Returns (displacement, speed, acceleration).
fn smooth_ramp(t: f64, speed: f64, ramp_time: f64) -> (f64, f64, f64) {
    let rate = |t: f64| {
        let s = (t / ramp_time).clamp(0.0, 1.0);
        speed * s * s * (3.0 - 2.0 * s)
    };
    let simpson = |a: f64, b: f64| (b - a) / 6.0 * (rate(a) + 4.0 * rate(0.5 * (a + b)) + rate(b));
    let ramp_end = t.min(ramp_time);
    let displacement = simpson(0.0, ramp_end) + speed * (t - ramp_end);
    let s = t / ramp_time;
    let acceleration = if s < 1.0 { speed * 6.0 * s * (1.0 - s) / ramp_time } else { 0.0 };
    (displacement, rate(t), acceleration)
}

/// The longest step [s] of the driven runs below: none. A body whose joints and driver
/// fix its motion has nothing for the error estimate to see (each step integrates the
/// profile's polynomial exactly), so a step can span the whole ramp (the prismatic run
/// takes two, 0 to 0.2 s and 0.2 to 0.3 s), and the samples between step ends rest on
/// the dense output alone: its quintic positions (`DenseStep::qdd`) read the smooth
/// ramp's quartic back exactly, where a cubic was `w T s^2 (1 - s)^2 / 2` off, 3.1e-3 m
/// at mid-ramp.
const DRIVEN_MAX_STEP: Option<f64> = None;

/// The largest of `f(k)` over the samples.
fn largest(n: usize, f: impl Fn(usize) -> f64) -> f64 {
    (0..n).map(f).fold(0.0, f64::max)
}

/// A slider on a prismatic joint along a skew axis `u`, pushed by a driver whose
/// profile is a smooth ramp, under gravity: its travel and speed channels follow the
/// profile, its centre of mass moves along the axis by the profile, and the driver's
/// force is what Newton's law along the axis asks, `F = m (x'' - g . u)`.
#[test]
fn a_prismatic_drive_follows_its_smooth_ramp_and_pushes_with_newtons_force() {
    let (mass, g) = (2.0, [0.0, 0.0, -9.81]);
    let u = unit([1.0, 1.0, 1.0]);
    let (centre, travel0) = ([0.2, -0.1, 0.3], 0.05);
    let (speed, ramp_time) = (0.5, 0.2);
    let model = json!({
        "dimension": 3,
        "gravity": g,
        "bodies": [{"name": "slider", "mass": mass, "inertia": {"principal": {"moments": [0.01, 0.012, 0.015]}},
                    "position": centre, "orientation": {"axis_angle": {"axis": [0.2, 1.0, -0.4], "angle": 0.7}}}],
        "joints": [{"name": "guide", "type": "prismatic", "body_i": "ground",
                    "point_i": sub(centre, scale(u, travel0)), "body_j": "slider", "point_j": [0.0, 0.0, 0.0],
                    "axis": u}],
        "drivers": [{"name": "push", "joint": "guide",
                     "profile": {"type": "smooth_ramp", "speed": speed, "ramp_time": ramp_time}}]
    });
    let res = run_with(model, 0.3, 1000.0, 1e-10, DRIVEN_MAX_STEP);
    let n = res.time.len();
    let (travel, rate, force) =
        (channel(&res, "guide.travel"), channel(&res, "guide.speed"), channel(&res, "push.force"));
    let profile = |k: usize| smooth_ramp(res.time[k], speed, ramp_time);
    let travel_off = largest(n, |k| (travel[k] - travel0 - profile(k).0).abs());
    let speed_off = largest(n, |k| (rate[k] - profile(k).1).abs());
    let centre_off = largest(n, |k| {
        norm(sub(vector(&res, "slider", ["x", "y", "z"], k), add(centre, scale(u, profile(k).0))))
    });
    let newton = |k: usize| mass * (profile(k).2 - dot(g, u));
    let force_off = largest(n, |k| (force[k] - newton(k)).abs());
    let peak = largest(n, |k| newton(k).abs());
    println!(
        "travel off the profile by {travel_off:.2e} m, speed by {speed_off:.2e} m/s, centre by {centre_off:.2e} m; \
         force (peak {peak:.3} N) off Newton's by {force_off:.2e} N"
    );
    assert!(travel_off < 1e-10, "travel off the profile by {travel_off:e} m");
    assert!(speed_off < 1e-9 * speed, "speed off the profile by {speed_off:e} m/s");
    assert!(centre_off < 1e-10, "centre of mass off the axis's profile by {centre_off:e} m");
    assert!(force_off < 1e-8 * peak, "driver force off m (x'' - g . u) by {force_off:e} N");
}

/// A sleeve on a cylindrical joint along a skew axis `u` (its centre of mass on the
/// axis), turned by a driver with a smooth-ramp profile, under gravity: its angle and
/// rate follow the profile, while its free travel along the axis falls as
/// `(g . u) t^2 / 2`; the driver's torque is `J_uu theta''`, with `J_uu = u^T J u` the
/// moment about the axis of the inertia tensor in ground axes (the axis is no principal
/// axis of the sleeve: the gyroscopic moments lie across it, taken by the joint).
#[test]
fn a_cylindrical_drive_turns_by_its_profile_while_the_sleeve_slides_freely() {
    let (mass, moments, g) = (1.5, [0.010, 0.020, 0.025], [0.0, 0.0, -9.81]);
    let u = unit([0.3, -0.5, 1.0]);
    let (turn_axis, turn) = ([1.0, 0.4, -0.3], 0.9);
    let a0 = rodrigues(turn_axis, turn);
    let inertia_global = mat_mul(
        &mat_mul(&a0, &[[moments[0], 0.0, 0.0], [0.0, moments[1], 0.0], [0.0, 0.0, moments[2]]]),
        &transpose(&a0),
    );
    let j_uu = dot(u, mat_vec(&inertia_global, u));
    let (centre, travel0) = ([0.1, 0.3, -0.2], 0.1);
    let (speed, ramp_time) = (20.0, 0.25);
    let model = json!({
        "dimension": 3,
        "gravity": g,
        "bodies": [{"name": "sleeve", "mass": mass, "inertia": {"principal": {"moments": moments}},
                    "position": centre, "orientation": {"axis_angle": {"axis": turn_axis, "angle": turn}}}],
        "joints": [{"name": "shaft", "type": "cylindrical", "body_i": "ground",
                    "point_i": sub(centre, scale(u, travel0)), "body_j": "sleeve", "point_j": [0.0, 0.0, 0.0],
                    "axis": u}],
        "drivers": [{"name": "spin", "joint": "shaft",
                     "profile": {"type": "smooth_ramp", "speed": speed, "ramp_time": ramp_time}}]
    });
    let res = run_with(model, 0.4, 1000.0, 1e-10, DRIVEN_MAX_STEP);
    let n = res.time.len();
    let c = |q: &str| channel(&res, &format!("shaft.{q}"));
    let (angle, omega, travel, slide) = (c("angle"), c("omega"), c("travel"), c("speed"));
    let torque = channel(&res, "spin.torque");
    let profile = |k: usize| smooth_ramp(res.time[k], speed, ramp_time);
    let fall = dot(g, u);
    let angle_off = largest(n, |k| wrapped(angle[k] - angle[0] - profile(k).0).abs());
    let rate_off = largest(n, |k| (omega[k] - profile(k).1).abs());
    let travel_off = largest(n, |k| (travel[k] - travel0 - 0.5 * fall * res.time[k].powi(2)).abs());
    let slide_off = largest(n, |k| (slide[k] - fall * res.time[k]).abs());
    let expected = |k: usize| j_uu * profile(k).2;
    let peak = largest(n, |k| expected(k).abs());
    let torque_off = largest(n, |k| (torque[k] - expected(k)).abs());
    println!(
        "turned {:.1} rad: angle off the profile by {angle_off:.2e} rad, rate by {rate_off:.2e} rad/s; travel off \
         the free fall by {travel_off:.2e} m, its speed by {slide_off:.2e} m/s; torque (peak {peak:.4} N m, \
         J_uu = {j_uu:.5} kg m^2) off J_uu theta'' by {torque_off:.2e} N m",
        profile(n - 1).0
    );
    assert!(angle_off < 1e-9, "angle off the profile by {angle_off:e} rad");
    assert!(rate_off < 1e-9 * speed, "rate off the profile by {rate_off:e} rad/s");
    assert!(travel_off < 1e-10, "travel off the free fall by {travel_off:e} m");
    assert!(slide_off < 1e-9, "sliding speed off the free fall by {slide_off:e} m/s");
    assert!(torque_off < 1e-8 * peak, "driver torque off J_uu theta'' by {torque_off:e} N m");
}

/// A pendulum (centre of mass `l` below its pin, inertia given as a full tensor with
/// products of inertia) on a revolute joint about the global x axis, driven from rest
/// by a smooth ramp to one turn per second: its angle follows the profile and the
/// driver's torque is the closed form of a driven pendulum,
/// `tau = J_pivot phi'' + m g l sin(phi)` with `J_pivot = J_xx + m l^2` (the products of
/// inertia load the pin across its axis, not about it); the pin's reaction force and
/// moment are Newton's and Euler's laws of the bob.
#[test]
fn a_driven_pendulum_needs_the_closed_form_torque() {
    let (mass, l, g) = (1.2, 0.25, 9.81);
    let tensor = [[0.020, 0.003, -0.002], [0.003, 0.015, 0.001], [-0.002, 0.001, 0.010]];
    let j_pivot = tensor[0][0] + mass * l * l;
    let (speed, ramp_time) = (2.0 * PI, 0.5);
    let model = json!({
        "dimension": 3,
        "gravity": [0.0, 0.0, -g],
        "bodies": [{"name": "bob", "mass": mass, "inertia": {"tensor": tensor}, "position": [0.0, 0.0, -l]}],
        "joints": [{"name": "pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                    "body_j": "bob", "point_j": [0.0, 0.0, l], "axis": [1.0, 0.0, 0.0]}],
        "drivers": [{"name": "motor", "joint": "pin",
                     "profile": {"type": "smooth_ramp", "speed": speed, "ramp_time": ramp_time}}]
    });
    let res = run_with(model, 1.0, 1000.0, 1e-10, DRIVEN_MAX_STEP);
    let n = res.time.len();
    let (angle, torque) = (channel(&res, "pin.angle"), channel(&res, "motor.torque"));
    let profile = |k: usize| smooth_ramp(res.time[k], speed, ramp_time);
    let angle_off = largest(n, |k| wrapped(angle[k] - angle[0] - profile(k).0).abs());
    let closed_form = |k: usize| {
        let (phi, _, alpha) = profile(k);
        j_pivot * alpha + mass * g * l * phi.sin()
    };
    // The bob's centre from the angle: (0, l sin phi, -l cos phi).
    let centre_off = largest(n, |k| {
        let phi = profile(k).0;
        norm(sub(vector(&res, "bob", ["x", "y", "z"], k), [0.0, l * phi.sin(), -l * phi.cos()]))
    });
    let peak = largest(n, |k| closed_form(k).abs());
    let torque_off = largest(n, |k| (torque[k] - closed_form(k)).abs());
    println!(
        "angle off the profile by {angle_off:.2e} rad, centre by {centre_off:.2e} m; torque (peak {peak:.4} N m) \
         off J_pivot phi'' + m g l sin phi by {torque_off:.2e} N m"
    );
    assert!(angle_off < 1e-9, "angle off the profile by {angle_off:e} rad");
    assert!(centre_off < 1e-10, "centre off the circle by {centre_off:e} m");
    assert!(torque_off < 1e-8 * peak, "driver torque off the closed form by {torque_off:e} N m");

    // The pin's reaction on the bob (global axes, moment about the pin): Newton's law
    // `f = m (a - g)` for the force; Euler's about the fixed pin for the moment,
    // `m_pin = I_O phi'' x + w x (I_O w) - tau x - r x m g`, with `I_O` the tensor about
    // the pin turned by the angle, `r` the centre from the pin. Its x part is zero (the
    // pin carries no moment about its axis); the products of inertia load it across.
    let gravity = [0.0, 0.0, -g];
    let about_pin =
        [0, 1, 2].map(|r| [0, 1, 2].map(|c| tensor[r][c] + if r == c && r < 2 { mass * l * l } else { 0.0 }));
    let (mut force_off, mut moment_off, mut force_peak, mut moment_peak) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for k in 0..n {
        let (phi, rate, alpha) = profile(k);
        let (sin, cos) = phi.sin_cos();
        let turn = rodrigues([1.0, 0.0, 0.0], phi);
        let centre = [0.0, l * sin, -l * cos];
        let acceleration =
            [0.0, l * (alpha * cos - rate * rate * sin), l * (alpha * sin + rate * rate * cos)];
        let force = scale(sub(acceleration, gravity), mass);
        let i_o = mat_mul(&mat_mul(&turn, &about_pin), &transpose(&turn));
        let w = [rate, 0.0, 0.0];
        let euler = add(mat_vec(&i_o, [alpha, 0.0, 0.0]), cross(w, mat_vec(&i_o, w)));
        let moment = sub(sub(euler, [closed_form(k), 0.0, 0.0]), cross(centre, scale(gravity, mass)));
        force_off = force_off.max(norm(sub(vector(&res, "pin", ["fx", "fy", "fz"], k), force)));
        moment_off = moment_off.max(norm(sub(vector(&res, "pin", ["mx", "my", "mz"], k), moment)));
        force_peak = force_peak.max(norm(force));
        moment_peak = moment_peak.max(norm(moment));
    }
    println!(
        "pin reaction (peaks {force_peak:.3} N, {moment_peak:.4} N m) off Newton's by {force_off:.2e} N, off \
         Euler's by {moment_off:.2e} N m"
    );
    assert!(moment_peak > 1e-3, "the products of inertia load the pin across its axis");
    assert!(force_off < 1e-8 * force_peak, "pin force off m (a - g) by {force_off:e} N");
    assert!(moment_off < 1e-8 * moment_peak, "pin moment off Euler's law by {moment_off:e} N m");
}

/// A body `link` hanging from a pin, with the body's and the joints' keys given by
/// `body` (merged over the defaults) and `joints`, and a second body `arm` for joints
/// between two bodies.
fn pendulum_with(body: serde_json::Value, joints: serde_json::Value) -> serde_json::Value {
    let mut link = json!({"name": "link", "mass": 1.0, "inertia": {"principal": {"moments": [0.01, 0.02, 0.025]}},
                          "position": [0.0, 0.0, -0.2]});
    for (key, value) in body.as_object().expect("an object") {
        link[key] = value.clone();
    }
    json!({
        "dimension": 3,
        "bodies": [link, {"name": "arm", "mass": 0.5, "inertia": {"principal": {"moments": [0.001, 0.002, 0.002]}},
                          "position": [0.0, 0.0, -0.5]}],
        "joints": joints
    })
}

/// The run of `model` fails before it starts with a model error about `key` of
/// element `element` of kind `kind`, whose message names the element and holds each of
/// `words` (the offending value and what is wrong), and does not panic.
fn expect_error(model: serde_json::Value, kind: &str, element: &str, key: &str, words: &[&str]) {
    let model = SpatialModel::from_json(&model.to_string()).expect("the model parses");
    let outcome = std::panic::catch_unwind(|| simulate_spatial(&model, &SimOptions::new(0.01), &mut Silent));
    let error = match outcome {
        Err(_) => panic!("the engine panicked on bad {kind} '{element}' {key}"),
        Ok(Ok(res)) => panic!("bad {kind} '{element}' {key} ran: {:?}", res.status),
        Ok(Err(error)) => error,
    };
    let parts = error.parts();
    let message = error.to_string();
    assert_eq!(
        (parts.category, parts.kind, parts.element.as_deref(), parts.key.as_deref()),
        ("model", Some(kind), Some(element), Some(key)),
        "{message}"
    );
    assert!(message.starts_with(&format!("{kind} '{element}': ")), "{message}");
    for w in words {
        assert!(message.contains(w), "{message:?} says {w:?}");
    }
}

/// Each bad input of a spatial model is an error naming the element, the key and the
/// value, never a panic or a run: a quaternion far from unit length or zero, an inertia
/// that is not positive definite or breaks the triangle inequality, an unknown Euler
/// convention, a joint axis of zero length, a ball larger than its socket, a universal
/// joint without body j's cross axis.
#[test]
fn bad_spatial_input_is_a_clear_error_naming_the_element_and_key() {
    let pin = json!([{"name": "pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                      "body_j": "link", "point_j": [0.0, 0.0, 0.2], "axis": [1.0, 0.0, 0.0]}]);
    let body = |patch: serde_json::Value| pendulum_with(patch, pin.clone());
    expect_error(
        body(json!({"orientation": {"quaternion": [1.0, 0.5, 0.0, 0.0]}})),
        "body",
        "link",
        "orientation",
        &["[1.0, 0.5, 0.0, 0.0]", "length 1.118", "not 1"],
    );
    expect_error(
        body(json!({"orientation": {"quaternion": [0.0, 0.0, 0.0, 0.0]}})),
        "body",
        "link",
        "orientation",
        &["[0.0, 0.0, 0.0, 0.0]", "length 0"],
    );
    expect_error(
        body(json!({"inertia": {"tensor": [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}})),
        "body",
        "link",
        "inertia",
        &["not positive definite", "[[1, 2, 0], [2, 1, 0], [0, 0, 1]]"],
    );
    expect_error(
        body(json!({"inertia": {"principal": {"moments": [0.01, -0.02, 0.02]}}})),
        "body",
        "link",
        "inertia",
        &["-0.02", "must be positive"],
    );
    expect_error(
        body(json!({"inertia": {"principal": {"moments": [0.01, 0.01, 0.03]}}})),
        "body",
        "link",
        "inertia",
        &["triangle inequality", "J3 = 0.03"],
    );
    expect_error(
        body(json!({"inertia": {"tensor": [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.03]]}})),
        "body",
        "link",
        "inertia",
        &["triangle inequality", "J3 = 0.03"],
    );
    for convention in ["XYQ", "XXZ", "zyx"] {
        expect_error(
            body(json!({"orientation": {"euler": {"convention": convention, "angles": [0.1, 0.2, 0.3]}}})),
            "body",
            "link",
            "orientation",
            &["unknown Euler convention", convention, "ZYX"],
        );
    }
    let no_axis = json!([{"name": "pin", "type": "revolute", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                          "body_j": "link", "point_j": [0.0, 0.0, 0.2], "axis": [0.0, 0.0, 0.0]}]);
    expect_error(pendulum_with(json!({}), no_axis), "joint", "pin", "axis", &["[0.0, 0.0, 0.0]", "non-zero"]);
    let zero_axis_j = json!([{"name": "slide", "type": "prismatic", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                              "body_j": "link", "point_j": [0.0, 0.0, 0.2], "axis": [1.0, 0.0, 0.0],
                              "axis_j": [0.0, 0.0, 0.0]}]);
    expect_error(pendulum_with(json!({}), zero_axis_j), "joint", "slide", "axis_j", &["[0.0, 0.0, 0.0]"]);
    let ball = json!([
        pin[0],
        {"name": "socket", "type": "clearance_spherical", "body_i": "link", "point_i": [0.0, 0.0, -0.2],
         "body_j": "arm", "point_j": [0.0, 0.0, 0.1],
         "clearance": {"bearing_radius": 0.010, "journal_radius": 0.0105, "stiffness": 1e9,
                       "normal_law": {"type": "hertz"}}}
    ]);
    expect_error(
        pendulum_with(json!({}), ball),
        "joint",
        "socket",
        "journal_radius",
        &["journal_radius = 0.0105 m", "bearing_radius = 0.01 m"],
    );
    let hooke = json!([
        pin[0],
        {"name": "hooke", "type": "universal", "body_i": "link", "point_i": [0.0, 0.0, -0.2],
         "body_j": "arm", "point_j": [0.0, 0.0, 0.1], "axis": [1.0, 0.0, 0.0]}
    ]);
    expect_error(pendulum_with(json!({}), hooke), "joint", "hooke", "axis_j", &["universal", "axis_j"]);
}
