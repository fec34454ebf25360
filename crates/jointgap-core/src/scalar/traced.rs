//! A number that records the computation it takes part in. [`record`] runs a kernel on
//! [`Traced`] inputs and returns the [`Graph`] of what it computed: one node per
//! operation, the model's constants folded where every argument is a constant, equal
//! operations on equal arguments merged, and a [`Guard`] for every comparison the kernel
//! branched on. The graph holds the one path the kernel took at the recorded values; its
//! guards say where that path holds.
//!
//! Every node's value is computed as it is recorded, so a kernel that branches reads the
//! branch it takes now. The model's numbers (lengths, masses, law parameters) enter as
//! parameters, read at run time from an array that the recording fills: variants of a
//! model whose numbers differ record the same graph, which is compiled once. The
//! literals of the kernels' own code (0, 1, 2, 3, 1/2, infinity, their negatives) are
//! constants; folding computes an operation on constants with the operation the graph
//! would run, and the only other simplifications (`x * 1`, `x / 1`, `x - 0`, `x + (-0)`)
//! give `x`'s bits exactly.

use std::cell::{Cell, RefCell};
use std::cmp::Ordering;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use super::Real;

/// A function the graph calls rather than computes in line: what the processor has no
/// instruction for, and what must give `f64`'s bits exactly (`max`'s treatment of equal
/// zeros).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func {
    /// `sin_cos(x).0`.
    Sin,
    /// `sin_cos(x).1`.
    Cos,
    /// `x.powf(y)`.
    Powf,
    /// `x.signum()`.
    Signum,
    /// `x.max(y)`.
    Max,
    /// `x.min(y)`.
    Min,
    /// `x.tanh()`.
    Tanh,
    /// `x.cosh()`.
    Cosh,
    /// `x.atan2(y)`.
    Atan2,
    /// `x.rem_euclid(y)`.
    RemEuclid,
    /// A function of two numbers computed by a method of its own ([`Implicit`]).
    Implicit(&'static Implicit),
}

/// A function of two numbers that a kernel computes by a method of its own, an
/// iteration whose branches depend on the numbers (a root in a bracket): a graph calls
/// it whole, as it calls `atan2`, and takes its slopes from the function that defines
/// it (the implicit function theorem), so that no guard records the iteration's steps.
pub struct Implicit {
    /// Its name, unique among them: the compiled code's symbol and its identity.
    pub name: &'static str,
    /// Its value at `(x, y)`, as the interpreted engine computes it.
    pub value: extern "C" fn(f64, f64) -> f64,
    /// Its slopes `(d/dx, d/dy)` at `(x, y)`, given its value there.
    pub slopes: fn(f64, f64, f64) -> (f64, f64),
}

impl PartialEq for Implicit {
    fn eq(&self, other: &Implicit) -> bool {
        self.name == other.name
    }
}

impl Eq for Implicit {}

impl std::hash::Hash for Implicit {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.name.hash(h);
    }
}

impl std::fmt::Debug for Implicit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

impl Func {
    /// The function on `f64`, as the interpreted engine computes it.
    pub fn eval(self, x: f64, y: f64) -> f64 {
        match self {
            Func::Sin => x.sin_cos().0,
            Func::Cos => x.sin_cos().1,
            Func::Powf => x.powf(y),
            Func::Signum => x.signum(),
            Func::Max => x.max(y),
            Func::Min => x.min(y),
            Func::Tanh => x.tanh(),
            Func::Cosh => x.cosh(),
            Func::Atan2 => x.atan2(y),
            Func::RemEuclid => x.rem_euclid(y),
            Func::Implicit(f) => (f.value)(x, y),
        }
    }
}

