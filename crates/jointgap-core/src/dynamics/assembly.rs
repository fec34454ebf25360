//! Initial conditions: Newton solve of the position constraints (and of the joint
//! coordinates given at t = 0) from the user's approximate placement, detection of
//! redundant rows, then the velocity constraints (and the given joint rates).

use nalgebra::{DMatrix, DVector};

use super::{constraints, Contacts, Workspace};
use crate::error::{ElementError, Error};
use crate::mechanics::drivers::Motion;
use crate::mechanics::kind::RowEval;
use crate::system::{InitialCondition, Owner, System};

/// Residual that counts as assembled [m or rad].
const ASSEMBLY_TOL: f64 = 1e-12;
/// A row whose part independent of the earlier rows is smaller than this fraction of its
/// norm is redundant.
const REDUNDANT_TOL: f64 = 1e-8;

/// Consistent initial state of a system.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Coordinates satisfying `C(q, 0) = 0`.
    pub q: Vec<f64>,
    /// Velocities satisfying `Cq v + Ct = 0`.
    pub v: Vec<f64>,
    /// Indices of the independent rows.
    pub active: Vec<usize>,
    /// Redundant rows removed, one note each.
    pub warnings: Vec<String>,
}

/// Minimum-norm solution of `A x = b` (least squares when inconsistent).
fn min_norm_solve(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let svd = a.clone().svd(true, true);
    let tol = 1e-10 * svd.singular_values.max().max(1e-300);
    svd.solve(b, tol).unwrap_or_else(|_| DVector::zeros(a.ncols()))
}

/// Assembles the mechanism at t = 0: the joints, the drivers and the joint coordinates
/// given as initial conditions hold exactly; the placement and the bodies' velocities
/// change as little as they must (a warning names each given velocity that changes).
pub fn assemble<K: Contacts>(sys: &System<K>) -> Result<Assembled, Error> {
    let mut q = sys.q_guess.clone();
    let v0 = sys.v_guess.clone();
    let t = 0.0;
    let placing: Vec<&InitialCondition<K>> = sys.initial_conditions.iter().filter(|ic| ic.placed).collect();
    if let Err(fit) = solve_positions(sys, t, &mut q, &v0, &placing) {
        if !placing.is_empty() {
            check_initial_conditions(sys, &q, &v0)?; // over-specified: say so
        }
        let m = sys.rows.len();
        let mut off: Vec<(usize, f64)> =
            fit.iter().enumerate().filter(|(_, c)| c.abs() > 1e-6).map(|(r, c)| (r, c.abs())).collect();
        off.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap());
        let mut names: Vec<String> = Vec::new();
        for (r, c) in off {
            let who = if r < m { element_name(sys, sys.rows[r].owner) } else { placing[r - m].label.clone() };
            if !names.iter().any(|n| n.starts_with(&who)) {
                names.push(format!("{who} (off by {c:.3e})"));
            }
        }
        if names.is_empty() {
            names.push("the constraints as a whole".into());
        }
        return Err(Error::Assembly(format!(
            "cannot assemble the mechanism from the given placement: {} cannot be satisfied; \
             check the joint points, the body positions and angles, the driver's initial value \
             and the joints' initial coordinates",
            names.join(", ")
        )));
    }
    let (active, warnings, given) = check_initial_conditions(sys, &q, &v0)?;
    // Velocities: the smallest change of the user's values that satisfies Cq v = -Ct and
    // gives each joint rate that was given.
    let mut ws = Workspace::in_order(sys, active.clone());
    constraints(sys, t, &q, &v0, &mut ws);
    let rates: Vec<(usize, f64)> =
        sys.initial_conditions.iter().enumerate().filter_map(|(a, ic)| ic.rate.map(|w| (a, w))).collect();
    let m = active.len();
    let mut cq = ws.dense_jacobian().resize_vertically(m + rates.len(), 0.0);
    let mut target = (-&ws.ct).resize_vertically(m + rates.len(), 0.0);
    for (b, &(a, rate)) in rates.iter().enumerate() {
        cq.set_row(m + b, &given.row(a));
        target[m + b] = rate;
    }
    let mut v = v0.clone();
    if cq.nrows() > 0 {
        let resid = &cq * DVector::from_column_slice(&v0) - target;
        let dv = min_norm_solve(&cq, &resid);
        for j in 0..v.len() {
            v[j] -= dv[j];
        }
    }
    let mut warnings = warnings;
    warnings.extend(changed_velocities(sys, &v0, &v));
    Ok(Assembled { q, v, active, warnings })
}

