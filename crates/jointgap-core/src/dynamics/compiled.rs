//! The first stage of an evaluation, compiled to native code: the bodies' states, the
//! active constraint rows (`C`, `Cq`, `dC/dt`, `gamma`) and the applied forces `Qe`
//! (gravity, force elements, contact loads), which [`super::constraints`] and
//! [`super::applied_forces`] compute interpreted (docs/compiled.md).
//!
//! At the first evaluation the stage records the kernels on [`Traced`] numbers, as a
//! graph with the model's constants folded, and compiles it ([`codegen`]). The graph is
//! one path through the kernels' branches (in contact or not, a friction regime); where
//! an evaluation finds that a guard of every path recorded so far fails, it records and
//! compiles the path it takes there. Each path computes what the interpreted kernels
//! compute, operation for operation, so a run gives the same bits either way.
//!
//! Inputs: `q`, `v`, the motion of each driven active row (position, speed,
//! acceleration), the table value of each applied load (two numbers), and each contact
//! point's state (in contact, 1 or 0, and its onset speed). Outputs: per active row `C`,
//! `dC/dt`, `gamma` and its two Jacobian blocks, then `Qe`.

use std::sync::Arc;

use crate::codegen::{compile_cached, Compiled};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::contact::{self, onset_for, ClearanceJoint, ClearanceRevolute, ContactState};
use crate::mechanics::drivers::Motion;
use crate::mechanics::forces::ForceElement;
use crate::mechanics::kind::BodyKind;
use crate::mechanics::layout::{block, Loads};
use crate::mechanics::planar::Planar;
use crate::mechanics::planar_body::{add_weight, BodyState};
use crate::mechanics::spatial::kind::Spatial;
use crate::scalar::{record, Graph, Real};
use crate::system::System;

use super::Workspace;

/// Paths a run compiles at most; past them, an evaluation that none of them covers runs
/// interpreted.
pub const MAX_PATHS: usize = 16;

/// How the rows and forces of a system of kind `K` are recorded and fed.
#[derive(Debug, Clone, Copy)]
pub struct Recorder<K: BodyKind> {
    /// The graph of the active rows `active` and the forces at inputs `x`.
    record: fn(&System<K>, &[usize], &[f64]) -> Graph,
    /// Appends the inputs after `q` and `v`: the driven rows' motions at time `t` (the
    /// piece of time `t_piece`), the applied loads' table values, the contact states.
    inputs: Feed<K>,
}

/// Appends a stage's inputs after `q` and `v` for the system, its active rows, time
/// `t`, the piece of time `t_piece` and the contact states.
type Feed<K> = fn(&System<K>, &[usize], f64, f64, &[ContactState], &mut Vec<f64>);

/// What a body kind gives the compiled stage.
pub trait Compile: BodyKind {
    /// How the rows and forces of `sys` are recorded, or why they are not compiled.
    fn recorder(sys: &System<Self>) -> Result<Recorder<Self>, String>;
}

/// The compiled stage of one run: its paths and what they cost.
#[derive(Debug, Clone)]
pub struct Stage<K: BodyKind> {
    recorder: Recorder<K>,
    paths: Vec<Arc<Compiled>>,
    /// The path that ran last, tried first.
    last: usize,
    inputs: Vec<f64>,
    outputs: Vec<f64>,
    /// Seconds spent compiling (paths taken from the process's cache cost none).
    pub compile_seconds: f64,
    /// Paths compiled during this run.
    pub compiled_now: usize,
    /// Paths taken from the process's cache.
    pub from_cache: usize,
    /// Evaluations the compiled code did, and those that ran interpreted.
    pub evaluations: [usize; 2],
    /// Why the stage stopped compiling (a code generation error), if it did.
    pub stopped: Option<String>,
}