/// One operation of a graph; arguments are earlier nodes' indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Node {
    /// A constant, by its bits.
    Const(u64),
    /// Parameter `k` of the compiled function (a number of the model).
    Param(u32),
    /// Input `k` of the compiled function.
    Input(u32),
    /// `a + b`.
    Add(u32, u32),
    /// `a - b`.
    Sub(u32, u32),
    /// `a * b`.
    Mul(u32, u32),
    /// `a / b`.
    Div(u32, u32),
    /// `-a`.
    Neg(u32),
    /// `sqrt(a)`.
    Sqrt(u32),
    /// `|a|`.
    Abs(u32),
    /// A called function of one argument (the second is unused, `u32::MAX`) or two.
    Call(Func, u32, u32),
    /// Output `k` of block `b`: `Out(b, k)`.
    Out(u32, u32),
}

impl Node {
    /// The node with each argument `a` replaced by `f(a)`.
    pub fn remapped(self, f: impl Fn(u32) -> u32) -> Node {
        match self {
            Node::Add(a, b) => Node::Add(f(a), f(b)),
            Node::Sub(a, b) => Node::Sub(f(a), f(b)),
            Node::Mul(a, b) => Node::Mul(f(a), f(b)),
            Node::Div(a, b) => Node::Div(f(a), f(b)),
            Node::Neg(a) => Node::Neg(f(a)),
            Node::Sqrt(a) => Node::Sqrt(f(a)),
            Node::Abs(a) => Node::Abs(f(a)),
            Node::Call(g, a, b) => Node::Call(g, f(a), if b == u32::MAX { b } else { f(b) }),
            Node::Const(_) | Node::Param(_) | Node::Input(_) | Node::Out(..) => self,
        }
    }
}

/// A comparison a kernel branched on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Cmp {
    /// `a < b`.
    Lt,
    /// `a <= b`.
    Le,
    /// `a > b`.
    Gt,
    /// `a >= b`.
    Ge,
    /// `a == b`.
    Eq,
    /// `a != b`.
    Ne,
}

impl Cmp {
    /// The comparison on `f64`, as Rust's operators do it (false where a NaN takes part,
    /// but for `!=`).
    pub fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
        }
    }
}

/// A condition of a graph's path: `a op b` came out `holds` when it was recorded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Guard {
    /// Left node.
    pub a: u32,
    /// Right node.
    pub b: u32,
    /// Comparison.
    pub op: Cmp,
    /// Its outcome on the recorded path.
    pub holds: bool,
}

/// A recorded evaluation: nodes in the order they were computed (every argument before
/// its use), the guards of its path, the nodes of its outputs and the blocks it calls.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Graph {
    /// Operations.
    pub nodes: Vec<Node>,
    /// Conditions under which this path is the one the kernel takes.
    pub guards: Vec<Guard>,
    /// Output `k` is node `outputs[k]`.
    pub outputs: Vec<u32>,
    /// Number of inputs.
    pub inputs: usize,
    /// Number of parameters.
    pub params: usize,
    /// Parts recorded apart (a clearance joint's contact loads), each with its own ways
    /// through its branches; [`Node::Out`] reads their outputs.
    pub blocks: Vec<Block>,
}

/// A part of an evaluation recorded apart, with the ways through its branches found so
/// far: an evaluation takes the first whose guards hold, so that a mechanism's
/// clearance joints each add their own ways instead of multiplying them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Block {
    /// Input `k` of every way is the graph's node `args[k]`.
    pub args: Vec<u32>,
    /// Number of outputs.
    pub outputs: usize,
    /// Its ways, each a graph of its own (its inputs being `args`) with the values of its
    /// parameters.
    pub ways: Vec<(Graph, Vec<f64>)>,
}

impl Graph {
    /// Whether every guard holds at inputs `x` and parameters `p`, and the outputs there,
    /// evaluated node by node on `f64`: what the compiled function computes, for tests
    /// and checks.
    pub fn eval(&self, x: &[f64], p: &[f64]) -> (bool, Vec<f64>) {
        let (v, ways) = self.run(x, p);
        (ways.is_some() && self.holds(&v), self.outputs.iter().map(|&o| v[o as usize]).collect())
    }

    /// The values of every node at inputs `x` and parameters `p`, in node order.
    pub fn values(&self, x: &[f64], p: &[f64]) -> Vec<f64> {
        self.run(x, p).0
    }