/// Residuals and Jacobian at `(t, q)` of the joints and drivers, then of the given
/// joint coordinates `placing`.
fn residuals<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    placing: &[&InitialCondition<K>],
    ws: &mut Workspace<K>,
) -> (DVector<f64>, DMatrix<f64>) {
    constraints(sys, t, q, v, ws);
    let m = ws.c.len();
    let mut c = ws.c.clone().resize_vertically(m + placing.len(), 0.0);
    let mut cq = ws.dense_jacobian().resize_vertically(m + placing.len(), 0.0);
    for (a, ic) in placing.iter().enumerate() {
        c[m + a] = initial_row(sys, ic, q, v, &mut cq, m + a).c;
    }
    (c, cq)
}

/// Damped Newton from `q` on the joints, drivers (at time `t`) and the given joint
/// coordinates `placing`, each step the minimum-norm one; `Err` with the residuals where
/// it stalls above [`ASSEMBLY_TOL`].
fn solve_positions<K: Contacts>(
    sys: &System<K>,
    t: f64,
    q: &mut [f64],
    v: &[f64],
    placing: &[&InitialCondition<K>],
) -> Result<(), DVector<f64>> {
    let mut ws = Workspace::in_order(sys, (0..sys.rows.len()).collect());
    let mut fit = residuals(sys, t, q, v, placing, &mut ws);
    if fit.0.nrows() == 0 {
        return Ok(());
    }
    for _ in 0..100 {
        let r0 = fit.0.amax();
        if r0 <= ASSEMBLY_TOL {
            return Ok(());
        }
        let dq = min_norm_solve(&fit.1, &fit.0);
        // Halve the step while the residual grows.
        let mut step = 1.0;
        let mut trial = q.to_vec();
        let mut next = fit.clone();
        let mut along = vec![0.0; dq.len()];
        for _ in 0..30 {
            along.iter_mut().zip(dq.iter()).for_each(|(a, d)| *a = -(step * d));
            trial.copy_from_slice(q);
            sys.displace(&mut trial, &along);
            next = residuals(sys, t, &trial, v, placing, &mut ws);
            if next.0.amax() < r0 {
                break;
            }
            step *= 0.5;
        }
        if next.0.amax() >= r0 {
            break; // stalled: the constraints cannot all be met from here
        }
        q.copy_from_slice(&trial);
        fit = next;
    }
    Err(fit.0)
}

/// The active rows, their warnings, and the Jacobian rows of the given joint coordinates.
type Checked = (Vec<usize>, Vec<String>, DMatrix<f64>);

/// The independent rows of the joints and drivers at `q` (and their warnings), and the
/// Jacobian rows of the given joint coordinates, each of which must move a coordinate the
/// joints and drivers leave free, and not one another's.
fn check_initial_conditions<K: Contacts>(sys: &System<K>, q: &[f64], v: &[f64]) -> Result<Checked, Error> {
    let at = generic_configuration(sys, q, v);
    let (active, warnings, mut basis) = independent_rows(sys, &jacobian(sys, 0.0, &at, v))?;
    let mut given = DMatrix::zeros(sys.initial_conditions.len(), sys.layout.nv());
    let mut near = DMatrix::zeros(1, sys.layout.nv());
    for (a, ic) in sys.initial_conditions.iter().enumerate() {
        initial_row(sys, ic, q, v, &mut given, a);
        initial_row(sys, ic, &at, v, &mut near, 0);
        if !independent(&mut basis, near.row(0).transpose()) {
            return Err(ElementError::assembly(
                "joint",
                &sys.joints[ic.joint].name,
                Some(if ic.placed { "initial" } else { "initial_rate" }),
                "the joints, drivers and the other initial conditions already fix this joint's \
                 coordinate; leave its initial value and rate out"
                    .into(),
            ));
        }
    }
    Ok((active, warnings, given))
}

/// The Jacobian of every joint and driver row at `(t, q)`.
fn jacobian<K: Contacts>(sys: &System<K>, t: f64, q: &[f64], v: &[f64]) -> DMatrix<f64> {
    let mut ws = Workspace::in_order(sys, (0..sys.rows.len()).collect());
    constraints(sys, t, q, v, &mut ws);
    ws.dense_jacobian()
}

