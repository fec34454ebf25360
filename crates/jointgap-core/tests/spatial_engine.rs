//! Spatial mechanisms through the whole engine (model -> system -> run), each against an
//! independent computation: the heavy symmetric top's nutation limits from the
//! closed-form cubic and its conserved quantities; a mass on a spring-damper and a free
//! body under loads that turn with it, against their closed forms.
#![allow(clippy::needless_range_loop)]

use jointgap_core::model::spatial::SpatialModel;
use jointgap_core::simulate::{simulate_spatial, Silent};
use jointgap_core::{SimOptions, SimResult, Status};
use serde_json::json;

fn run(model: serde_json::Value, t_end: f64, rate: f64, rtol: f64) -> SimResult {
    let model = SpatialModel::from_json(&model.to_string()).expect("a valid model");
    let mut opts = SimOptions::new(t_end);
    opts.rate = Some(rate);
    opts.rtol = rtol;
    opts.atol = rtol * 1e-2;
    let res = simulate_spatial(&model, &opts, &mut Silent).expect("a run");
    assert_eq!(res.status, Status::Finished, "{:?}", res.status);
    res
}

fn channel<'a>(res: &'a SimResult, name: &str) -> &'a [f64] {
    res.channel(name).unwrap_or_else(|| panic!("no channel {name} in {:?}", res.names))
}

/// A symmetric top (moments J1 = J1, J3 about its centre of mass, which lies `l` up its
/// axis from a spherical joint at the origin), released at tilt `theta0` with spin `w3`
/// and no precession: its axis's cosine to the vertical, `u`, swings between `u0` and the
/// other root `u1` of `f(u) = (u0 - u) [beta (1 - u^2) - b^2 (u0 - u)]` (Goldstein,
/// Classical Mechanics, section 5.7), with `beta = 2 m g l / I1`, `b = J3 w3 / I1` and
/// `I1 = J1 + m l^2` about the pivot. Energy, the vertical angular momentum and the spin
/// momentum `J3 w3` stay constant.
#[test]
fn heavy_symmetric_top_nutates_between_the_roots_of_the_cubic() {
    let (m, g, l, j1, j3) = (0.5, 9.81, 0.04, 2.0e-4, 3.0e-4);
    let (theta0, w3) = (0.5f64, 60.0);
    let axis = [theta0.sin(), 0.0, theta0.cos()];
    let model = json!({
        "dimension": 3,
        "gravity": [0.0, 0.0, -g],
        "bodies": [{
            "name": "top", "mass": m, "inertia": {"principal": {"moments": [j1, j1, j3]}},
            "position": axis.map(|x| x * l),
            "orientation": {"axis_angle": {"axis": [0.0, 1.0, 0.0], "angle": theta0}},
            "angular_velocity": axis.map(|x| x * w3)
        }],
        "joints": [{"name": "pivot", "type": "spherical", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                    "body_j": "top", "point_j": [0.0, 0.0, -l]}]
    });
    // The conserved quantities drift with the tolerance, as an integrator's error does
    // (energy 1.1e-9, 2.6e-11, 4.2e-12 and L_z 4.3e-9, 1.1e-10, 1.7e-11 relative at rtol
    // 1e-10, 1e-12, 1e-13): checked at the tightest.
    let res = run(model, 1.0, 20000.0, 1e-13);
    let e: Vec<&[f64]> =
        ["e0", "e1", "e2", "e3"].iter().map(|q| channel(&res, &format!("top.{q}"))).collect();
    let n = res.time.len();
    let u: Vec<f64> =
        (0..n).map(|k| e[0][k].powi(2) - e[1][k].powi(2) - e[2][k].powi(2) + e[3][k].powi(2)).collect();
    for k in 0..n {
        let norm = (0..4).map(|c| e[c][k] * e[c][k]).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "|e| = {norm} at t = {}", res.time[k]);
    }
    let i1 = j1 + m * l * l;
    let (beta, b) = (2.0 * m * g * l / i1, j3 * w3 / i1);
    let u0 = theta0.cos();
    // beta u^2 - b^2 u + (b^2 u0 - beta) = 0, the root below u0.
    let disc = (b.powi(4) - 4.0 * beta * (b * b * u0 - beta)).sqrt();
    let u1 = [(b * b - disc) / (2.0 * beta), (b * b + disc) / (2.0 * beta)]
        .into_iter()
        .filter(|r| *r < u0 && *r > -1.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = u.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let swing = u0 - u1;
    assert!(swing > 1e-3, "the test needs a visible nutation: {swing}");
    assert!((hi - u0).abs() < 1e-6 * swing, "upper turning point {hi} vs u0 = {u0}");
    assert!((lo - u1).abs() < 1e-4 * swing, "lower turning point {lo} vs u1 = {u1} (swing {swing})");
    // Energy and the two momenta.
    let (kin, pot) = (channel(&res, "system.kinetic_energy"), channel(&res, "system.potential_energy"));
    let e0 = kin[0] + pot[0];
    let w: Vec<&[f64]> = ["wx", "wy", "wz"].iter().map(|q| channel(&res, &format!("top.{q}"))).collect();
    for k in 0..n {
        assert!(((kin[k] + pot[k]) - e0).abs() < 1e-10 * e0.abs(), "energy {} vs {e0}", kin[k] + pot[k]);
        assert!((j3 * w[2][k] - j3 * w3).abs() < 1e-10 * j3 * w3, "spin momentum at {}", res.time[k]);
    }
    // Vertical angular momentum about the pivot: (A J w')_z + m (r x v)_z; the centre of
    // mass's r x v from the position and velocity channels.
    let c = |q: &str| channel(&res, &format!("top.{q}"));
    let lz = |k: usize| {
        let (e0, e1, e2, e3) = (e[0][k], e[1][k], e[2][k], e[3][k]);
        // Third row of A.
        let a3 =
            [2.0 * (e1 * e3 - e0 * e2), 2.0 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3];
        let h = [j1 * w[0][k], j1 * w[1][k], j3 * w[2][k]];
        let spin: f64 = a3.iter().zip(h).map(|(a, h)| a * h).sum();
        spin + m * (c("x")[k] * c("vy")[k] - c("y")[k] * c("vx")[k])
    };
    let lz0 = lz(0);
    for k in 0..n {
        assert!((lz(k) - lz0).abs() < 1e-10 * lz0.abs(), "L_z {} vs {lz0} at {}", lz(k), res.time[k]);
    }
}