    /// The values of every node at inputs `x` and parameters `p`, and the way each block
    /// took (`None` where one has no way whose guards hold; its outputs are then NaN).
    pub fn run(&self, x: &[f64], p: &[f64]) -> (Vec<f64>, Option<Vec<usize>>) {
        let mut v = vec![0.0; self.nodes.len()];
        let mut taken = Some(Vec::with_capacity(self.blocks.len()));
        let mut outs: Vec<f64> = Vec::new();
        for (k, node) in self.nodes.iter().enumerate() {
            if let Node::Out(b, 0) = *node {
                let block = &self.blocks[b as usize];
                let args: Vec<f64> = block.args.iter().map(|&a| v[a as usize]).collect();
                let held = block.ways.iter().enumerate().find_map(|(w, (g, q))| {
                    let (ok, out) = g.eval(&args[..g.inputs], q);
                    ok.then_some((w, out))
                });
                let way = held.as_ref().map(|(w, _)| *w);
                outs = held.map_or_else(|| vec![f64::NAN; block.outputs], |(_, out)| out);
                taken = taken.zip(way).map(|(mut t, w)| {
                    t.push(w);
                    t
                });
            }
            let a = |i: u32| v[i as usize];
            v[k] = match *node {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Input(i) => x[i as usize],
                Node::Param(i) => p[i as usize],
                Node::Add(p, q) => a(p) + a(q),
                Node::Sub(p, q) => a(p) - a(q),
                Node::Mul(p, q) => a(p) * a(q),
                Node::Div(p, q) => a(p) / a(q),
                Node::Neg(p) => -a(p),
                Node::Sqrt(p) => a(p).sqrt(),
                Node::Abs(p) => a(p).abs(),
                Node::Call(f, p, q) => f.eval(a(p), if q == u32::MAX { 0.0 } else { a(q) }),
                Node::Out(_, o) => outs[o as usize],
            };
        }
        (v, taken)
    }

    /// The graph with the ways `taken` of its blocks written in line (no blocks left),
    /// and its parameters, `p` followed by theirs: what a recording that took those ways
    /// without blocks gives, for the derivatives.
    pub fn flattened(&self, taken: &[usize], p: &[f64]) -> (Graph, Vec<f64>) {
        let mut flat = Graph { inputs: self.inputs, ..Graph::default() };
        let mut params = p.to_vec();
        let mut map = vec![u32::MAX; self.nodes.len()];
        let mut outs: Vec<u32> = Vec::new();
        let push = |flat: &mut Graph, node: Node| {
            flat.nodes.push(node);
            flat.nodes.len() as u32 - 1
        };
        for (k, &node) in self.nodes.iter().enumerate() {
            map[k] = match node {
                Node::Out(b, o) => {
                    if o == 0 {
                        let block = &self.blocks[b as usize];
                        let (way, q) = &block.ways[taken[b as usize]];
                        let base = params.len() as u32;
                        params.extend(q);
                        let mut local: Vec<u32> = Vec::with_capacity(way.nodes.len());
                        for &n in &way.nodes {
                            let id = match n {
                                Node::Input(i) => map[block.args[i as usize] as usize],
                                Node::Param(i) => push(&mut flat, Node::Param(base + i)),
                                n => push(&mut flat, n.remapped(|a| local[a as usize])),
                            };
                            local.push(id);
                        }
                        flat.guards.extend(way.guards.iter().map(|g| Guard {
                            a: local[g.a as usize],
                            b: local[g.b as usize],
                            ..*g
                        }));
                        outs = way.outputs.iter().map(|&o| local[o as usize]).collect();
                    }
                    outs[o as usize]
                }
                Node::Const(_) | Node::Param(_) | Node::Input(_) => push(&mut flat, node),
                n => push(&mut flat, n.remapped(|a| map[a as usize])),
            };
        }
        flat.guards.extend(self.guards.iter().map(|g| Guard {
            a: map[g.a as usize],
            b: map[g.b as usize],
            ..*g
        }));
        flat.outputs = self.outputs.iter().map(|&o| map[o as usize]).collect();
        flat.params = params.len();
        (flat, params)
    }