/// The configuration at which the rows' independence is decided: `q` itself where its
/// rows are independent (nearly always), else the assembled configuration nearby where
/// the most rows are independent.
///
/// At a singular position (a parallelogram with all bars collinear, a change point) rows
/// that are independent everywhere else depend on one another for that instant; decided
/// there, they would be dropped for the whole run and the mechanism would leave its
/// branch after it. The rank of the Jacobian on the constraint manifold drops only at
/// such points, so it is read a small step away, where the mechanism goes: `q + h v`
/// assembled with the drivers at time `h`, `h` such that the bodies turn by about
/// [`NEARBY_STEP`] rad (and move by that fraction of the mechanism's lever arms), and the
/// same step back. Only where that finds no more independent rows (a mechanism at rest)
/// is it moved along a generic combination of its free directions, each way: such a
/// step may land on another branch of the mechanism (with the drivers held, one where a
/// driver is fixed by the joints: that configuration is not taken). Rows of a truly
/// redundant mechanism (a third parallel rocker, a joint given twice) depend on the
/// others there too and are dropped as before.
fn generic_configuration<K: Contacts>(sys: &System<K>, q: &[f64], v: &[f64]) -> Vec<f64> {
    let cq = jacobian(sys, 0.0, q, v);
    let rank = |cq: &DMatrix<f64>| {
        let mut basis = Basis::new();
        (0..cq.nrows()).filter(|&r| independent(&mut basis, cq.row(r).transpose())).count()
    };
    let rank_at_q = rank(&cq);
    if rank_at_q == cq.nrows() {
        return q.to_vec();
    }
    let mut best = (rank_at_q, q.to_vec());
    let scale = step_scale(&cq, sys.rotations());
    let along = DVector::from_column_slice(v);
    let free = free_direction(&cq);
    // Where the mechanism goes first (the drivers moving with it); only where that does not
    // help (a mechanism at rest), a generic free direction with the drivers held.
    let mut tries: Vec<Vec<(f64, DVector<f64>)>> = Vec::new();
    if let Some(h) = scale(&along) {
        tries.push(vec![(h, along.clone() * h), (-h, along * -h)]);
    }
    if let Some(h) = scale(&free) {
        tries.push(vec![(0.0, free.clone() * h), (0.0, free * -h)]);
    }
    for steps in tries {
        for (t, step) in steps {
            let mut p = q.to_vec();
            sys.displace(&mut p, step.as_slice());
            if solve_positions(sys, t, &mut p, v, &[]).is_err() {
                continue;
            }
            let cq = jacobian(sys, t, &p, v);
            let r = rank(&cq);
            if r > best.0 && independent_rows(sys, &cq).is_ok() {
                best = (r, p);
            }
        }
        if best.0 > rank_at_q {
            break;
        }
    }
    best.1
}

/// Size of the step to the configuration where the rows' independence is decided (see
/// [`generic_configuration`]): about 1e-3 rad.
const NEARBY_STEP: f64 = 1e-3;

/// The factor that makes a direction a step of [`NEARBY_STEP`]: the bodies turn by at
/// most that many radians and move by at most that fraction of the mechanism's largest
/// lever arm (the largest ratio of a row's angle entry to its position entries); `None`
/// for a zero direction.
fn step_scale(cq: &DMatrix<f64>, rotations: Vec<bool>) -> impl Fn(&DVector<f64>) -> Option<f64> {
    let (mut lever, mut unit) = (0.0f64, 0.0f64);
    for (j, column) in cq.column_iter().enumerate() {
        if rotations[j] {
            lever = lever.max(column.amax());
        } else {
            unit = unit.max(column.amax());
        }
    }
    let length = if lever > 0.0 && unit > 0.0 { lever / unit } else { 1.0 };
    move |d: &DVector<f64>| {
        let size = d.iter().enumerate().map(|(j, x)| x.abs() / if rotations[j] { 1.0 } else { length });
        let size = size.fold(0.0, f64::max);
        (size > 0.0).then(|| NEARBY_STEP / size)
    }
}

/// A generic combination of the free directions of `cq` (its null space), with weights
/// from the golden ratio's multiples: no two alike, none zero.
fn free_direction(cq: &DMatrix<f64>) -> DVector<f64> {
    let n = cq.ncols();
    // A square matrix, so that the SVD gives every right singular vector.
    let svd = cq.clone().resize_vertically(cq.nrows().max(n), 0.0).svd(false, true);
    let tol = REDUNDANT_TOL * svd.singular_values.max().max(1e-300);
    let mut direction = DVector::zeros(n);
    if let Some(vt) = svd.v_t {
        for k in (0..n).filter(|&k| svd.singular_values[k] <= tol) {
            direction += vt.row(k).transpose() * (0.5 + ((k + 1) as f64 * 0.618_033_988_749_895).fract());
        }
    }
    direction
}