impl<K: BodyKind> Stage<K> {
    /// The stage of a run, recorded by `recorder` as the run needs its paths.
    pub fn new(recorder: Recorder<K>) -> Self {
        Stage {
            recorder,
            paths: Vec::new(),
            last: 0,
            inputs: Vec::new(),
            outputs: Vec::new(),
            compile_seconds: 0.0,
            compiled_now: 0,
            from_cache: 0,
            evaluations: [0; 2],
            stopped: None,
        }
    }

    /// The one-line account of the run's compiled code.
    pub fn summary(&self) -> String {
        let [native, interpreted] = self.evaluations;
        let mut line = format!(
            "native code: {} paths ({} compiled in {:.1} ms, {} from the cache), {native} evaluations \
             compiled, {interpreted} interpreted",
            self.paths.len(),
            self.compiled_now,
            1e3 * self.compile_seconds,
            self.from_cache
        );
        if let Some(why) = &self.stopped {
            line += &format!(" ({why})");
        }
        line
    }
}

/// Fills the rows and forces of `ws` at `(t, q, v)` by compiled code; `false` where none
/// covers this state (the caller then evaluates them interpreted).
pub fn rows_and_forces<K: BodyKind>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
) -> bool {
    let Some(stage) = ws.compiled.as_mut() else {
        return false;
    };
    stage.inputs.clear();
    stage.inputs.extend_from_slice(q);
    stage.inputs.extend_from_slice(v);
    (stage.recorder.inputs)(sys, &ws.active, t, ws.t_piece, &ws.contacts, &mut stage.inputs);
    let n = stage.paths.len();
    let covered = (0..n)
        .map(|k| (stage.last + k) % n)
        .find(|&k| stage.paths[k].call(&stage.inputs, &mut stage.outputs));
    let found = match covered {
        Some(k) => Some(k),
        None if stage.paths.len() < MAX_PATHS && stage.stopped.is_none() => {
            match compile_cached(&(stage.recorder.record)(sys, &ws.active, &stage.inputs)) {
                Ok((code, fresh)) => {
                    if fresh {
                        stage.compile_seconds += code.compile_seconds;
                        stage.compiled_now += 1;
                    } else {
                        stage.from_cache += 1;
                    }
                    stage.outputs.resize(code.outputs(), 0.0);
                    stage.paths.push(code);
                    let k = stage.paths.len() - 1;
                    // A path holds where it was recorded.
                    stage.paths[k].call(&stage.inputs, &mut stage.outputs).then_some(k)
                }
                Err(e) => {
                    stage.stopped = Some(e.0);
                    None
                }
            }
        }
        None => None,
    };
    let Some(k) = found else {
        stage.evaluations[1] += 1;
        return false;
    };
    stage.last = k;
    stage.evaluations[0] += 1;
    let nb = K::SHAPE.nv;
    let per_row = 3 + 2 * nb;
    let out = &stage.outputs;
    for (a, row) in ws.jac.iter_mut().enumerate() {
        let o = &out[a * per_row..(a + 1) * per_row];
        ws.c[a] = o[0];
        ws.ct[a] = o[1];
        ws.gamma[a] = o[2];
        row.entries[0].as_mut().copy_from_slice(&o[3..3 + nb]);
        row.entries[1].as_mut().copy_from_slice(&o[3 + nb..per_row]);
    }
    ws.qe.copy_from_slice(&out[ws.jac.len() * per_row..]);
    true
}

/// The round dry revolute clearance joints of `sys`, or why a clearance joint of it is
/// not compiled.
fn round_revolutes(sys: &System<Planar>) -> Result<Vec<&ClearanceRevolute>, String> {
    sys.clearances
        .iter()
        .map(|c| match c {
            PlanarClearance::Revolute(r) if r.worn.is_none() => Ok(r),
            other => {
                let what = match other {
                    PlanarClearance::Revolute(_) => "a worn profile",
                    PlanarClearance::Lubricated(_) => "an oil film",
                    PlanarClearance::Translational(_) => "a block in its guide",
                    PlanarClearance::Play(_) => "a joint's play",
                    PlanarClearance::Gear(_) => "a gear mesh",
                };
                Err(format!("joint '{}' has {what}, which is not compiled yet", other.name()))
            }
        })
        .collect()
}