    /// Whether every guard holds at the node values `v` ([`Graph::values`]).
    pub fn holds(&self, v: &[f64]) -> bool {
        self.guards.iter().all(|g| g.op.holds(v[g.a as usize], v[g.b as usize]) == g.holds)
    }
}

/// The graph being recorded on this thread at one level: the evaluation, or a block
/// within it.
#[derive(Default)]
struct Tape {
    graph: Graph,
    values: Vec<f64>,
    params: Vec<f64>,
    param_of: HashMap<u64, u32, Quick>,
    merged: HashMap<Node, u32, Quick>,
    guarded: HashMap<(u32, u32, Cmp), bool, Quick>,
    /// Which recording or block it is, for the numbers computed in it.
    scope: u32,
    /// A block's inputs: the node of the evaluation each one is.
    args: Vec<u32>,
    /// A block's input node for each node of the evaluation it read.
    imported: HashMap<u32, u32, Quick>,
}

/// The tape's maps hash node indices and bits, which need no defence against chosen
/// keys: a multiply-rotate hash (as rustc's own) instead of SipHash.
type Quick = BuildHasherDefault<QuickHasher>;

/// See [`Quick`].
#[derive(Default)]
struct QuickHasher(u64);

impl Hasher for QuickHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        bytes.iter().for_each(|&b| self.write_u64(u64::from(b)));
    }
    fn write_u8(&mut self, x: u8) {
        self.write_u64(u64::from(x));
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn write_isize(&mut self, x: isize) {
        self.write_u64(x as u64);
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

thread_local! {
    /// The evaluation being recorded, and the block being recorded within it.
    static TAPES: RefCell<Vec<Tape>> = const { RefCell::new(Vec::new()) };
    /// Scopes handed out on this thread.
    static SCOPES: Cell<u32> = const { Cell::new(0) };
}

/// A tape of a scope of its own.
fn new_tape() -> Tape {
    let scope = SCOPES.with(|s| {
        s.set(s.get().wrapping_add(1));
        s.get()
    });
    Tape { scope, ..Tape::default() }
}

/// `f` on the tapes of the recording running on this thread.
fn with_tapes<R>(f: impl FnOnce(&mut Vec<Tape>) -> R) -> R {
    TAPES.with(|t| {
        let mut tapes = t.borrow_mut();
        assert!(!tapes.is_empty(), "a traced number is used outside a recording");
        f(&mut tapes)
    })
}

/// Runs `f` on `inputs.len()` traced inputs holding `inputs` and returns the graph of
/// what it computed, its outputs being the values `f` returns, in order, and the values
/// of its parameters; `None` where `f` returns none (it took a way the graph does not
/// cover).
pub fn record(inputs: &[f64], f: impl FnOnce(&[Traced]) -> Option<Vec<Traced>>) -> Option<(Graph, Vec<f64>)> {
    TAPES.with(|t| {
        let mut tapes = t.borrow_mut();
        assert!(tapes.is_empty(), "a recording is already running on this thread");
        tapes.push(new_tape());
    });
    let traced: Vec<Traced> =
        inputs.iter().enumerate().map(|(k, &x)| push(Node::Input(k as u32), x)).collect();
    let outputs = f(&traced);
    let tape = TAPES.with(|t| t.borrow_mut().pop()).expect("the recording's tape");
    let mut graph = tape.graph;
    graph.outputs = outputs?
        .iter()
        .map(|o| {
            assert_eq!(o.scope, tape.scope, "an output of the recording computed inside a block");
            o.id
        })
        .collect();
    graph.inputs = inputs.len();
    graph.params = tape.params.len();
    Some((graph, tape.params))
}

/// Runs `f` on `values` as a block of the recording: a graph of its own, whose inputs
/// are the recording's numbers it reads, whose outputs are the values it returns, and
/// whose guards are its own. The recording reads the outputs ([`Node::Out`]).
fn block(values: &[Traced], f: impl FnOnce(&[Traced]) -> Option<Vec<Traced>>) -> Option<Vec<Traced>> {
    with_tapes(|t| {
        assert_eq!(t.len(), 1, "a block is recorded in an evaluation, not in another block");
        t.push(new_tape());
    });
    let out = f(values);
    let (mut tape, ids) = with_tapes(|t| {
        let ids: Option<Vec<u32>> = out.map(|o| o.iter().map(|&x| here(t, x)).collect());
        (t.pop().expect("the block's tape"), ids)
    });
    let ids = ids?;
    let values: Vec<f64> = ids.iter().map(|&i| tape.values[i as usize]).collect();
    tape.graph.outputs = ids;
    tape.graph.inputs = tape.args.len();
    tape.graph.params = tape.params.len();
    with_tapes(|t| {
        let outer = t.last_mut().expect("the recording's tape");
        let b = outer.graph.blocks.len() as u32;
        let way = (tape.graph, tape.params);
        outer.graph.blocks.push(Block { args: tape.args, outputs: values.len(), ways: vec![way] });
        Some(values.iter().enumerate().map(|(k, &x)| insert(outer, Node::Out(b, k as u32), x)).collect())
    })
}

/// The constant an operation on constants gives.
fn folded(x: f64) -> Traced {
    push(Node::Const(x.to_bits()), x)
}

/// Whether `x` is a literal of the kernels' code rather than a number of the model.
fn literal(x: f64) -> bool {
    let a = x.abs();
    a == 0.0 || a == 1.0 || a == 2.0 || a == 3.0 || a == 0.5 || a.is_infinite()
}

/// Adds node `node` of value `value` to the innermost tape, or finds the equal one
/// recorded before.
fn push(node: Node, value: f64) -> Traced {
    with_tapes(|t| insert(t.last_mut().expect("a tape"), node, value))
}

/// Adds node `node` of value `value` to `tape`, or finds the equal one recorded before.
fn insert(tape: &mut Tape, node: Node, value: f64) -> Traced {
    let scope = tape.scope;
    if let Some(&id) = tape.merged.get(&node) {
        return Traced { id, scope, value: tape.values[id as usize] };
    }
    let id = tape.graph.nodes.len() as u32;
    tape.graph.nodes.push(node);
    tape.values.push(value);
    tape.merged.insert(node, id);
    Traced { id, scope, value }
}

/// `x`'s node in the innermost tape: a block reads a number of the recording around it
/// as an input of its own (a constant as the same constant).
fn here(tapes: &mut [Tape], x: Traced) -> u32 {
    let (top, below) = tapes.split_last_mut().expect("a tape");
    if x.scope == top.scope {
        return x.id;
    }
    let outer = below
        .last()
        .filter(|o| o.scope == x.scope)
        .expect("a traced number is used outside the block it was computed in");
    if let Some(&id) = top.imported.get(&x.id) {
        return id;
    }
    let node = match outer.graph.nodes[x.id as usize] {
        Node::Const(bits) => Node::Const(bits),
        _ => {
            top.args.push(x.id);
            Node::Input(top.args.len() as u32 - 1)
        }
    };
    let id = insert(top, node, x.value).id;
    top.imported.insert(x.id, id);
    id
}

/// Records that the kernel branched on `a op b`, unless both are constants.
fn guard(a: Traced, b: Traced, op: Cmp) -> bool {
    let holds = op.holds(a.value, b.value);
    if !(a.is_constant() && b.is_constant()) {
        with_tapes(|t| {
            let (a, b) = (here(t, a), here(t, b));
            let tape = t.last_mut().expect("a tape");
            if tape.guarded.insert((a, b, op), holds).is_none() {
                tape.graph.guards.push(Guard { a, b, op, holds });
            }
        });
    }
    holds
}

/// A number of a recording: its node, the tape it is a node of, and the value it holds.
#[derive(Debug, Clone, Copy)]
pub struct Traced {
    id: u32,
    scope: u32,
    value: f64,
}

impl Traced {
    /// Whether it is a constant of the graph.
    fn is_constant(self) -> bool {
        with_tapes(|t| {
            let tape = t.iter().rev().find(|tape| tape.scope == self.scope);
            let tape = tape.expect("a traced number is used outside the block it was computed in");
            matches!(tape.graph.nodes[self.id as usize], Node::Const(_))
        })
    }

    /// The constant it is, if it is one.
    fn known(self) -> Option<f64> {
        self.is_constant().then_some(self.value)
    }

    /// `node(self, other)` of value `value`: a constant where both are.
    fn binary(self, other: Traced, node: impl Fn(u32, u32) -> Node, value: f64) -> Traced {
        if self.is_constant() && other.is_constant() {
            return folded(value);
        }
        with_tapes(|t| {
            let (a, b) = (here(t, self), here(t, other));
            insert(t.last_mut().expect("a tape"), node(a, b), value)
        })
    }

    fn unary(self, node: impl Fn(u32) -> Node, value: f64) -> Traced {
        if self.is_constant() {
            return folded(value);
        }
        with_tapes(|t| {
            let a = here(t, self);
            insert(t.last_mut().expect("a tape"), node(a), value)
        })
    }

    fn call(self, f: Func, other: Option<Traced>) -> Traced {
        let y = other.map_or(0.0, |o| o.value);
        let value = f.eval(self.value, y);
        match other {
            None => self.unary(|a| Node::Call(f, a, u32::MAX), value),
            Some(o) => self.binary(o, |a, b| Node::Call(f, a, b), value),
        }
    }
}

impl PartialEq for Traced {
    fn eq(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Eq)
    }
    #[allow(clippy::partialeq_ne_impl)]
    fn ne(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Ne)
    }
}

