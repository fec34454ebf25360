//! The implicit methods' Jacobians against differences of the whole equations of motion.
//! The force Jacobian (`dynamics::force_jacobian`): equal where there are no
//! constraints, and within the geometric terms it leaves out on the founding
//! slider-crank in contact, where the contact's stiffness dominates. The exact Jacobian
//! (`dynamics::compiled::jacobian`): equal to central differences to their own error.

use jointgap_core::dynamics::force_jacobian;
use jointgap_core::integrators::jacobian::forward_difference;
use jointgap_core::mechanics::spatial::kind::Spatial;
use jointgap_core::model::spatial::SpatialModel;
use jointgap_core::simulate::equations::Ode;
use jointgap_core::simulate::{prepare, prepare_model, simulate_spatial, Silent};
use jointgap_core::{simulate, Model, SimOptions, SimResult, Status};
use nalgebra::DMatrix;
use serde_json::json;

/// Both Jacobians `[dqdd/dq dqdd/dv]` of `model` at state `y = (q, v)`, time `t`.
fn both_jacobians(model: &Model, t: f64, y: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let prepared = prepare(model).unwrap();
    let sys = &prepared.system;
    let n = sys.layout.nv();
    let mut ode = Ode::new(sys, prepared.initial.active.clone(), 1e-7, 1e-10);
    let mut f0 = vec![0.0; 2 * n];
    ode.rhs(t, y, &mut f0).unwrap();
    let mut by_forces = DMatrix::zeros(n, 2 * n);
    force_jacobian(sys, t, &y[..n], &y[n..], &mut ode.ws, &mut by_forces).unwrap();
    let mut full = DMatrix::zeros(n, 2 * n);
    let mut work = vec![0.0; 2 * n];
    forward_difference(&mut ode, t, y, &f0, n, &mut full, &mut work).unwrap();
    (by_forces, full)
}

/// The state `(q, v)` of `bodies` at sample `i` of a run with every channel.
fn state_at(res: &SimResult, bodies: &[&str], i: usize) -> Vec<f64> {
    let channel = |name: String| res.channel(&name).unwrap_or_else(|| panic!("channel {name}"))[i];
    let mut q = Vec::new();
    let mut v = Vec::new();
    for b in bodies {
        for c in ["x", "y", "angle"] {
            q.push(channel(format!("{b}.{c}")));
        }
        for c in ["vx", "vy", "omega"] {
            v.push(channel(format!("{b}.{c}")));
        }
    }
    q.extend(v);
    q
}

fn largest(m: &DMatrix<f64>) -> f64 {
    m.amax()
}

/// A free journal pressed into its bearing and sliding (ADAMS impact law, Coulomb
/// friction), no constraints: `P = M^-1`, so both are `M^-1 dQe/dy` and agree to
/// round-off.
#[test]
fn equals_forward_differences_without_constraints() {
    let model = Model::from_json(
        &json!({
            "gravity": [0.0, -9.81],
            "bodies": [{"name": "pin", "mass": 0.72, "inertia": 1e-5}],
            "joints": [{
                "name": "gap", "type": "clearance_revolute", "body_i": "ground", "point_i": [0.0, 0.0], "body_j": "pin", "point_j": [0.0, 0.0],
                "clearance": {"bearing_radius": 7.5e-3, "clearance": 0.5e-3, "stiffness": 3.136e10,
                              "normal_law": {"type": "adams_impact", "c_max": 27960.0, "d_max": 1e-5},
                              "friction": {"type": "coulomb", "mu_s": 0.08, "mu_d": 0.05,
                                           "v_s": 1e-4, "v_d": 0.01016}}
            }]
        })
        .to_string(),
    )
    .unwrap();
    // 2 um into the wall below the centre, approaching at 0.05 m/s, sliding at 0.3 m/s
    // and spinning: normal, damping and friction forces all depend on the state.
    let y = [0.0, -0.502e-3, 0.3, 0.3, -0.05, 40.0];
    let (by_forces, full) = both_jacobians(&model, 0.0, &y);
    let scale = largest(&full);
    assert!(scale > 1e8, "contact stiffness / mass {scale:.3e} 1/s^2");
    let diff = largest(&(&by_forces - &full));
    assert!(diff <= 1e-9 * scale, "differ by {diff:.3e} of {scale:.3e}");
}

