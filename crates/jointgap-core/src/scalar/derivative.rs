//! Exact first derivatives of a recorded [`Graph`] by reverse-mode differentiation: the
//! node values are computed forward, then each node's derivatives of the chosen outputs
//! (its adjoints) are gathered from its uses by the chain rule, the last node first, so
//! that one sweep gives every input's derivatives (a planar mechanism's accelerations
//! have half as many rows as the state has columns). The graph is one path of its kernels, so the
//! derivatives are those of the branch that holds there (in contact or not, a friction
//! regime); at a kink (`|x|` at 0, `max` of equal numbers) they take one side's.

use std::ops::Range;

use super::traced::{Func, Graph, Node};

impl Graph {
    /// What [`Graph::jacobian`] needs to know of this graph to differentiate outputs `of`
    /// with respect to inputs `wrt`, worked out once.
    pub fn sweep(&self, wrt: Range<usize>, of: Range<usize>) -> Sweep {
        assert!(self.blocks.is_empty(), "a graph with blocks is differentiated flattened");
        let count = self.nodes.len();
        let mut reaches = vec![false; count];
        for (k, &node) in self.nodes.iter().enumerate() {
            reaches[k] = match node {
                Node::Input(i) => wrt.contains(&(i as usize)),
                _ => arguments(node).any(|a| reaches[a as usize]),
            };
        }
        let mut needed = vec![false; count];
        for &o in &self.outputs[of.clone()] {
            needed[o as usize] = true;
        }
        for k in (0..count).rev() {
            if needed[k] {
                arguments(self.nodes[k]).for_each(|a| needed[a as usize] = true);
            }
        }
        let between: Vec<bool> = reaches.iter().zip(&needed).map(|(&r, &n)| r && n).collect();
        let order = (0..count as u32).rev().filter(|&k| between[k as usize]).collect();
        Sweep { wrt, of, between, order }
    }

    /// The derivatives of the outputs with respect to the inputs of `sweep` (made by
    /// [`Graph::sweep`] for this graph) at inputs `x` and parameters `p`, each handed
    /// to `put(output - of.start, input - wrt.start, d)`; `false` (and nothing handed)
    /// where a guard fails there, the path not being the kernels' at `x`. `adjoint`
    /// holds zeros between calls.
    pub fn jacobian(
        &self,
        x: &[f64],
        p: &[f64],
        sweep: &Sweep,
        adjoint: &mut Vec<f64>,
        mut put: impl FnMut(usize, usize, f64),
    ) -> bool {
        let v = self.values(x, p);
        if !self.holds(&v) {
            return false;
        }
        let Sweep { wrt, of, between, order } = sweep;
        let (n, m) = (wrt.len(), of.len());
        for o in 0..m {
            for j in 0..n {
                put(o, j, 0.0);
            }
        }
        // Row k: the derivatives of the outputs with respect to node k (its adjoints),
        // gathered from its uses, the last first; each row is zeroed again once passed on.
        if adjoint.len() < self.nodes.len() * m {
            adjoint.resize(self.nodes.len() * m, 0.0);
        }
        for (o, &node) in self.outputs[of.clone()].iter().enumerate() {
            if between[node as usize] {
                adjoint[node as usize * m + o] += 1.0;
            }
        }
        for &k in order {
            let k = k as usize;
            let (before, row) = adjoint.split_at_mut(k * m);
            let row = &mut row[..m];
            let mut term = |arg: u32, slope: f64| {
                let i = arg as usize;
                if !between[i] || slope == 0.0 {
                    // A zero slope passes nothing on (not even an infinite adjoint's NaN).
                    return;
                }
                let to = &mut before[i * m..(i + 1) * m];
                if slope.is_finite() {
                    to.iter_mut().zip(row.iter()).for_each(|(t, &a)| *t += slope * a);
                } else {
                    // An infinite slope passes nothing on where the adjoint is zero.
                    to.iter_mut()
                        .zip(row.iter())
                        .filter(|(_, &a)| a != 0.0)
                        .for_each(|(t, &a)| *t += slope * a);
                }
            };
            let value = v[k];
            let a = |i: u32| v[i as usize];
            match self.nodes[k] {
                Node::Const(_) | Node::Param(_) | Node::Out(..) => {}
                Node::Input(i) => {
                    let j = i as usize - wrt.start;
                    row.iter().enumerate().for_each(|(o, &d)| put(o, j, d));
                }
                Node::Add(p, q) => {
                    term(p, 1.0);
                    term(q, 1.0);
                }
                Node::Sub(p, q) => {
                    term(p, 1.0);
                    term(q, -1.0);
                }
                Node::Mul(p, q) => {
                    term(p, a(q));
                    term(q, a(p));
                }
                Node::Div(p, q) => {
                    term(p, 1.0 / a(q));
                    term(q, -value / a(q));
                }
                Node::Neg(p) => term(p, -1.0),
                Node::Sqrt(p) => term(p, 0.5 / value),
                Node::Abs(p) => term(p, side(a(p))),
                Node::Call(f, p, q) => {
                    let (x, y) = (a(p), if q == u32::MAX { 0.0 } else { a(q) });
                    match f {
                        Func::Sin => term(p, x.sin_cos().1),
                        Func::Cos => term(p, -x.sin_cos().0),
                        Func::Powf => {
                            term(p, y * x.powf(y - 1.0));
                            term(q, value * x.ln());
                        }
                        Func::Signum => {}
                        // As f64's: the first argument unless the second is larger or the
                        // first is NaN.
                        Func::Max if x >= y || y.is_nan() => term(p, 1.0),
                        Func::Min if x <= y || y.is_nan() => term(p, 1.0),
                        Func::Max | Func::Min => term(q, 1.0),
                        Func::Tanh => term(p, 1.0 - value * value),
                        Func::Cosh => term(p, x.sinh()),
                        Func::Atan2 => {
                            let r2 = x * x + y * y;
                            term(p, y / r2);
                            term(q, -x / r2);
                        }
                        // x - k y, k the whole number of y's taken off: a slope of 1 in
                        // x, -k in y (between the jumps).
                        Func::RemEuclid => {
                            term(p, 1.0);
                            term(q, -((x - value) / y).round());
                        }
                        Func::Implicit(f) => {
                            let (dx, dy) = (f.slopes)(x, y, value);
                            term(p, dx);
                            term(q, dy);
                        }
                    }
                }
            }
            row.fill(0.0);
        }
        true
    }
}