impl PartialOrd for Traced {
    fn partial_cmp(&self, other: &Traced) -> Option<Ordering> {
        if guard(*self, *other, Cmp::Lt) {
            Some(Ordering::Less)
        } else if guard(*self, *other, Cmp::Gt) {
            Some(Ordering::Greater)
        } else if guard(*self, *other, Cmp::Eq) {
            Some(Ordering::Equal)
        } else {
            None
        }
    }
    fn lt(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Lt)
    }
    fn le(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Le)
    }
    fn gt(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Gt)
    }
    fn ge(&self, other: &Traced) -> bool {
        guard(*self, *other, Cmp::Ge)
    }
}

impl PartialEq<f64> for Traced {
    fn eq(&self, other: &f64) -> bool {
        *self == Traced::constant(*other)
    }
}

impl PartialOrd<f64> for Traced {
    fn partial_cmp(&self, other: &f64) -> Option<Ordering> {
        self.partial_cmp(&Traced::constant(*other))
    }
    fn lt(&self, other: &f64) -> bool {
        *self < Traced::constant(*other)
    }
    fn le(&self, other: &f64) -> bool {
        *self <= Traced::constant(*other)
    }
    fn gt(&self, other: &f64) -> bool {
        *self > Traced::constant(*other)
    }
    fn ge(&self, other: &f64) -> bool {
        *self >= Traced::constant(*other)
    }
}

