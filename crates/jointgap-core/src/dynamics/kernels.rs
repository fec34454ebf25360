//! One evaluation of the equations of motion in any number type, for each body kind: the
//! bodies' states, the active constraint rows, the applied forces `Qe` (gravity, the
//! gyroscopic moments, force elements, contact loads) and the augmented solve, in the
//! order and with the operations of [`super::accelerations_for_integration`]. The
//! compiled stage ([`super::compiled`]) records it on traced numbers; what it returns is
//! the stage's outputs, what it reads its inputs (docs/compiled.md).

use crate::mechanics::contact::geometry::{
    read_found, search_cylinder, search_worn, write_found, CylinderBearing, SliderGuide, Worn, CORNERS3,
    FOUND,
};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::contact::spatial::{SpatialClearance, SpatialGeometry};
use crate::mechanics::contact::{self, onset_for, ClearanceJoint, ClearanceRevolute, ContactState};
use crate::mechanics::drivers::Motion;
use crate::mechanics::forces::ForceElement;
use crate::mechanics::kind::{BodyKind, RowEval};
use crate::mechanics::layout::{block, Layout, Loads};
use crate::mechanics::planar::Planar;
use crate::mechanics::planar_body;
use crate::mechanics::spatial::body as spatial_body;
use crate::mechanics::spatial::forces::SpatialForce;
use crate::mechanics::spatial::kind::Spatial;
use crate::scalar::Real;
use crate::system::System;

use super::Workspace;

/// A body kind's kernels in any number type `T`, `N` velocities per body.
pub trait Kernels<const N: usize>: BodyKind {
    /// A body's state in `T`.
    type StateOf<T: Real>: Copy;
    /// Numbers an applied load's table gives at a time.
    const TABLE: usize;

    /// A body's state from its positions and velocities.
    fn state_of<T: Real>(q: &[T], v: &[T]) -> Self::StateOf<T>;
    /// The ground's state.
    fn ground_of<T: Real>() -> Self::StateOf<T>;
    /// A constraint row at the bodies' states.
    fn row_of<T: Real>(
        row: &Self::RowKind,
        bi: &Self::StateOf<T>,
        bj: &Self::StateOf<T>,
        motion: Motion<T>,
    ) -> RowEval<[T; N], T>;
    /// Adds a body's weight and the loads of its own motion to its generalised forces.
    fn add_body_loads<T: Real>(
        qe: &mut [T],
        mass: f64,
        inertia: &Self::Inertia,
        gravity: &Self::Vector,
        state: &Self::StateOf<T>,
    );
    /// Whether a force element's load comes from a table of time (an input of the
    /// stage).
    fn has_table(f: &Self::Force) -> bool;
    /// Appends a force element's table value at time `t` to `x` (`Self::TABLE`
    /// numbers).
    fn table_at(f: &Self::Force, t: f64, x: &mut Vec<f64>);
    /// Adds a force element's loads, `applied` its table value (`Self::TABLE` numbers,
    /// or none).
    fn add_force_loads<T: Real>(
        f: &Self::Force,
        applied: &[T],
        state: impl Fn(Option<usize>) -> Self::StateOf<T>,
        loads: &mut Loads<T>,
    );
    /// The numbers a clearance joint's search gives at a state: where the rims of its
    /// worn profiles lie ([`crate::mechanics::contact::geometry::Worn::search`]), which
    /// the compiled code reads as inputs. None for the other joints.
    fn searched(c: &Self::Clearance) -> usize;
    /// Appends the [`Kernels::searched`] numbers of a clearance joint's search at its
    /// bodies' states `(i, j)`.
    fn search(c: &Self::Clearance, i: &Self::StateOf<f64>, j: &Self::StateOf<f64>, x: &mut Vec<f64>);
    /// `qe` (laid out as `to` says) with a clearance joint's contact loads added
    /// (`onset(k, rate)`: the impact onset speed of its point `k`; `found`: what its
    /// search gave, [`Kernels::search`]), each part with branches of its own (the
    /// joint, or each of its points) a block ([`in_block`]); `None` where a block gives
    /// none.
    fn add_clearance_loads<T: Real>(
        c: &Self::Clearance,
        parts: (&Self::StateOf<T>, &Self::StateOf<T>),
        found: &[T],
        onset: impl Fn(usize, T) -> T,
        to: LoadsOf,
        qe: Vec<T>,
    ) -> Option<Vec<T>>;
}

