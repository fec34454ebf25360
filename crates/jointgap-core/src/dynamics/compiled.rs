//! One evaluation of the equations of motion compiled to native code: the bodies' states,
//! the active constraint rows (`C`, `Cq`, `dC/dt`, `gamma`), the applied forces `Qe`
//! (gravity, gyroscopic moments, force elements, contact loads), and the accelerations
//! and multipliers of the augmented solve (the prescribed bodies' blocks, the Schur
//! complement's plain factor and solve), which [`super::accelerations_for_integration`]
//! computes interpreted otherwise (docs/compiled.md).
//!
//! At the first evaluation the stage records the kernels ([`super::kernels`]) on
//! [`crate::scalar::Traced`] numbers, as a graph with the model's constants folded, and
//! compiles it ([`crate::codegen`]). The graph is one path through the kernels' branches
//! (in contact or not, a friction regime); where an evaluation finds that a guard of
//! every path recorded so far fails, it records and compiles the path it takes there.
//! Each path computes what the interpreted kernels compute, operation for operation, so
//! a run gives the same bits either way. An evaluation the graphs do not cover (a Schur
//! complement that is not well conditioned, a singular prescribed block) runs
//! interpreted. The implicit methods' Jacobians are the paths' graphs differentiated
//! ([`jacobian`]); a run that does not compile still records its paths for them. The
//! inputs and outputs are [`super::kernels::inputs`]' and
//! [`super::kernels::evaluation`]'s.

use std::ops::Range;
use std::sync::Arc;

use nalgebra::DMatrix;

use crate::codegen::{compile_cached, Compiled};
use crate::mechanics::contact::ContactState;
use crate::mechanics::kind::BodyKind;
use crate::mechanics::planar::Planar;
use crate::mechanics::spatial::kind::Spatial;
use crate::scalar::{record, Graph, Sweep};
use crate::system::System;

use super::kernels::{evaluation, inputs, Kernels};
use super::schur::Factorisation;
use super::Workspace;

/// Paths a run compiles at most; past them, an evaluation that the last path used does
/// not cover runs interpreted (a mechanism with several clearance joints has as many
/// combinations of their branches as it meets).
pub const MAX_PATHS: usize = 16;
/// Operations of a recorded evaluation above which it is not compiled: compiling takes
/// about 10 us per operation, which a long run of a large mechanism repays, but a short
/// one does not (docs/compiled.md).
pub const MAX_OPERATIONS: usize = 6000;
/// Why a run whose options turn compiling off runs interpreted.
pub const TURNED_OFF: &str = "turned off by the run's options";
/// Evaluations after one that no graph covers (a Schur complement near a singular
/// position, which the plain solve does not take) before the next is recorded again.
const BACK_OFF: usize = 64;

/// How the evaluation of a system of kind `K` is recorded and fed.
#[derive(Debug, Clone, Copy)]
pub struct Recorder<K: BodyKind> {
    /// The graph of an evaluation with the workspace's rows at inputs `x`; `None` where
    /// the evaluation there takes a way that is not compiled.
    record: Record<K>,
    /// Appends the inputs after `q` and `v`: the driven rows' motions at time `t` (the
    /// piece of time `t_piece`), the applied loads' table values, the contact states.
    inputs: Feed<K>,
}

/// Records an evaluation of the system with the workspace's rows at the inputs: its graph
/// and the values of its parameters.
type Record<K> = fn(&System<K>, &Workspace<K>, &[f64]) -> Option<(Graph, Vec<f64>)>;

/// Appends a stage's inputs after `q` and `v` for the system, its active rows, time
/// `t`, the piece of time `t_piece` and the contact states.
type Feed<K> = fn(&System<K>, &[usize], f64, f64, &[ContactState], &mut Vec<f64>);

/// What a body kind gives the compiled stage.
pub trait Compile: BodyKind {
    /// How the evaluation of `sys` is recorded, or why it is not compiled.
    fn recorder(sys: &System<Self>) -> Result<Recorder<Self>, String>;
}