/// The founding slider-crank with its rod-slider joint in sliding contact, mid-run: the
/// terms left out (the constraint forces' geometric stiffness and the velocity terms,
/// of the order of the crank speed squared, 1e3 1/s^2, and of the joint loads over the
/// rod's inertia) are a small part of the contact's stiffness through the constraints.
#[test]
fn keeps_the_stiff_part_on_the_founding_case_in_contact() {
    let model = common::slider_crank_clearance();
    let opts = SimOptions { rate: Some(10_000.0), ..SimOptions::new(0.3) };
    let res = simulate(&model, &opts).unwrap();
    assert_eq!(res.status, Status::Finished);
    let pen = res.channel("rod_slider.penetration").unwrap();
    let slip = res.channel("rod_slider.slip").unwrap();
    let i = (0..pen.len()).rev().find(|&i| pen[i] > 1e-7 && slip[i].abs() > 0.0102).expect("sliding contact");
    let y = state_at(&res, &["crank", "rod", "slider"], i);
    let (by_forces, full) = both_jacobians(&model, res.time[i], &y);
    let scale = largest(&full);
    assert!(scale > 1e6, "contact stiffness through the constraints {scale:.3e} 1/s^2");
    let diff = largest(&(&by_forces - &full));
    // Measured: 2.4e3 of 4.0e7 at t = 0.3 s.
    assert!(diff <= 1e-3 * scale, "differ by {diff:.3e} of {scale:.3e}");
}

use crate::common;

/// Central differences of the accelerations `[dqdd/dq dqdd/dv]` at `y`, each column with
/// its own increment `steps[j]`.
fn central_differences(ode: &mut Ode, t: f64, y: &[f64], steps: &[f64]) -> DMatrix<f64> {
    let n = y.len() / 2;
    let mut jac = DMatrix::zeros(n, 2 * n);
    let (mut up, mut down) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
    let mut yp = y.to_vec();
    for j in 0..2 * n {
        yp[j] = y[j] + steps[j];
        ode.rhs(t, &yp, &mut up).unwrap();
        yp[j] = y[j] - steps[j];
        ode.rhs(t, &yp, &mut down).unwrap();
        yp[j] = y[j];
        for i in 0..n {
            jac[(i, j)] = (up[n + i] - down[n + i]) / (2.0 * steps[j]);
        }
    }
    jac
}

/// The exact Jacobian of a planar slider-crank (its three bodies) at `(t, y)`, central
/// differences of its whole equations of motion there, and the applied forces' part.
/// The increments are well below a contact's 1e-7 m penetration and a sliding speed, and
/// large enough that rounding stays below the terms compared (measured on the founding
/// case: the differences move towards the exact Jacobian as the increments grow from
/// 1e-13 m to 3e-9 m).
fn three_jacobians(model: &Model, t: f64, y: &[f64]) -> [DMatrix<f64>; 3] {
    let prepared = prepare(model).unwrap();
    let sys = &prepared.system;
    let n = sys.layout.nv();
    let mut ode = Ode::new(sys, prepared.initial.active.clone(), 1e-7, 1e-10);
    ode.ws.compile(false, true).unwrap();
    let mut f0 = vec![0.0; 2 * n];
    ode.rhs(t, y, &mut f0).unwrap();
    let mut exact = DMatrix::zeros(n, 2 * n);
    assert!(jointgap_core::dynamics::compiled::jacobian(sys, t, &y[..n], &y[n..], &mut ode.ws, &mut exact));
    let steps: Vec<f64> = (0..2 * n).map(|j| if j < n { 1e-9 } else { 1e-6 }).collect();
    let central = central_differences(&mut ode, t, y, &steps);
    let mut by_forces = DMatrix::zeros(n, 2 * n);
    force_jacobian(sys, t, &y[..n], &y[n..], &mut ode.ws, &mut by_forces).unwrap();
    [exact, central, by_forces]
}

/// [`three_jacobians`] of a founding slider-crank at the last output sample before 0.3 s
/// where its rod-slider joint slides in contact (pressed 0.1 um deep, slipping faster
/// than the friction law's dynamic speed).
fn jacobians_in_sliding_contact(model: &Model) -> [DMatrix<f64>; 3] {
    let opts = SimOptions { rate: Some(10_000.0), ..SimOptions::new(0.3) };
    let res = simulate(model, &opts).unwrap();
    let pen = res.channel("rod_slider.penetration").unwrap();
    let slip = res.channel("rod_slider.slip").unwrap();
    let i = (0..pen.len()).rev().find(|&i| pen[i] > 1e-7 && slip[i].abs() > 0.0102).expect("sliding contact");
    three_jacobians(model, res.time[i], &state_at(&res, &["crank", "rod", "slider"], i))
}