impl Add for Traced {
    type Output = Traced;
    fn add(self, o: Traced) -> Traced {
        // x + (-0) is x, signed zero included; x + 0 is not (-0 + 0 = +0).
        let negative_zero = |t: Traced| t.known().is_some_and(|z| z == 0.0 && z.is_sign_negative());
        if negative_zero(o) {
            return self;
        }
        if negative_zero(self) {
            return o;
        }
        self.binary(o, Node::Add, self.value + o.value)
    }
}

impl Sub for Traced {
    type Output = Traced;
    fn sub(self, o: Traced) -> Traced {
        if o.known().is_some_and(|z| z == 0.0 && z.is_sign_positive()) {
            return self;
        }
        self.binary(o, Node::Sub, self.value - o.value)
    }
}

impl Mul for Traced {
    type Output = Traced;
    fn mul(self, o: Traced) -> Traced {
        if o.known() == Some(1.0) {
            return self;
        }
        if self.known() == Some(1.0) {
            return o;
        }
        self.binary(o, Node::Mul, self.value * o.value)
    }
}

impl Div for Traced {
    type Output = Traced;
    fn div(self, o: Traced) -> Traced {
        if o.known() == Some(1.0) {
            return self;
        }
        self.binary(o, Node::Div, self.value / o.value)
    }
}