/// The compiled stage of one run: its paths and what they cost.
#[derive(Debug, Clone)]
pub struct Stage<K: BodyKind> {
    recorder: Recorder<K>,
    /// Whether evaluations run the paths' native code (else only their graphs serve,
    /// for the Jacobians).
    native: bool,
    /// Whether the implicit methods take their Jacobians from the paths' graphs.
    exact_jacobian: bool,
    paths: Vec<Path>,
    /// The path that ran last, tried first.
    last: usize,
    inputs: Vec<f64>,
    outputs: Vec<f64>,
    /// The adjoints of [`Graph::jacobian`], zero between calls.
    adjoints: Vec<f64>,
    /// Seconds spent compiling (paths taken from the process's cache cost none).
    pub compile_seconds: f64,
    /// Paths compiled during this run.
    pub compiled_now: usize,
    /// Paths taken from the process's cache.
    pub from_cache: usize,
    /// Evaluations the compiled code did, and those that ran interpreted.
    pub evaluations: [usize; 2],
    /// Jacobians taken exactly from a graph, and those left to the applied forces'
    /// differences (no graph covers the state).
    pub jacobians: [usize; 2],
    /// Evaluations whose recording left the compiled ways (then interpreted), in the
    /// account.
    uncovered: usize,
    /// Evaluations left before the next recording after an uncovered one.
    back_off: usize,
    /// Calls of a path whose guards failed (the next path was tried).
    pub misses: usize,
    /// Why the stage stopped compiling (a code generation error), if it did.
    pub stopped: Option<String>,
}

/// One path through the kernels' branches: its graph, its native code where the stage
/// runs native code, and the values of its parameters.
#[derive(Debug, Clone)]
struct Path {
    graph: Graph,
    code: Option<Arc<Compiled>>,
    params: Vec<f64>,
    /// The nodes between the state and the accelerations, once the path has served a
    /// Jacobian.
    sweep: Option<Sweep>,
}

impl<K: BodyKind> Stage<K> {
    /// The stage of a run, recorded by `recorder` as the run needs its paths; `native`:
    /// evaluations run the paths' native code; `exact_jacobian`: the implicit methods'
    /// Jacobians come from the paths' graphs.
    pub fn new(recorder: Recorder<K>, native: bool, exact_jacobian: bool) -> Self {
        Stage {
            recorder,
            native,
            exact_jacobian,
            paths: Vec::new(),
            last: 0,
            inputs: Vec::new(),
            outputs: Vec::new(),
            adjoints: Vec::new(),
            compile_seconds: 0.0,
            compiled_now: 0,
            from_cache: 0,
            evaluations: [0; 2],
            jacobians: [0; 2],
            uncovered: 0,
            back_off: 0,
            misses: 0,
            stopped: None,
        }
    }

    /// The one-line account of the run's compiled code and Jacobians.
    pub fn summary(&self) -> String {
        let [native, interpreted] = self.evaluations;
        let mut line = if self.native {
            let nodes: usize =
                self.paths.iter().map(|p| p.code.as_ref().map_or(p.graph.nodes.len(), |c| c.nodes)).sum();
            format!(
                "native code: {} paths of {nodes} operations ({} compiled in {:.1} ms, {} from the cache), \
                 {native} evaluations compiled, {interpreted} interpreted, {} calls of a path that did not hold",
                self.paths.len(),
                self.compiled_now,
                1e3 * self.compile_seconds,
                self.from_cache,
                self.misses
            )
        } else {
            format!("interpreted: {TURNED_OFF}; {} paths recorded", self.paths.len())
        };
        if self.uncovered > 0 {
            line += &format!(
                ", {} evaluations outside the compiled solve (a Schur complement not well conditioned or a singular prescribed block)",
                self.uncovered
            );
        }
        let [exact, forces] = self.jacobians;
        if exact + forces > 0 {
            line += &format!(", Jacobians: {exact} exact, {forces} of the applied forces only");
        }
        if let Some(why) = &self.stopped {
            line += &format!(" ({why})");
        }
        line
    }
}

/// Evaluates `ws` at `(t, q, v)` by compiled code, as
/// [`super::accelerations_for_integration`] does; `false` where none covers this state
/// (the caller then evaluates interpreted).
pub fn accelerations<K: BodyKind>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
) -> bool {
    let Some(mut stage) = ws.compiled.take_if(|s| s.native) else {
        return false;
    };
    let found = stage.run(sys, t, q, v, ws);
    if found {
        stage.evaluations[0] += 1;
        scatter(&stage.outputs, ws);
    } else {
        stage.evaluations[1] += 1;
    }
    ws.compiled = Some(stage);
    found
}