/// Evaluates a given joint coordinate's row at `(q, v)` and writes its Jacobian into row
/// `a` of `cq`.
fn initial_row<K: Contacts>(
    sys: &System<K>,
    ic: &InitialCondition<K>,
    q: &[f64],
    v: &[f64],
    cq: &mut DMatrix<f64>,
    a: usize,
) -> RowEval<K::Row> {
    let (bi, bj) = (sys.body_state(ic.body_i, q, v), sys.body_state(ic.body_j, q, v));
    let ev = K::eval(&ic.kind, &bi, &bj, Motion { position: 0.0, speed: 0.0, acceleration: 0.0 });
    cq.row_mut(a).fill(0.0);
    for (body, entries) in [(ic.body_i, ev.jac_i), (ic.body_j, ev.jac_j)] {
        if let Some(k) = body {
            let at = sys.layout.slot(k).v_at;
            for (d, e) in entries.as_ref().iter().enumerate() {
                cq[(a, at + d)] += e;
            }
        }
    }
    ev
}

/// A warning for each body velocity the user gave (non-zero) that assembly changed.
fn changed_velocities<K: Contacts>(sys: &System<K>, given: &[f64], used: &[f64]) -> Vec<String> {
    let mut out = Vec::new();
    let why = "assembly changed it to satisfy the joints and drivers; give a joint's \
               initial_rate to set a velocity that assembly keeps";
    for (b, slot) in sys.bodies.iter().zip(sys.layout.slots()) {
        let (g, u) = (&given[slot.v()], &used[slot.v()]);
        let moved = |g: f64, u: f64, scale: f64| (g - u).abs() > 1e-9 * scale.max(1e-12);
        let speed = g[0].hypot(g[1]);
        if speed > 0.0 && (moved(g[0], u[0], speed) || moved(g[1], u[1], speed)) {
            out.push(format!(
                "body '{}': velocity = [{:.6}, {:.6}] m/s was given, [{:.6}, {:.6}] m/s is used: {why}",
                b.name, g[0], g[1], u[0], u[1]
            ));
        }
        if g[2] != 0.0 && moved(g[2], u[2], g[2].abs()) {
            out.push(format!(
                "body '{}': omega = {:.6} rad/s was given, {:.6} rad/s is used: {why}",
                b.name, g[2], u[2]
            ));
        }
    }
    out
}

/// `joint 'name'` or `driver 'name'`.
pub fn element_name<K: Contacts>(sys: &System<K>, owner: Owner) -> String {
    match owner {
        Owner::Joint(k) => format!("joint '{}'", sys.joints[k].name),
        Owner::Driver(k) => format!("driver '{}'", sys.drivers[k].name),
    }
}

/// Gram-Schmidt over the Jacobian rows in model order: a row that depends on earlier
/// ones is redundant and dropped (a warning names it); a redundant driver is an error,
/// since it would fight the joints.
/// Returns the active rows, the warnings and the orthonormal basis of the active rows.
fn independent_rows<K: Contacts>(
    sys: &System<K>,
    cq: &DMatrix<f64>,
) -> Result<(Vec<usize>, Vec<String>, Basis), Error> {
    let mut basis: Basis = Vec::new();
    let mut active = Vec::new();
    let mut warnings = Vec::new();
    for r in 0..cq.nrows() {
        if independent(&mut basis, cq.row(r).transpose()) {
            active.push(r);
            continue;
        }
        let row_info = &sys.rows[r];
        if let Owner::Driver(k) = row_info.owner {
            return Err(ElementError::assembly(
                "driver",
                &sys.drivers[k].name,
                Some("joint"),
                "the driven joint cannot move, the other constraints already fix it".into(),
            ));
        }
        warnings.push(format!(
            "{}: redundant constraint equation removed (it repeats the others); the joint reactions \
             of a redundant mechanism are not unique, this one's share is reported as zero",
            row_info.label
        ));
    }
    Ok((active, warnings, basis))
}

/// An orthonormal basis of rows taken so far.
type Basis = Vec<DVector<f64>>;

/// Whether `row` has a part independent of `basis` (then added to it).
fn independent(basis: &mut Basis, row: DVector<f64>) -> bool {
    let norm = row.norm();
    let mut rest = row;
    for b in basis.iter() {
        let p = b.dot(&rest);
        rest.axpy(-p, b, 1.0);
    }
    if rest.norm() > REDUNDANT_TOL * norm.max(1e-300) {
        basis.push(rest.normalize());
        return true;
    }
    false
}
