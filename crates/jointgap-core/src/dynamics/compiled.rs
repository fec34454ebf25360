//! One evaluation of the equations of motion compiled to native code: the bodies' states,
//! the active constraint rows (`C`, `Cq`, `dC/dt`, `gamma`), the applied forces `Qe`
//! (gravity, gyroscopic moments, force elements, contact loads), and the accelerations
//! and multipliers of the augmented solve (the prescribed bodies' blocks, the Schur
//! complement's plain factor and solve), which [`super::accelerations_for_integration`]
//! computes interpreted otherwise (docs/compiled.md).
//!
//! At the first evaluation the stage records the kernels ([`super::kernels`]) on
//! [`crate::scalar::Traced`] numbers, as a graph with the model's constants folded, and
//! compiles it ([`crate::codegen`]). Each clearance joint's contact loads are a block of
//! the graph, recorded apart with the way it took through its branches (in contact or
//! not, a friction regime); the rest is a path. Where an evaluation finds that no way of
//! a block holds, it records the evaluation again and adds the block's new way to its
//! path (compiling only that way), so that the ways of several joints add up instead of
//! multiplying; where a guard of the path itself fails, the new recording is a path of
//! its own. Each path and way computes what the interpreted kernels compute, operation
//! for operation, so a run gives the same bits either way. An evaluation the graphs do not cover (a Schur
//! complement that is not well conditioned, a singular prescribed block) runs
//! interpreted. The implicit methods' Jacobians are the paths' graphs differentiated
//! ([`jacobian`]); a run that does not compile still records its paths for them. The
//! inputs and outputs are [`super::kernels::inputs`]' and
//! [`super::kernels::evaluation`]'s.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

use nalgebra::DMatrix;

use crate::codegen::{compile_cached, BlockCode, Compiled};
use crate::mechanics::contact::ContactState;
use crate::mechanics::kind::BodyKind;
use crate::mechanics::planar::Planar;
use crate::mechanics::spatial::kind::Spatial;
use crate::scalar::{record, Graph, Node, Sweep};
use crate::system::System;

use super::kernels::{evaluation, inputs, Kernels};
use super::schur::Factorisation;
use super::Workspace;

/// Paths a run compiles at most; past them, or past [`MAX_WAYS`] in a block, an
/// evaluation that the last path used does not cover runs interpreted.
pub const MAX_PATHS: usize = 16;
/// Ways through one block (a clearance joint's contact, a mesh cycle's table) a path
/// compiles at most: a table of stiffness along a gear's mesh cycle has a way per
/// interval.
pub const MAX_WAYS: usize = 64;
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
    /// How an evaluation is recorded.
    fn recorder() -> Recorder<Self>;
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
    /// Whether a recording found no room for its path or a block's way (then nothing
    /// more is recorded).
    full: bool,
    /// Calls of a path whose guards failed (the next path was tried).
    pub misses: usize,
    /// Why the stage stopped compiling (a code generation error), if it did.
    pub stopped: Option<String>,
}

/// One path through the kernels' branches: its graph (with its blocks' ways), its native
/// code and its blocks' where the stage runs native code, and the values of its
/// parameters.
#[derive(Debug, Clone)]
struct Path {
    graph: Graph,
    code: Option<Arc<Compiled>>,
    /// The compiled ways of each block, in the graph's order of them.
    blocks: Vec<BlockCode>,
    params: Vec<f64>,
    /// For each combination of its blocks' ways that has served a Jacobian: the graph
    /// with those ways in line, its parameters, and the nodes between the state and the
    /// accelerations.
    flat: HashMap<Vec<usize>, (Graph, Vec<f64>, Sweep)>,
    /// The combination that served the last Jacobian.
    served: Option<Vec<usize>>,
}

impl Path {
    /// Whether the path holds at `inputs` (its outputs then in `outputs`).
    fn call(&mut self, inputs: &[f64], outputs: &mut [f64]) -> bool {
        self.code.as_ref().is_some_and(|code| code.call_with(inputs, &self.params, outputs, &mut self.blocks))
    }

    /// The way each block takes at `inputs`, where the path holds there.
    fn ways_at(&mut self, inputs: &[f64], outputs: &mut [f64]) -> Option<Vec<usize>> {
        if self.code.is_some() {
            return self.call(inputs, outputs).then(|| self.blocks.iter().map(|b| b.last).collect());
        }
        let (values, ways) = self.graph.run(inputs, &self.params);
        ways.filter(|_| self.graph.holds(&values))
    }
}