/// Writes the acceleration rows of `df/dy` at `(t, q, v)`, `[dqdd/dq dqdd/dv]`, into
/// `jac`, exactly: the reverse-mode derivatives of the graph of the path that holds
/// there (recorded now if none does). `false` where the run takes no exact Jacobians or
/// no graph covers the state (the caller then takes the applied forces' differences).
pub fn jacobian<K: BodyKind>(
    sys: &System<K>,
    t: f64,
    q: &[f64],
    v: &[f64],
    ws: &mut Workspace<K>,
    jac: &mut DMatrix<f64>,
) -> bool {
    let Some(mut stage) = ws.compiled.take_if(|s| s.exact_jacobian) else {
        return false;
    };
    let done = stage.jacobian(sys, t, q, v, ws, jac);
    stage.jacobians[usize::from(!done)] += 1;
    ws.compiled = Some(stage);
    done
}

impl<K: BodyKind> Stage<K> {
    /// Gathers the inputs at `(t, q, v)`.
    fn gather(&mut self, sys: &System<K>, t: f64, q: &[f64], v: &[f64], ws: &Workspace<K>) {
        self.inputs.clear();
        self.inputs.extend_from_slice(q);
        self.inputs.extend_from_slice(v);
        (self.recorder.inputs)(sys, &ws.active, t, ws.t_piece, &ws.contacts, &mut self.inputs);
    }

    /// Runs the path that covers `(t, q, v)`, recording and compiling it if none does;
    /// `false` where none can.
    fn run(&mut self, sys: &System<K>, t: f64, q: &[f64], v: &[f64], ws: &Workspace<K>) -> bool {
        self.gather(sys, t, q, v, ws);
        let n = self.paths.len();
        // At capacity only the last path is tried: the others cost a whole evaluation
        // each to fail.
        let tries = if n >= MAX_PATHS { n.min(1) } else { n };
        let mut tried = 0;
        let covered = (0..tries).map(|k| (self.last + k) % n).find(|&k| {
            tried += 1;
            let path = &self.paths[k];
            path.code.as_ref().is_some_and(|code| code.call(&self.inputs, &path.params, &mut self.outputs))
        });
        self.misses += tried - usize::from(covered.is_some());
        if let Some(k) = covered {
            self.last = k;
            return true;
        }
        if n >= MAX_PATHS || self.stopped.is_some() {
            return false;
        }
        if self.back_off > 0 {
            self.back_off -= 1;
            return false;
        }
        let Some((graph, params)) = self.record(sys, ws) else {
            self.uncovered += 1;
            self.back_off = BACK_OFF;
            return false;
        };
        if !self.add(graph, params) {
            return false;
        }
        // A path holds where it was recorded.
        let path = &self.paths[self.last];
        path.code.as_ref().is_some_and(|code| code.call(&self.inputs, &path.params, &mut self.outputs))
    }

    /// The graph of the evaluation at the gathered inputs and its parameters; `None`
    /// where it takes a way that is not compiled, or is too large (which stops the
    /// stage).
    fn record(&mut self, sys: &System<K>, ws: &Workspace<K>) -> Option<(Graph, Vec<f64>)> {
        if self.stopped.is_some() {
            return None;
        }
        let (graph, params) = (self.recorder.record)(sys, ws, &self.inputs)?;
        if graph.nodes.len() > MAX_OPERATIONS {
            self.stopped = Some(format!(
                "an evaluation of {} operations is more than the {MAX_OPERATIONS} compiled",
                graph.nodes.len()
            ));
            return None;
        }
        Some((graph, params))
    }

    /// Keeps a recorded path as the last, compiled where the stage runs native code;
    /// `false` where compiling it failed (which stops the stage).
    fn add(&mut self, graph: Graph, params: Vec<f64>) -> bool {
        let code = if self.native {
            match compile_cached(&graph) {
                Ok((code, fresh)) => {
                    if fresh {
                        self.compile_seconds += code.compile_seconds;
                        self.compiled_now += 1;
                    } else {
                        self.from_cache += 1;
                    }
                    self.outputs.resize(code.outputs(), 0.0);
                    Some(code)
                }
                Err(e) => {
                    self.stopped = Some(e.0);
                    return false;
                }
            }
        } else {
            None
        };
        self.paths.push(Path { graph, code, params, sweep: None });
        self.last = self.paths.len() - 1;
        true
    }