/// The nodes of a graph that lie between the inputs and the outputs it is differentiated
/// for ([`Graph::sweep`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    wrt: Range<usize>,
    of: Range<usize>,
    /// Whether node k depends on an input of `wrt` and an output of `of` on it.
    between: Vec<bool>,
    /// Those nodes, the last first.
    order: Vec<u32>,
}

/// The nodes an operation reads.
fn arguments(node: Node) -> impl Iterator<Item = u32> {
    let (a, b) = match node {
        Node::Const(_) | Node::Param(_) | Node::Input(_) | Node::Out(..) => (None, None),
        Node::Add(p, q) | Node::Sub(p, q) | Node::Mul(p, q) | Node::Div(p, q) => (Some(p), Some(q)),
        Node::Neg(p) | Node::Sqrt(p) | Node::Abs(p) => (Some(p), None),
        Node::Call(_, p, q) => (Some(p), (q != u32::MAX).then_some(q)),
    };
    a.into_iter().chain(b)
}

/// The slope of `|x|`: the sign of `x`, 0 at 0.
fn side(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use crate::scalar::{c, record, Real, Traced};

    /// Derivatives of `kernel` at `x` by the graph, as a matrix by rows.
    fn derivatives(x: &[f64], kernel: impl FnOnce(&[Traced]) -> Vec<Traced>) -> Vec<Vec<f64>> {
        let (g, p) = record(x, |t| Some(kernel(t))).expect("a graph");
        let mut jac = vec![vec![f64::NAN; x.len()]; g.outputs.len()];
        let sweep = g.sweep(0..x.len(), 0..g.outputs.len());
        let mut adjoint = Vec::new();
        assert!(g.jacobian(x, &p, &sweep, &mut adjoint, |i, j, d| jac[i][j] = d));
        assert!(adjoint.iter().all(|&a| a == 0.0), "the adjoints are left zero");
        jac
    }

    /// Every operation's derivative against its closed form.
    #[test]
    fn each_operation_has_its_closed_form_derivative() {
        let (x, y) = (0.7, 1.3);
        let jac = derivatives(&[x, y], |t| {
            let (a, b) = (t[0], t[1]);
            let (s, co) = a.sin_cos();
            vec![
                a * b + a / b - b,
                -a.sqrt() + (a - b).abs(),
                s * co,
                a.powf(b),
                a.powf(c::<Traced>(2.5)),
                a.max(b) + a.min(b) * 3.0,
                a.tanh() + b.cosh() + a.signum(),
                a.atan2(b),
                (a * 10.0).rem_euclid(b),
            ]
        });
        let expected = [
            [y + 1.0 / y, x - x / (y * y) - 1.0],
            [-0.5 / x.sqrt() - 1.0, 1.0],
            [(2.0 * x).cos(), 0.0],
            [y * x.powf(y - 1.0), x.powf(y) * x.ln()],
            [2.5 * x.powf(1.5), 0.0],
            [3.0, 1.0],
            [1.0 - x.tanh().powi(2), y.sinh()],
            [y / (x * x + y * y), -x / (x * x + y * y)],
            [10.0, -5.0],
        ];
        for (got, want) in jac.iter().zip(expected) {
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() <= 1e-14 * w.abs().max(1.0), "{got:?} against {want:?}");
            }
        }
    }

    /// A branch's derivatives, and no derivatives where the path does not hold.
    #[test]
    fn derivatives_follow_the_recorded_branch() {
        let kernel = |t: &[Traced]| {
            let r = (t[0] * t[0] + t[1] * t[1]).sqrt() - 1.0;
            vec![if r > 0.0 { r * c::<Traced>(3.0) } else { t[1] * 2.0 }]
        };
        let (x, y) = (3.0, 4.0);
        let jac = derivatives(&[x, y], kernel);
        for (got, want) in jac[0].iter().zip([3.0 * x / 5.0, 3.0 * y / 5.0]) {
            assert!((got - want).abs() <= 1e-15 * want, "{got} against {want}");
        }
        let (g, p) = record(&[x, y], |t| Some(kernel(t))).expect("a graph");
        let sweep = g.sweep(0..2, 0..1);
        assert!(!g.jacobian(&[0.1, 0.2], &p, &sweep, &mut Vec::new(), |_, _, _| panic!("no derivative")));
    }

    /// An infinite slope times a zero derivative stays zero: `sqrt(u)` at `u = 0` where
    /// `u` does not move with the input.
    #[test]
    fn a_zero_derivative_through_an_infinite_slope_stays_zero() {
        let jac = derivatives(&[0.5], |t| vec![(t[0] * 0.0).sqrt() + t[0]]);
        assert_eq!(jac, vec![vec![1.0]]);
    }
}