/// A body hung from the ground by a spring-damper (no joint): it settles at the static
/// deflection `m g / k` below the spring's free length, and without damping it
/// oscillates at `sqrt(k / m)` about there (the closed form of a mass on a spring);
/// an applied force and torque in the body's frame turn with it.
#[test]
fn spring_damper_and_applied_loads_follow_their_closed_forms() {
    let (m, k, l0, g): (f64, f64, f64, f64) = (2.0, 800.0, 0.3, 9.81);
    let model = |damping: f64| {
        json!({
            "dimension": 3,
            "gravity": [0.0, 0.0, -g],
            "bodies": [{"name": "bob", "mass": m, "inertia": {"principal": {"moments": [0.01, 0.01, 0.01]}},
                        "position": [0.0, 0.0, -l0]}],
            "forces": [{"type": "spring_damper", "name": "spring", "body_i": "ground", "point_i": [0.0, 0.0, 0.0],
                        "body_j": "bob", "point_j": [0.0, 0.0, 0.0], "stiffness": k, "damping": damping,
                        "free_length": l0}]
        })
    };
    // Released at the free length: z(t) = -l0 - (m g / k) (1 - cos(w t)).
    let res = run(model(0.0), 0.5, 2000.0, 1e-11);
    let (w, d) = ((k / m).sqrt(), m * g / k);
    for (t, z) in res.time.iter().zip(channel(&res, "bob.z")) {
        let expected = -l0 - d * (1.0 - (w * t).cos());
        assert!((z - expected).abs() < 1e-8 * d, "z at {t}: {z} vs {expected}");
    }
    // Critically damped (c = 2 sqrt(k m)), it settles at the static deflection within
    // (1 + w t) exp(-w t) of it: 1e-16 after 2 s.
    let res = run(model(2.0 * (k * m).sqrt()), 2.0, 100.0, 1e-10);
    let z = *channel(&res, "bob.z").last().unwrap();
    assert!((z - (-l0 - d)).abs() < 1e-9, "settled at {z}, static {}", -l0 - d);

    // A free body (no gravity) under a torque about its body z axis, given in its own
    // frame, while a force along its body x axis pushes its centre of mass: w'_z = tau t /
    // J3, the body turns about global z by phi = tau t^2 / (2 J3), and the force, turning
    // with it, drives the centre along (cos phi, sin phi) / m.
    let (tau, f, j3) = (0.02, 0.5, 0.04);
    let free = json!({
        "dimension": 3,
        "gravity": [0.0, 0.0, 0.0],
        "bodies": [{"name": "disc", "mass": m, "inertia": {"principal": {"moments": [0.02, 0.03, j3]}}}],
        "forces": [{"type": "applied_torque", "name": "twist", "body": "disc", "torque": [0.0, 0.0, tau], "frame": "body"},
                   {"type": "applied_force", "name": "push", "body": "disc", "force": [f, 0.0, 0.0], "frame": "body"}]
    });
    let res = run(free, 1.0, 100.0, 1e-11);
    let (wz, ax, ay) = (channel(&res, "disc.wz"), channel(&res, "disc.ax"), channel(&res, "disc.ay"));
    for (i, t) in res.time.iter().enumerate() {
        let phi = tau * t * t / (2.0 * j3);
        assert!((wz[i] - tau * t / j3).abs() < 1e-9, "w'_z at {t}");
        assert!(
            (ax[i] - f / m * phi.cos()).abs() < 1e-8 && (ay[i] - f / m * phi.sin()).abs() < 1e-8,
            "a at {t}"
        );
    }
}