/// The exact Jacobian (reverse-mode derivatives of the recorded evaluation) on the
/// founding slider-crank in sliding contact mid-run, against central differences of the
/// whole equations of motion: equal to the differences' own error, and closer by far
/// than the applied forces' part, which leaves out the constraint forces' geometric
/// stiffness and the velocity terms.
#[test]
fn exact_jacobian_matches_central_differences_in_contact() {
    let [exact, central, by_forces] = jacobians_in_sliding_contact(&common::slider_crank_clearance());
    let scale = largest(&central);
    let exact_off = largest(&(&exact - &central));
    let forces_off = largest(&(&by_forces - &central));
    // Measured: 1.3 and 1.6e4 of 4.0e7.
    assert!(exact_off <= 1e-7 * scale, "exact off by {exact_off:.3e} of {scale:.3e}");
    assert!(forces_off >= 1000.0 * exact_off, "forces only {forces_off:.3e}, exact {exact_off:.3e}");
}

/// The exact Jacobian through the long bearing's positive-pressure film (the end of its
/// arc a root found by iteration, which the graph calls whole), on the lubricated
/// founding case mid-run, the film carrying the rod: against central differences of the
/// whole equations of motion.
#[test]
fn exact_jacobian_through_the_long_film_matches_central_differences() {
    let model = crate::compiled::lubricated_founding_case("long");
    let opts = SimOptions { rate: Some(10_000.0), ..SimOptions::new(0.05) };
    let res = simulate(&model, &opts).unwrap();
    let (fx, fy) = (res.channel("rod_slider.film_fx").unwrap(), res.channel("rod_slider.film_fy").unwrap());
    let i = (0..fx.len()).rev().find(|&i| fx[i].hypot(fy[i]) > 1.0).expect("a film that carries");
    let y = state_at(&res, &["crank", "rod", "slider"], i);
    let [exact, central, _] = three_jacobians(&model, res.time[i], &y);
    let scale = largest(&central);
    let off = largest(&(&exact - &central));
    // Measured: 0.18 of 6.3e6.
    assert!(off <= 1e-6 * scale, "exact off by {off:.3e} of {scale:.3e}");
}

/// The exact Jacobian through a worn contact (the rim's angle from the search, then one
/// Newton step on `delta' = 0` in the recording, so that it turns with the state as the
/// implicit function theorem says), on the founding case with a bearing worn into an
/// oval, in sliding contact mid-run: against central differences of the whole
/// equations of motion. With the rim's angle held, the normal would not turn with the
/// eccentricity, and the Jacobian would lose the contact force over the eccentricity.
#[test]
fn exact_jacobian_through_a_worn_contact_matches_central_differences() {
    let oval: Vec<f64> =
        (0..24).map(|k| 2e-5 * (1.0 + (std::f64::consts::TAU * k as f64 / 12.0).cos())).collect();
    let model = crate::compiled::worn_founding_case(serde_json::json!({"bearing_wear": oval}));
    let [exact, central, _] = jacobians_in_sliding_contact(&model);
    let scale = largest(&central);
    let off = largest(&(&exact - &central));
    // Measured: 3.4 of 1.4e8; 7.8e6 with the rim's angle held (no Newton step).
    assert!(off <= 1e-7 * scale, "exact off by {off:.3e} of {scale:.3e}");
}

/// The exact Jacobian of a spatial mechanism: the spatial four-bar with its ball sliding
/// in its socket mid-run, against central differences of the whole equations of motion
/// over the positions (the quaternions' four entries each, which the reading normalises)
/// and the velocities.
#[test]
fn exact_jacobian_of_a_spatial_mechanism_matches_central_differences() {
    let model = common::spatial_four_bar_clearance();
    let (exact, central) = spatial_jacobians(&model, 0.2, "coupler_rocker", &["crank", "coupler", "rocker"]);
    let scale = largest(&central);
    let off = largest(&(&exact - &central));
    assert!(scale > 1e6, "the contact's stiffness shows: {scale:.3e}");
    // Measured: 0.18 of 6.3e6.
    assert!(off <= 1e-6 * scale, "exact off by {off:.3e} of {scale:.3e}");
}