    /// [`jacobian`]'s work: the derivatives from the path that holds at `(t, q, v)`, or
    /// from the one recorded there (kept while the stage has room).
    fn jacobian(
        &mut self,
        sys: &System<K>,
        t: f64,
        q: &[f64],
        v: &[f64],
        ws: &Workspace<K>,
        jac: &mut DMatrix<f64>,
    ) -> bool {
        self.gather(sys, t, q, v, ws);
        let (wrt, of) = (0..q.len() + v.len(), accelerations_in_outputs(ws));
        let mut put = |i: usize, j: usize, d: f64| jac[(i, j)] = d;
        let n = self.paths.len();
        for k in (0..n).map(|k| (self.last + k) % n) {
            let path = &mut self.paths[k];
            // Native code tells a path that does not hold faster than the graph's values.
            if path
                .code
                .as_ref()
                .is_some_and(|code| !code.call(&self.inputs, &path.params, &mut self.outputs))
            {
                continue;
            }
            let sweep = path.sweep.get_or_insert_with(|| path.graph.sweep(wrt.clone(), of.clone()));
            if path.graph.jacobian(&self.inputs, &path.params, sweep, &mut self.adjoints, &mut put) {
                self.last = k;
                return true;
            }
        }
        let Some((graph, params)) = self.record(sys, ws) else {
            return false;
        };
        let sweep = graph.sweep(wrt, of);
        let held = graph.jacobian(&self.inputs, &params, &sweep, &mut self.adjoints, put);
        if n < MAX_PATHS && self.add(graph, params) {
            self.paths[self.last].sweep = Some(sweep);
        }
        held
    }
}

/// Where the accelerations lie among a path's outputs ([`scatter`]'s layout).
fn accelerations_in_outputs<K: BodyKind>(ws: &Workspace<K>) -> Range<usize> {
    let at = ws.jac.len() * (3 + 2 * K::SHAPE.nv) + ws.qe.len();
    at..at + ws.qe.len()
}

/// Puts a path's outputs in the workspace ([`self`]'s layout of them).
fn scatter<K: BodyKind>(out: &[f64], ws: &mut Workspace<K>) {
    let nb = K::SHAPE.nv;
    let per_row = 3 + 2 * nb;
    let (m, nv) = (ws.jac.len(), ws.qe.len());
    for (a, row) in ws.jac.iter_mut().enumerate() {
        let o = &out[a * per_row..(a + 1) * per_row];
        ws.c[a] = o[0];
        ws.ct[a] = o[1];
        ws.gamma[a] = o[2];
        row.entries[0].as_mut().copy_from_slice(&o[3..3 + nb]);
        row.entries[1].as_mut().copy_from_slice(&o[3 + nb..per_row]);
    }
    let mut at = m * per_row;
    let mut next = |count: usize| {
        at += count;
        &out[at - count..at]
    };
    ws.qe.copy_from_slice(next(nv));
    ws.qdd.copy_from_slice(next(nv));
    let dynamic = ws.dynamic;
    ws.lambda.as_mut_slice()[..dynamic].copy_from_slice(next(dynamic));
    for b_inv in ws.prescribed_inverse.iter_mut() {
        for row in b_inv.iter_mut() {
            let n = row.len();
            row.copy_from_slice(next(n));
        }
    }
    ws.schur.solved_elsewhere();
}

/// The recorder of a body kind whose kernels are written over the number type
/// ([`kernels`]), or why `sys` is not compiled.
fn recorder_of<K: Kernels<N>, const N: usize>(sys: &System<K>) -> Result<Recorder<K>, String> {
    K::uncompiled_joint(sys)?;
    Ok(Recorder {
        record: |sys, ws, x| record(x, |x| evaluation::<K, N, _>(sys, ws, x)),
        inputs: inputs::<K, N>,
    })
}

impl Compile for Planar {
    fn recorder(sys: &System) -> Result<Recorder<Planar>, String> {
        recorder_of(sys)
    }
}

impl Compile for Spatial {
    fn recorder(sys: &System<Spatial>) -> Result<Recorder<Spatial>, String> {
        recorder_of(sys)
    }
}

impl<K: Compile> Workspace<K> {
    /// Records the evaluation of `sys` as the run needs its paths, or says why it is not
    /// recorded: compiled to native code for the evaluations where `native`, and
    /// differentiated for the implicit methods' Jacobians where `exact_jacobian`.
    pub fn compile(&mut self, sys: &System<K>, native: bool, exact_jacobian: bool) -> Result<(), String> {
        let recorder = K::recorder(sys)?;
        if self.schur.factorisation() == Factorisation::Sparse {
            return Err(format!(
                "the Schur complement of its {} rows is factored sparse, which is not compiled yet",
                self.dynamic
            ));
        }
        self.compiled = Some(Box::new(Stage::new(recorder, native, exact_jacobian)));
        Ok(())
    }
}