/// Appends the inputs of a stage after `q` and `v` (which `x` holds): the motion of
/// each driven active row (position, speed, acceleration) at time `t` (the piece of time
/// `t_piece`), the table values of the applied loads, and for each clearance joint its
/// points' states (in contact, 1 or 0, and the onset speed) and what its search finds
/// at `(q, v)` ([`Kernels::search`]).
pub fn inputs<K: Kernels<N>, const N: usize>(
    sys: &System<K>,
    active: &[usize],
    t: f64,
    t_piece: f64,
    contacts: &[ContactState],
    x: &mut Vec<f64>,
) {
    for &r in active {
        if let Some(d) = sys.rows[r].driver {
            let m = sys.drivers[d].profile.motion_on(t, t_piece);
            x.extend([m.position, m.speed, m.acceleration]);
        }
    }
    for f in sys.forces.iter().filter(|f| K::has_table(f)) {
        K::table_at(f, t, x);
    }
    let state_of = |s: &ContactState| [if s.in_contact { 1.0 } else { 0.0 }, s.onset_speed];
    if sys.clearances.iter().all(|c| K::searched(c) == 0) {
        for s in contacts {
            x.extend(state_of(s));
        }
        return;
    }
    let (nq, nv) = (sys.layout.nq(), sys.layout.nv());
    for (_, c, points) in contact::slots(&sys.clearances) {
        for s in &contacts[points] {
            x.extend(state_of(s));
        }
        if K::searched(c) > 0 {
            let state = |b: Option<usize>| match b {
                Some(k) => {
                    let slot = &sys.layout.slots()[k];
                    K::state_of(&x[..nq][slot.q()], &x[nq..nq + nv][slot.v()])
                }
                None => K::ground_of(),
            };
            let [i, j] = c.parts();
            let (i, j) = (state(i), state(j));
            K::search(c, &i, &j, x);
        }
    }
}