/// Whether two recordings took the same path outside their blocks.
fn same_path(a: &Graph, b: &Graph) -> bool {
    a.nodes == b.nodes
        && a.guards == b.guards
        && a.outputs == b.outputs
        && a.inputs == b.inputs
        && a.params == b.params
        && a.blocks.len() == b.blocks.len()
        && a.blocks.iter().zip(&b.blocks).all(|(x, y)| x.outputs == y.outputs)
}

/// The operations of a graph and of its blocks' ways.
fn operations(graph: &Graph) -> usize {
    graph.nodes.len() + graph.blocks.iter().flat_map(|b| &b.ways).map(|(g, _)| g.nodes.len()).sum::<usize>()
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
            full: false,
            misses: 0,
            stopped: None,
        }
    }

    /// The one-line account of the run's compiled code and Jacobians.
    pub fn summary(&self) -> String {
        let [native, interpreted] = self.evaluations;
        let mut line = if self.native {
            let nodes: usize = self.paths.iter().map(|p| operations(&p.graph)).sum();
            let ways: usize = self.paths.iter().flat_map(|p| &p.graph.blocks).map(|b| b.ways.len()).sum();
            format!(
                "native code: {} paths and {ways} ways through their blocks, of {nodes} operations \
                 ({} compiled in {:.1} ms, {} from the cache), \
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
        // Once full only the last path is tried: the others cost a whole evaluation each
        // to fail.
        let tries = if self.full { n.min(1) } else { n };
        let mut tried = 0;
        let covered = (0..tries).map(|k| (self.last + k) % n).find(|&k| {
            tried += 1;
            self.paths[k].call(&self.inputs, &mut self.outputs)
        });
        self.misses += tried - usize::from(covered.is_some());
        if let Some(k) = covered {
            self.last = k;
            return true;
        }
        if self.full || self.stopped.is_some() {
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
        let Some(k) = self.admit(&graph, &params) else {
            return false;
        };
        // A path holds where it was recorded.
        self.last = k;
        self.paths[k].call(&self.inputs, &mut self.outputs)
    }

    /// The graph of the evaluation at the gathered inputs and its parameters; `None`
    /// where it takes a way that is not compiled, or is too large (which stops the
    /// stage).
    fn record(&mut self, sys: &System<K>, ws: &Workspace<K>) -> Option<(Graph, Vec<f64>)> {
        if self.stopped.is_some() {
            return None;
        }
        let (graph, params) = (self.recorder.record)(sys, ws, &self.inputs)?;
        let count = operations(&graph);
        if count > MAX_OPERATIONS {
            self.stopped = Some(format!(
                "an evaluation of {count} operations is more than the {MAX_OPERATIONS} compiled"
            ));
            return None;
        }
        Some((graph, params))
    }

    /// Keeps a recording: its blocks' ways added to the path it took, or a path of its
    /// own; each compiled where the stage runs native code. The path's index, or `None`
    /// where there was no room (the stage is then full) or compiling failed (which stops
    /// the stage).
    fn admit(&mut self, graph: &Graph, params: &[f64]) -> Option<usize> {
        if let Some(k) = self.paths.iter().position(|p| p.params == params && same_path(&p.graph, graph)) {
            return self.add_ways(k, graph).then_some(k);
        }
        if self.paths.len() >= MAX_PATHS {
            self.full = true;
            return None;
        }
        let mut path = Path {
            graph: graph.clone(),
            code: None,
            blocks: vec![BlockCode::default(); graph.blocks.len()],
            params: params.to_vec(),
            flat: HashMap::new(),
            served: None,
        };
        if self.native {
            let code = self.compiled(&path.graph)?;
            self.outputs.resize(code.outputs(), 0.0);
            path.code = Some(code);
            for (code, block) in path.blocks.iter_mut().zip(&path.graph.blocks) {
                let (way, q) = &block.ways[0];
                code.ways.push((self.compiled(way)?, q.clone()));
            }
        }
        self.paths.push(path);
        Some(self.paths.len() - 1)
    }

    /// Adds the ways of `graph`'s blocks that path `k` lacks; `false` where a block has
    /// no room (the stage is then full) or compiling failed.
    fn add_ways(&mut self, k: usize, graph: &Graph) -> bool {
        let mut inputs_grew = false;
        for (b, block) in graph.blocks.iter().enumerate() {
            let (way, q) = &block.ways[0];
            let site = &mut self.paths[k].graph.blocks[b];
            // The way's inputs numbered as the path's block numbers them.
            let index: Vec<u32> = block
                .args
                .iter()
                .map(|a| {
                    let at = site.args.iter().position(|s| s == a).unwrap_or_else(|| {
                        site.args.push(*a);
                        inputs_grew = true;
                        site.args.len() - 1
                    });
                    at as u32
                })
                .collect();
            let mut way = way.clone();
            for node in &mut way.nodes {
                if let Node::Input(i) = node {
                    *i = index[*i as usize];
                }
            }
            way.inputs = site.args.len();
            if site.ways.iter().any(|(g, p)| g.nodes == way.nodes && g.guards == way.guards && p == q) {
                continue;
            }
            if site.ways.len() >= MAX_WAYS {
                self.full = true;
                return false;
            }
            if self.native {
                let Some(code) = self.compiled(&way) else {
                    return false;
                };
                self.paths[k].blocks[b].ways.push((code, q.clone()));
            }
            self.paths[k].graph.blocks[b].ways.push((way, q.clone()));
        }
        if inputs_grew && self.native {
            // The path's code passes its blocks more inputs now.
            let graph = self.paths[k].graph.clone();
            let Some(code) = self.compiled(&graph) else {
                return false;
            };
            self.paths[k].code = Some(code);
        }
        true
    }

    /// The native code of `graph`, from the process's cache or compiled now; `None`
    /// where compiling failed (which stops the stage).
    fn compiled(&mut self, graph: &Graph) -> Option<Arc<Compiled>> {
        match compile_cached(graph) {
            Ok((code, fresh)) => {
                if fresh {
                    self.compile_seconds += code.compile_seconds;
                    self.compiled_now += 1;
                } else {
                    self.from_cache += 1;
                }
                Some(code)
            }
            Err(e) => {
                self.stopped = Some(e.0);
                None
            }
        }
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
            let path = &self.paths[k];
            // Without native code, the combination that served last is tried first: its
            // graph's own guards say whether it holds, for one evaluation of it.
            let served = path.served.as_ref().filter(|_| path.code.is_none()).map(|w| &path.flat[w]);
            if served.is_some_and(|(flat, p, sweep)| {
                flat.jacobian(&self.inputs, p, sweep, &mut self.adjoints, &mut put)
            }) {
                self.last = k;
                return true;
            }
            if let Some(ways) = self.paths[k].ways_at(&self.inputs, &mut self.outputs) {
                self.last = k;
                return self.differentiate(k, ways, (wrt, of), &mut put);
            }
        }
        let Some((graph, params)) = self.record(sys, ws) else {
            return false;
        };
        if let Some(k) = self.admit(&graph, &params) {
            if let Some(ways) = self.paths[k].ways_at(&self.inputs, &mut self.outputs) {
                self.last = k;
                return self.differentiate(k, ways, (wrt, of), &mut put);
            }
        }
        // Not kept: the recording itself, differentiated once.
        let (wrt, of) = (0..q.len() + v.len(), accelerations_in_outputs(ws));
        let (flat, p) = graph.flattened(&vec![0; graph.blocks.len()], &params);
        let sweep = flat.sweep(wrt, of);
        flat.jacobian(&self.inputs, &p, &sweep, &mut self.adjoints, put)
    }

    /// The derivatives from path `k` with its blocks' `ways` (which hold at the gathered
    /// inputs), each handed to `put`.
    fn differentiate(
        &mut self,
        k: usize,
        ways: Vec<usize>,
        (wrt, of): (Range<usize>, Range<usize>),
        put: &mut impl FnMut(usize, usize, f64),
    ) -> bool {
        let path = &mut self.paths[k];
        path.served = Some(ways.clone());
        let (graph, params) = (&path.graph, &path.params);
        let (flat, p, sweep) = path.flat.entry(ways).or_insert_with_key(|ways| {
            let (flat, p) = graph.flattened(ways, params);
            let sweep = flat.sweep(wrt, of);
            (flat, p, sweep)
        });
        flat.jacobian(&self.inputs, p, sweep, &mut self.adjoints, put)
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
/// ([`kernels`]).
fn recorder_of<K: Kernels<N>, const N: usize>() -> Recorder<K> {
    Recorder { record: |sys, ws, x| record(x, |x| evaluation::<K, N, _>(sys, ws, x)), inputs: inputs::<K, N> }
}

impl Compile for Planar {
    fn recorder() -> Recorder<Planar> {
        recorder_of()
    }
}

impl Compile for Spatial {
    fn recorder() -> Recorder<Spatial> {
        recorder_of()
    }
}

impl<K: Compile> Workspace<K> {
    /// Records the run's evaluation as it needs its paths, or says why it is not
    /// recorded: compiled to native code for the evaluations where `native`, and
    /// differentiated for the implicit methods' Jacobians where `exact_jacobian`.
    pub fn compile(&mut self, native: bool, exact_jacobian: bool) -> Result<(), String> {
        let recorder = K::recorder();
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