impl Compile for Planar {
    fn recorder(sys: &System) -> Result<Recorder<Planar>, String> {
        round_revolutes(sys)?;
        Ok(Recorder {
            record: |sys, active, x| record(x, |x| planar_rows_and_forces(sys, active, x)),
            inputs: planar_inputs,
        })
    }
}

/// The inputs of a planar system's stage after `q` and `v` ([`Recorder`]).
fn planar_inputs(
    sys: &System,
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
    for f in sys.forces.iter().filter(|f| has_table(f)) {
        x.extend(f.applied_at(t));
    }
    for s in contacts {
        x.extend([if s.in_contact { 1.0 } else { 0.0 }, s.onset_speed]);
    }
}

/// Whether a force element's load comes from a table of time (an input of the stage).
fn has_table(f: &ForceElement) -> bool {
    matches!(f, ForceElement::AppliedForce { .. } | ForceElement::AppliedTorque { .. })
}

/// The outputs of the stage at inputs `x`, in any number type: the sequence of
/// [`super::constraints`] and [`super::applied_forces`] for a planar system.
fn planar_rows_and_forces<T: Real>(sys: &System, active: &[usize], x: &[T]) -> Vec<T> {
    let (nq, nv) = (sys.layout.nq(), sys.layout.nv());
    let (q, v) = (&x[..nq], &x[nq..nq + nv]);
    let mut at = nq + nv;
    let mut next = |count: usize| {
        at += count;
        &x[at - count..at]
    };
    let bodies: Vec<BodyState<T>> =
        sys.layout.slots().iter().map(|s| BodyState::read(block(q, s.q_at), block(v, s.v_at))).collect();
    let ground = BodyState::ground();
    let state = |b: Option<usize>| b.map_or(ground, |k| bodies[k]);
    let zero = T::constant(0.0);
    let mut out = Vec::with_capacity(active.len() * 9 + nv);
    for &r in active {
        let row = &sys.rows[r];
        let motion = match row.driver {
            Some(_) => {
                let m = next(3);
                Motion { position: m[0], speed: m[1], acceleration: m[2] }
            }
            None => Motion { position: zero, speed: zero, acceleration: zero },
        };
        let ev = row.kind.eval(&state(row.body_i), &state(row.body_j), motion);
        out.extend([ev.c, ev.ct, ev.gamma]);
        out.extend(ev.jac_i);
        out.extend(ev.jac_j);
    }
    let mut qe = vec![zero; nv];
    for (b, slot) in sys.bodies.iter().zip(sys.layout.slots()) {
        add_weight(&mut qe[slot.v()], b.mass, sys.gravity);
    }
    let mut loads = Loads::new(&sys.layout, &mut qe);
    for f in &sys.forces {
        let applied = if has_table(f) {
            let a = next(2);
            [a[0], a[1]]
        } else {
            [zero; 2]
        };
        f.add_loads(applied, state, &mut loads);
    }
    if let Ok(joints) = round_revolutes(sys) {
        for ((_, _, points), c) in contact::slots(&sys.clearances).zip(joints) {
            let s = next(2 * points.len());
            let [i, j] = c.parts();
            c.add_round_loads(
                &state(i),
                &state(j),
                |k, rate| onset_for(s[2 * k], s[2 * k + 1], rate),
                &mut loads,
            );
        }
    }
    out.extend(qe);
    out
}

impl Compile for Spatial {
    fn recorder(_: &System<Spatial>) -> Result<Recorder<Spatial>, String> {
        Err("a spatial model's kernels are not yet written over the number type that compiling records"
            .into())
    }
}

impl<K: Compile> Workspace<K> {
    /// Compiles the rows and forces of `sys` as the run needs them, or says why they
    /// stay interpreted.
    pub fn compile(&mut self, sys: &System<K>) -> Result<(), String> {
        self.compiled = Some(Stage::new(K::recorder(sys)?));
        Ok(())
    }
}