/// The outputs of the stage at inputs `x` ([`inputs`], after `q` and `v`): per active
/// row `C`, `dC/dt`, `gamma` and its two Jacobian blocks, then `Qe`, the accelerations,
/// the Schur complement's multipliers and each prescribed body's inverse block. The
/// sequence of [`super::accelerations_for_integration`]; `None` where it leaves the
/// plain solve or meets a joint not written over `T`.
pub fn evaluation<K: Kernels<N>, const N: usize, T: Real>(
    sys: &System<K>,
    ws: &Workspace<K>,
    x: &[T],
) -> Option<Vec<T>> {
    let active = &ws.active;
    let (nq, nv) = (sys.layout.nq(), sys.layout.nv());
    let (q, v) = (&x[..nq], &x[nq..nq + nv]);
    let mut at = nq + nv;
    let mut next = |count: usize| {
        at += count;
        &x[at - count..at]
    };
    let bodies: Vec<K::StateOf<T>> =
        sys.layout.slots().iter().map(|s| K::state_of(&q[s.q()], &v[s.v()])).collect();
    let ground = K::ground_of::<T>();
    let state = |b: Option<usize>| b.map_or(ground, |k| bodies[k]);
    let zero = T::constant(0.0);
    let mut out = Vec::with_capacity(active.len() * (3 + 2 * N) + 2 * nv);
    let mut blocks: Vec<[[T; N]; 2]> = Vec::with_capacity(active.len());
    let mut gamma = Vec::with_capacity(active.len());
    for &r in active {
        let row = &sys.rows[r];
        let motion = match row.driver {
            Some(_) => {
                let m = next(3);
                Motion { position: m[0], speed: m[1], acceleration: m[2] }
            }
            None => Motion { position: zero, speed: zero, acceleration: zero },
        };
        let ev = K::row_of(&row.kind, &state(row.body_i), &state(row.body_j), motion);
        out.extend([ev.c, ev.ct, ev.gamma]);
        out.extend(ev.jac_i);
        out.extend(ev.jac_j);
        blocks.push([ev.jac_i, ev.jac_j]);
        gamma.push(ev.gamma);
    }
    let mut qe = vec![zero; nv];
    for ((b, slot), s) in sys.bodies.iter().zip(sys.layout.slots()).zip(&bodies) {
        K::add_body_loads(&mut qe[slot.v()], b.mass, &b.inertia, &sys.gravity, s);
    }
    let mut loads = Loads::new(&sys.layout, &mut qe);
    for f in &sys.forces {
        let applied = if K::has_table(f) { next(K::TABLE) } else { &[] };
        K::add_force_loads(f, applied, state, &mut loads);
    }
    for (_, c, points) in contact::slots(&sys.clearances) {
        let s = next(2 * points.len());
        let onset = |k: usize, rate| onset_for(s[2 * k], s[2 * k + 1], rate);
        let found = next(K::searched(c));
        let [i, j] = c.parts();
        let to = LoadsOf { layout: &sys.layout, parts: [i, j] };
        qe = K::add_clearance_loads(c, (&state(i), &state(j)), found, onset, to, qe)?;
    }
    // The solve of [`super::accelerations_for_integration`], operation for operation.
    let mut qdd: Vec<T> = qe.iter().zip(&ws.m_inv).map(|(f, m)| *f * *m).collect();
    out.extend(qe);
    let dot = |a: usize, x: &[T]| ws.jac[a].dot_of([&blocks[a][0], &blocks[a][1]], x);
    let mut inverses = Vec::with_capacity(ws.prescribed.len());
    let mut lambda = Vec::with_capacity(ws.dynamic);
    if !active.is_empty() {
        for p in &ws.prescribed {
            let b_inv = p.inverse_of(|a, side| planar_block(&blocks[a][side])).ok()?;
            p.solve_rows_of(dot, &b_inv, |a| gamma[a], &mut qdd);
            inverses.push(b_inv);
        }
        lambda.extend((0..ws.dynamic).map(|a| dot(a, &qdd) - gamma[a]));
        if !lambda.is_empty() {
            ws.schur
                .solve_plain(&ws.jac[..ws.dynamic], &blocks[..ws.dynamic], &ws.m_inv, &mut lambda)?
                .ok()?;
        }
        let mut correction = vec![zero; nv];
        for ((row, block), &m) in ws.jac.iter().zip(&blocks).zip(&lambda) {
            row.add_transposed_of([&block[0], &block[1]], m, &mut correction);
        }
        for ((a, c), m) in qdd.iter_mut().zip(&correction).zip(&ws.m_inv) {
            *a -= *c * *m;
        }
    }
    out.extend(qdd);
    out.extend(lambda);
    out.extend(inverses.iter().flatten().flatten());
    Some(out)
}

/// Where a clearance joint's loads go: the layout of `Qe` and the joint's two bodies.
#[derive(Debug, Clone, Copy)]
pub struct LoadsOf<'a> {
    layout: &'a Layout,
    parts: [Option<usize>; 2],
}

/// `qe` with the loads that `add` adds to the joint's bodies (`to`), recorded as a block
/// of their own: a part of the evaluation whose branches (in contact or not, a friction
/// regime) are its own ([`Real::block`]), whose outputs are the two bodies' entries of
/// `Qe`. `None` where `add` gives none.
fn in_block<T: Real>(
    to: LoadsOf,
    mut qe: Vec<T>,
    add: impl FnOnce(&mut Loads<T>) -> Option<()>,
) -> Option<Vec<T>> {
    let mut entries: Vec<usize> = to.parts.iter().flatten().flat_map(|&b| to.layout.slot(b).v()).collect();
    entries.sort_unstable();
    entries.dedup();
    if entries.is_empty() {
        // Both parts the ground: nothing takes the loads.
        return Some(qe);
    }
    let out = T::block(&qe, |before| {
        let mut qe = before.to_vec();
        add(&mut Loads::new(to.layout, &mut qe))?;
        Some(entries.iter().map(|&k| qe[k]).collect())
    })?;
    for (&k, value) in entries.iter().zip(out) {
        qe[k] = value;
    }
    Some(qe)
}

/// A row's block on a prescribed body, which is planar ([`super::prescribed::split`]).
fn planar_block<T: Real, const N: usize>(b: &[T; N]) -> [T; planar_body::NV] {
    std::array::from_fn(|d| b[d])
}

impl Kernels<{ planar_body::NV }> for Planar {
    type StateOf<T: Real> = planar_body::BodyState<T>;
    const TABLE: usize = 2;