impl Neg for Traced {
    type Output = Traced;
    fn neg(self) -> Traced {
        self.unary(Node::Neg, -self.value)
    }
}

macro_rules! with_constant {
    ($($trait:ident $method:ident $assign:ident $assign_method:ident),*) => {$(
        impl $trait<f64> for Traced {
            type Output = Traced;
            fn $method(self, o: f64) -> Traced {
                self.$method(Traced::constant(o))
            }
        }
        impl $assign for Traced {
            fn $assign_method(&mut self, o: Traced) {
                *self = self.$method(o);
            }
        }
    )*};
}

with_constant!(Add add AddAssign add_assign, Sub sub SubAssign sub_assign, Mul mul MulAssign mul_assign,
    Div div DivAssign div_assign);

impl num_traits::Zero for Traced {
    fn zero() -> Traced {
        Traced::constant(0.0)
    }
    fn is_zero(&self) -> bool {
        *self == 0.0
    }
}

impl num_traits::One for Traced {
    fn one() -> Traced {
        Traced::constant(1.0)
    }
}

impl Real for Traced {
    fn constant(x: f64) -> Traced {
        if literal(x) {
            return folded(x);
        }
        with_tapes(|t| {
            let tape = t.last_mut().expect("a tape");
            let next = tape.params.len() as u32;
            let k = *tape.param_of.entry(x.to_bits()).or_insert(next);
            if k == next {
                tape.params.push(x);
            }
            insert(tape, Node::Param(k), x)
        })
    }
    fn value(self) -> f64 {
        self.value
    }
    fn sqrt(self) -> Traced {
        self.unary(Node::Sqrt, self.value.sqrt())
    }
    fn sin_cos(self) -> (Traced, Traced) {
        (self.call(Func::Sin, None), self.call(Func::Cos, None))
    }
    fn powf(self, n: Traced) -> Traced {
        self.call(Func::Powf, Some(n))
    }
    fn abs(self) -> Traced {
        self.unary(Node::Abs, self.value.abs())
    }
    fn signum(self) -> Traced {
        self.call(Func::Signum, None)
    }
    fn max(self, other: Traced) -> Traced {
        self.call(Func::Max, Some(other))
    }
    fn min(self, other: Traced) -> Traced {
        self.call(Func::Min, Some(other))
    }
    fn tanh(self) -> Traced {
        self.call(Func::Tanh, None)
    }
    fn cosh(self) -> Traced {
        self.call(Func::Cosh, None)
    }
    fn atan2(self, x: Traced) -> Traced {
        self.call(Func::Atan2, Some(x))
    }
    fn rem_euclid(self, m: Traced) -> Traced {
        self.call(Func::RemEuclid, Some(m))
    }
    fn implicit(self, y: Traced, f: &'static Implicit) -> Traced {
        self.call(Func::Implicit(f), Some(y))
    }
    fn block(values: &[Traced], f: impl FnOnce(&[Traced]) -> Option<Vec<Traced>>) -> Option<Vec<Traced>> {
        block(values, f)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A kernel with a branch: `sqrt(x^2 + y^2) - 1` where positive, else `2 y`.
    fn kernel<T: Real>(x: T, y: T) -> T {
        let r = (x * x + y * y).sqrt() - 1.0;
        if r > 0.0 {
            r * c::<T>(3.0) * c::<T>(1.0)
        } else {
            y * 2.0
        }
    }
    use super::super::c;

    /// The graph computes the kernel's bits where its guards hold, and its guards fail
    /// where the kernel takes the other branch.
    #[test]
    fn graph_repeats_the_kernel_on_its_path() {
        let (g, p) = record(&[3.0, 4.0], |x| Some(vec![kernel(x[0], x[1])])).expect("a graph");
        assert_eq!(g.guards.len(), 1);
        for (x, y) in [(3.0, 4.0), (0.7, 0.9), (-2.0, 1e-3)] {
            let (ok, out) = g.eval(&[x, y], &p);
            assert!(ok, "({x}, {y})");
            assert_eq!(out[0].to_bits(), kernel(x, y).to_bits());
        }
        assert!(!g.eval(&[0.1, 0.2], &p).0);
    }

    /// Literals fold with the operation itself, equal operations merge, `x * 1` leaves
    /// `x`, and the model's numbers are parameters: a kernel of other numbers records the
    /// same graph.
    #[test]
    fn literals_fold_numbers_are_parameters_and_equal_operations_merge() {
        let kernel = |k: f64| {
            move |x: &[Traced]| {
                let two = c::<Traced>(0.5) * 3.0 + 0.5;
                Some(vec![x[0] * two, x[0] * two, x[0] * 1.0, x[0] * k])
            }
        };
        let (g, p) = record(&[0.5], kernel(0.1)).expect("a graph");
        assert_eq!(g.outputs[0], g.outputs[1]);
        assert_eq!(g.outputs[2], 0);
        assert!(g.nodes.contains(&Node::Const(2.0f64.to_bits())));
        assert_eq!((g.params, p), (1, vec![0.1]));
        let operations = g.nodes.iter().filter(|n| matches!(n, Node::Mul(..))).count();
        assert_eq!(operations, 2, "{:?}", g.nodes);
        let (other, q) = record(&[0.5], kernel(0.3)).expect("a graph");
        assert_eq!(other, g);
        assert_eq!(g.eval(&[0.5], &q).1[3].to_bits(), (0.5f64 * 0.3).to_bits());
    }

    /// Two blocks, each with a branch of its own, reading the numbers around them.
    pub(crate) fn blocked<T: Real>(x: &[T]) -> Option<Vec<T>> {
        let mut out = vec![x[0] * x[1]];
        for k in 1..3 {
            let r = T::block(&out, |before| {
                let y = x[k];
                let v = if y > 0.0 { before[0] + y * c::<T>(1.5) } else { before[0] - y.abs() };
                Some(vec![v, y * 2.0])
            })?;
            out = vec![r[0] + r[1]];
        }
        Some(out)
    }

    /// A block is a graph of its own: its inputs are the numbers it reads, its guards are
    /// its own, and the evaluation reads its outputs; where no way of a block holds the
    /// evaluation does not; written in line, the ways give the kernel's bits.
    #[test]
    fn blocks_record_their_own_branches() {
        let (g, p) = record(&[0.5, 2.0, 3.0], blocked).expect("a graph");
        assert!(g.guards.is_empty());
        assert_eq!(g.blocks.len(), 2);
        for block in &g.blocks {
            assert_eq!((block.args.len(), block.outputs, block.ways.len()), (2, 2, 1));
            assert_eq!(block.ways[0].0.guards.len(), 1);
        }
        for x in [[0.5, 2.0, 3.0], [-1.5, 0.25, 7.0]] {
            let expected = blocked::<f64>(&x).expect("a value")[0];
            let (ok, out) = g.eval(&x, &p);
            assert!(ok);
            assert_eq!(out[0].to_bits(), expected.to_bits());
            let (flat, q) = g.flattened(&[0, 0], &p);
            assert!(flat.blocks.is_empty());
            assert_eq!(flat.eval(&x, &q), (true, vec![expected]));
        }
        let (_, ways) = g.run(&[0.5, -2.0, 3.0], &p);
        assert!(ways.is_none());
        assert!(!g.eval(&[0.5, 2.0, -3.0], &p).0);
    }

    /// `x + 0` is kept (it turns -0 into +0); `x - 0` is dropped (it never changes x).
    #[test]
    fn signed_zeros_survive_simplification() {
        let (g, p) = record(&[-0.0], |x| Some(vec![x[0] + 0.0, x[0] - 0.0])).expect("a graph");
        let (_, out) = g.eval(&[-0.0], &p);
        assert!(out[0].is_sign_positive() && out[1].is_sign_negative());
    }
}