/// The exact Jacobian through a spatial worn contact: a journal tilted in a bearing
/// worn into an oval (20 um), pressed by a load and spinning, both ends sliding on
/// the wall, each end's rim searched in its section; against central differences of
/// the whole equations of motion.
#[test]
fn exact_jacobian_through_a_spatial_worn_contact_matches_central_differences() {
    let mut journal = crate::spatial_joint_kinds::lubricated_journal(200.0, 100.0, 1e-3, [0.0; 3], [1e-3; 3]);
    let dry = journal["joints"][0].as_object_mut().unwrap();
    dry.remove("lubrication");
    dry.insert("type".into(), serde_json::json!("clearance_cylindrical"));
    let oval: Vec<f64> =
        (0..24).map(|k| 2e-5 * (1.0 + (std::f64::consts::TAU * k as f64 / 12.0).cos())).collect();
    journal["joints"][0]["clearance"]["bearing_wear"] = serde_json::json!(oval);
    let (exact, central) = spatial_jacobians(&journal, 0.05, "bearing.p1", &["journal"]);
    let scale = largest(&central);
    let off = largest(&(&exact - &central));
    assert!(scale > 1e6, "the contact's stiffness shows: {scale:.3e}");
    // Measured: 0.010 of 1.8e8; 6.8e6 with the rims' angles held (no Newton step).
    assert!(off <= 1e-6 * scale, "exact off by {off:.3e} of {scale:.3e}");
}

/// The exact Jacobian of the spatial `model` (JSON, SI units) and central differences
/// of its whole equations of motion over the positions (the quaternions' four entries
/// each, which the reading normalises) and the velocities, at the last output sample
/// before `t_end` where `point` (a contact point's channel prefix) slides in contact,
/// the state read from the channels of `bodies`.
fn spatial_jacobians(
    model: &serde_json::Value,
    t_end: f64,
    point: &str,
    bodies: &[&str],
) -> (DMatrix<f64>, DMatrix<f64>) {
    let model = SpatialModel::from_json(&model.to_string()).unwrap();
    let opts = SimOptions { rate: Some(10_000.0), ..SimOptions::new(t_end) };
    let res = simulate_spatial(&model, &opts, &mut Silent).unwrap();
    let pen = res.channel(&format!("{point}.penetration")).unwrap();
    let slip = res.channel(&format!("{point}.slip")).unwrap();
    let i = (0..pen.len()).rev().find(|&i| pen[i] > 1e-7 && slip[i].abs() > 0.0102).expect("sliding contact");
    let read = |names: &[&str]| -> Vec<f64> {
        let channel = |n: String| res.channel(&n).unwrap_or_else(|| panic!("channel {n}"))[i];
        bodies.iter().flat_map(|b| names.iter().map(move |c| channel(format!("{b}.{c}")))).collect()
    };
    let mut y = read(&["x", "y", "z", "e0", "e1", "e2", "e3"]);
    y.extend(read(&["vx", "vy", "vz", "wx", "wy", "wz"]));
    let t = res.time[i];
    let prepared = prepare_model::<Spatial>(&model).unwrap();
    let sys = &prepared.system;
    let (nq, nv) = (sys.layout.nq(), sys.layout.nv());
    let mut ode = Ode::new(sys, prepared.initial.active.clone(), 1e-7, 1e-10);
    ode.ws.compile(false, true).unwrap();
    let mut f0 = vec![0.0; nq + nv];
    ode.rhs(t, &y, &mut f0).unwrap();
    let mut exact = DMatrix::zeros(nv, nq + nv);
    assert!(jointgap_core::dynamics::compiled::jacobian(sys, t, &y[..nq], &y[nq..], &mut ode.ws, &mut exact));
    let mut central = DMatrix::zeros(nv, nq + nv);
    let (mut up, mut down) = (vec![0.0; nq + nv], vec![0.0; nq + nv]);
    // The differences' own error is their truncation (h^2) above these increments and
    // their rounding below (measured on the four-bar: 4.0e3, 4.5e2, 62 and 1.9e2 of 3.2e8
    // at position increments 3e-9, 1e-9, 3e-10 and 1e-10): the bound is a few times the
    // smallest.
    for j in 0..nq + nv {
        let step = if j < nq { 3e-10 } else { 1e-6 };
        let mut yp = y.clone();
        yp[j] = y[j] + step;
        ode.rhs(t, &yp, &mut up).unwrap();
        yp[j] = y[j] - step;
        ode.rhs(t, &yp, &mut down).unwrap();
        for r in 0..nv {
            central[(r, j)] = (up[nq + r] - down[nq + r]) / (2.0 * step);
        }
    }
    (exact, central)
}