    fn state_of<T: Real>(q: &[T], v: &[T]) -> planar_body::BodyState<T> {
        planar_body::BodyState::read(block(q, 0), block(v, 0))
    }

    fn ground_of<T: Real>() -> planar_body::BodyState<T> {
        planar_body::BodyState::ground()
    }

    fn row_of<T: Real>(
        row: &Self::RowKind,
        bi: &planar_body::BodyState<T>,
        bj: &planar_body::BodyState<T>,
        motion: Motion<T>,
    ) -> RowEval<[T; planar_body::NV], T> {
        row.eval(bi, bj, motion)
    }

    fn add_body_loads<T: Real>(
        qe: &mut [T],
        mass: f64,
        _: &f64,
        gravity: &Self::Vector,
        _: &planar_body::BodyState<T>,
    ) {
        planar_body::add_weight(qe, mass, *gravity);
    }

    fn has_table(f: &ForceElement) -> bool {
        matches!(f, ForceElement::AppliedForce { .. } | ForceElement::AppliedTorque { .. })
    }

    fn table_at(f: &ForceElement, t: f64, x: &mut Vec<f64>) {
        x.extend(f.applied_at(t));
    }

    fn add_force_loads<T: Real>(
        f: &ForceElement,
        applied: &[T],
        state: impl Fn(Option<usize>) -> planar_body::BodyState<T>,
        loads: &mut Loads<T>,
    ) {
        let zero = T::constant(0.0);
        f.add_loads([0, 1].map(|k| applied.get(k).copied().unwrap_or(zero)), state, loads);
    }

    fn searched(c: &PlanarClearance) -> usize {
        if worn_revolute(c).is_some() {
            FOUND
        } else {
            0
        }
    }

    fn search(c: &PlanarClearance, i: &planar_body::BodyState, j: &planar_body::BodyState, x: &mut Vec<f64>) {
        if let Some((r, worn)) = worn_revolute(c) {
            write_found(&search_worn(&r.geometry, worn, i, j, r.reach()), x);
        }
    }

    /// A block in its guide adds each corner as a block of its own: its four corners'
    /// branches would otherwise multiply.
    fn add_clearance_loads<T: Real>(
        c: &PlanarClearance,
        (i, j): (&planar_body::BodyState<T>, &planar_body::BodyState<T>),
        found: &[T],
        onset: impl Fn(usize, T) -> T,
        to: LoadsOf,
        qe: Vec<T>,
    ) -> Option<Vec<T>> {
        let whole = |qe, add: &dyn Fn(&mut Loads<T>)| {
            in_block(to, qe, |loads| {
                add(loads);
                Some(())
            })
        };

        match c {
            PlanarClearance::Revolute(r) => match &r.worn {
                Some(worn) => {
                    whole(qe, &|loads| r.add_worn_loads(worn, &read_found(found), i, j, &onset, loads))
                }
                None => whole(qe, &|loads| r.add_round_loads(i, j, &onset, loads)),
            },
            PlanarClearance::Play(p) => whole(qe, &|loads| p.add_play_loads(i, j, &onset, loads)),
            PlanarClearance::Gear(g) => {
                let m = g.mesh(i, j);
                // A mesh cycle's table is read in a block of its own: its intervals are
                // its ways, apart from the teeth's contact.
                let share = match &g.cycle {
                    Some(cycle) => T::block(&[m.theta_1], |theta| Some(vec![cycle.at(theta[0])]))?[0],
                    None => g.share_at(m.theta_1),
                };
                whole(qe, &|loads| g.add_gear_loads(&m, share, (i, j), &onset, loads))
            }
            PlanarClearance::Lubricated(l) => in_block(to, qe, |loads| {
                l.dry.add_round_loads(i, j, &onset, loads);
                l.add_film_loads(i, j, |m| l.film.loads(m), loads);
                Some(())
            }),
            PlanarClearance::Translational(t) => {
                let frames = t.geometry.frames(i, j);
                (0..SliderGuide::POINTS).try_fold(qe, |qe, k| {
                    in_block(to, qe, |loads| {
                        t.add_corner_loads(frames, (i, j), k, &onset, loads);
                        Some(())
                    })
                })
            }
        }
    }
}

/// The revolute joint of a planar clearance joint and its worn profiles, if it has them
/// (a lubricated joint has none).
fn worn_revolute(c: &PlanarClearance) -> Option<(&ClearanceRevolute, &Worn)> {
    match c {
        PlanarClearance::Revolute(r) => Some((r, r.worn.as_ref()?)),
        _ => None,
    }
}

