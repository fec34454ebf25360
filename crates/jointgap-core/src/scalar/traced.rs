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

use std::cell::RefCell;
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
/// its use), the guards of its path and the nodes of its outputs.
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
}

impl Graph {
    /// Whether every guard holds at inputs `x` and parameters `p`, and the outputs there,
    /// evaluated node by node on `f64`: what the compiled function computes, for tests
    /// and checks.
    pub fn eval(&self, x: &[f64], p: &[f64]) -> (bool, Vec<f64>) {
        let v = self.values(x, p);
        (self.holds(&v), self.outputs.iter().map(|&o| v[o as usize]).collect())
    }

    /// The values of every node at inputs `x` and parameters `p`, in node order.
    pub fn values(&self, x: &[f64], p: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.nodes.len()];
        for (k, node) in self.nodes.iter().enumerate() {
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
            };
        }
        v
    }

    /// Whether every guard holds at the node values `v` ([`Graph::values`]).
    pub fn holds(&self, v: &[f64]) -> bool {
        self.guards.iter().all(|g| g.op.holds(v[g.a as usize], v[g.b as usize]) == g.holds)
    }
}

/// The graph being recorded on this thread.
#[derive(Default)]
struct Tape {
    graph: Graph,
    values: Vec<f64>,
    params: Vec<f64>,
    param_of: HashMap<u64, u32, Quick>,
    merged: HashMap<Node, u32, Quick>,
    guarded: HashMap<(u32, u32, Cmp), bool, Quick>,
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
    static TAPE: RefCell<Option<Tape>> = const { RefCell::new(None) };
}

/// Runs `f` on `inputs.len()` traced inputs holding `inputs` and returns the graph of
/// what it computed, its outputs being the values `f` returns, in order, and the values
/// of its parameters; `None` where `f` returns none (it took a way the graph does not
/// cover).
pub fn record(inputs: &[f64], f: impl FnOnce(&[Traced]) -> Option<Vec<Traced>>) -> Option<(Graph, Vec<f64>)> {
    let previous = TAPE.with(|t| t.borrow_mut().replace(Tape::default()));
    assert!(previous.is_none(), "a recording is already running on this thread");
    let traced: Vec<Traced> =
        inputs.iter().enumerate().map(|(k, &x)| push(Node::Input(k as u32), x)).collect();
    let outputs = f(&traced);
    let mut tape = TAPE.with(|t| t.borrow_mut().take()).expect("the recording's tape");
    tape.graph.outputs = outputs?.iter().map(|o| o.id).collect();
    tape.graph.inputs = inputs.len();
    tape.graph.params = tape.params.len();
    Some((tape.graph, tape.params))
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

/// Adds node `node` of value `value` to the tape, or finds the equal one recorded before.
fn push(node: Node, value: f64) -> Traced {
    TAPE.with(|t| {
        let mut guard = t.borrow_mut();
        let tape = guard.as_mut().expect("a traced number is used outside a recording");
        if let Some(&id) = tape.merged.get(&node) {
            return Traced { id, value: tape.values[id as usize] };
        }
        let id = tape.graph.nodes.len() as u32;
        tape.graph.nodes.push(node);
        tape.values.push(value);
        tape.merged.insert(node, id);
        Traced { id, value }
    })
}

/// Records that the kernel branched on `a op b`, unless both are constants.
fn guard(a: Traced, b: Traced, op: Cmp) -> bool {
    let holds = op.holds(a.value, b.value);
    if !(a.is_constant() && b.is_constant()) {
        TAPE.with(|t| {
            let mut guard = t.borrow_mut();
            let tape = guard.as_mut().expect("a traced number is used outside a recording");
            if tape.guarded.insert((a.id, b.id, op), holds).is_none() {
                tape.graph.guards.push(Guard { a: a.id, b: b.id, op, holds });
            }
        });
    }
    holds
}

/// A number of a recording: its node and the value it holds.
#[derive(Debug, Clone, Copy)]
pub struct Traced {
    id: u32,
    value: f64,
}

impl Traced {
    /// Whether it is a constant of the graph.
    fn is_constant(self) -> bool {
        TAPE.with(|t| {
            let guard = t.borrow();
            let tape = guard.as_ref().expect("a traced number is used outside a recording");
            matches!(tape.graph.nodes[self.id as usize], Node::Const(_))
        })
    }

    /// The constant it is, if it is one.
    fn known(self) -> Option<f64> {
        self.is_constant().then_some(self.value)
    }

    /// `f(self, other)` of value `value`: a constant where both are.
    fn binary(self, other: Traced, node: Node, value: f64) -> Traced {
        if self.is_constant() && other.is_constant() {
            folded(value)
        } else {
            push(node, value)
        }
    }

    fn unary(self, node: Node, value: f64) -> Traced {
        if self.is_constant() {
            folded(value)
        } else {
            push(node, value)
        }
    }

    fn call(self, f: Func, other: Option<Traced>) -> Traced {
        let y = other.map_or(0.0, |o| o.value);
        let value = f.eval(self.value, y);
        match other {
            None => self.unary(Node::Call(f, self.id, u32::MAX), value),
            Some(o) => self.binary(o, Node::Call(f, self.id, o.id), value),
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
        self.binary(o, Node::Add(self.id, o.id), self.value + o.value)
    }
}

impl Sub for Traced {
    type Output = Traced;
    fn sub(self, o: Traced) -> Traced {
        if o.known().is_some_and(|z| z == 0.0 && z.is_sign_positive()) {
            return self;
        }
        self.binary(o, Node::Sub(self.id, o.id), self.value - o.value)
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
        self.binary(o, Node::Mul(self.id, o.id), self.value * o.value)
    }
}

impl Div for Traced {
    type Output = Traced;
    fn div(self, o: Traced) -> Traced {
        if o.known() == Some(1.0) {
            return self;
        }
        self.binary(o, Node::Div(self.id, o.id), self.value / o.value)
    }
}

impl Neg for Traced {
    type Output = Traced;
    fn neg(self) -> Traced {
        self.unary(Node::Neg(self.id), -self.value)
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
        let k = TAPE.with(|t| {
            let mut guard = t.borrow_mut();
            let tape = guard.as_mut().expect("a traced number is used outside a recording");
            let next = tape.params.len() as u32;
            let k = *tape.param_of.entry(x.to_bits()).or_insert(next);
            if k == next {
                tape.params.push(x);
            }
            k
        });
        push(Node::Param(k), x)
    }
    fn value(self) -> f64 {
        self.value
    }
    fn sqrt(self) -> Traced {
        self.unary(Node::Sqrt(self.id), self.value.sqrt())
    }
    fn sin_cos(self) -> (Traced, Traced) {
        (self.call(Func::Sin, None), self.call(Func::Cos, None))
    }
    fn powf(self, n: Traced) -> Traced {
        self.call(Func::Powf, Some(n))
    }
    fn abs(self) -> Traced {
        self.unary(Node::Abs(self.id), self.value.abs())
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
}

#[cfg(test)]
mod tests {
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

    /// `x + 0` is kept (it turns -0 into +0); `x - 0` is dropped (it never changes x).
    #[test]
    fn signed_zeros_survive_simplification() {
        let (g, p) = record(&[-0.0], |x| Some(vec![x[0] + 0.0, x[0] - 0.0])).expect("a graph");
        let (_, out) = g.eval(&[-0.0], &p);
        assert!(out[0].is_sign_positive() && out[1].is_sign_negative());
    }
}