impl Kernels<{ spatial_body::NV }> for Spatial {
    type StateOf<T: Real> = spatial_body::BodyState<T>;
    const TABLE: usize = 3;

    fn state_of<T: Real>(q: &[T], v: &[T]) -> spatial_body::BodyState<T> {
        spatial_body::BodyState::read(q, v)
    }

    fn ground_of<T: Real>() -> spatial_body::BodyState<T> {
        spatial_body::BodyState::read(
            &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0].map(T::constant),
            &[T::constant(0.0); 6],
        )
    }

    fn row_of<T: Real>(
        row: &Self::RowKind,
        bi: &spatial_body::BodyState<T>,
        bj: &spatial_body::BodyState<T>,
        motion: Motion<T>,
    ) -> RowEval<[T; spatial_body::NV], T> {
        row.eval(bi, bj, motion)
    }

    fn add_body_loads<T: Real>(
        qe: &mut [T],
        mass: f64,
        inertia: &Self::Inertia,
        gravity: &Self::Vector,
        state: &spatial_body::BodyState<T>,
    ) {
        spatial_body::add_weight(qe, mass, *gravity);
        spatial_body::add_gyroscopic(qe, inertia.moments, &state.omega);
    }

    fn has_table(f: &SpatialForce) -> bool {
        matches!(f, SpatialForce::AppliedForce { .. } | SpatialForce::AppliedTorque { .. })
    }

    fn table_at(f: &SpatialForce, t: f64, x: &mut Vec<f64>) {
        x.extend(f.applied_at(t));
    }

    fn add_force_loads<T: Real>(
        f: &SpatialForce,
        applied: &[T],
        state: impl Fn(Option<usize>) -> spatial_body::BodyState<T>,
        loads: &mut Loads<T>,
    ) {
        let zero = T::constant(0.0);
        f.add_loads([0, 1, 2].map(|k| applied.get(k).copied().unwrap_or(zero)), state, loads);
    }

    fn searched(c: &SpatialClearance) -> usize {
        if c.worn().is_some() {
            2 * FOUND
        } else {
            0
        }
    }

    fn search(
        c: &SpatialClearance,
        i: &spatial_body::BodyState,
        j: &spatial_body::BodyState,
        x: &mut Vec<f64>,
    ) {
        if let Some((g, worn)) = c.worn() {
            for found in search_cylinder(g, worn, i, j, c.reach()) {
                write_found(&found, x);
            }
        }
    }

    fn add_clearance_loads<T: Real>(
        c: &SpatialClearance,
        (i, j): (&spatial_body::BodyState<T>, &spatial_body::BodyState<T>),
        found: &[T],
        onset: impl Fn(usize, T) -> T,
        to: LoadsOf,
        qe: Vec<T>,
    ) -> Option<Vec<T>> {
        match &c.geometry {
            SpatialGeometry::Play(g) => in_block(to, qe, |loads| {
                c.add_play_loads(g, i, j, onset, loads);
                Some(())
            }),
            SpatialGeometry::Block(g) => {
                let f = g.frames(i, j);
                (0..CORNERS3.len()).try_fold(qe, |qe, k| {
                    let corner = g.corner(&f, k);
                    (2 * k..2 * k + 2).try_fold(qe, |qe, index| {
                        in_block(to, qe, |loads| {
                            c.add_wall_loads((g, &f, corner), (i, j), index, &onset, loads);
                            Some(())
                        })
                    })
                })
            }
            SpatialGeometry::Lubricated(g) => in_block(to, qe, |loads| {
                c.add_dry_loads(i, j, &onset, loads)?;
                g.add_film_loads(i, j, |m| g.film.loads(m), loads);
                Some(())
            }),
            SpatialGeometry::Cylinder(g @ CylinderBearing { worn: Some(worn), .. }) => {
                let found = [read_found(&found[..FOUND]), read_found(&found[FOUND..])];
                in_block(to, qe, |loads| {
                    c.add_worn_loads((g, worn, &found), i, j, onset, loads);
                    Some(())
                })
            }
            _ => in_block(to, qe, |loads| c.add_dry_loads(i, j, onset, loads)),
        }
    }
}
