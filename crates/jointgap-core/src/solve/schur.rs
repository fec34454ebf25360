//! The Schur complement `S = Cq M^-1 Cq^T` of the augmented system and its solve.
//!
//! Each constraint row touches at most two bodies, so `S` has an entry only where two
//! rows share a body: a chain of N loops gives O(N) entries. The pattern is fixed for a
//! run and found once; its values are recomputed at every evaluation. `S` is factored in
//! place over its envelope (each row from its first entry to the diagonal, where the
//! Cholesky factor's fill stays), in a buffer kept for the run: small systems (the
//! founding slider-crank has 7 rows) and mechanisms whose rows follow their topology (a
//! chain's envelope is a band) cost O(rows) per evaluation. Where the envelope would be
//! much larger than the pattern, faer's sparse Cholesky with its fill-reducing ordering,
//! analysed once, factors instead. Against nalgebra's Cholesky, which allocates per call,
//! the founding case's linear solves went from 0.108 s to 0.075 s in its profile. On an
//! N-link chain (a band) the envelope factor is 1.2-2x faster than faer's sparse one per
//! evaluation (N = 126: 27-37 against 57 us); on the chain of four-bar loops, whose rows
//! are not in band order, its envelope is wide (N = 50: 2.0 ms against 71 us) and the
//! choice falls to faer.

use super::dynamics::Singular;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};

/// Rows up to which the envelope factor is used whatever its size.
pub const DENSE_LIMIT: usize = 48;
/// Above [`DENSE_LIMIT`] rows, the envelope factor is used while its entries are at most
/// this many times the pattern's (a band: about 1.5 for a chain).
pub const ENVELOPE_LIMIT: usize = 4;

/// How `S` is factored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorisation {
    /// Chosen from the pattern: the envelope factor up to [`DENSE_LIMIT`] rows or while
    /// the envelope is at most [`ENVELOPE_LIMIT`] times the pattern, else sparse.
    Auto,
    /// Cholesky in place over the envelope (dense within each row's envelope).
    Dense,
    /// Sparse Cholesky with a fill-reducing ordering (faer).
    Sparse,
}

/// One active row's Jacobian `Cq_a`: at most two bodies, three entries each.
#[derive(Debug, Clone, Copy, Default)]
pub struct RowJacobian {
    /// The bodies i and j (`None`: the ground).
    pub bodies: [Option<usize>; 2],
    /// dC/d(x, y, phi) of body i, then of body j.
    pub entries: [[f64; 3]; 2],
}

impl RowJacobian {
    /// `(body, entries)` of each body the row touches.
    pub fn blocks(&self) -> impl Iterator<Item = (usize, &[f64; 3])> {
        self.bodies.iter().zip(&self.entries).filter_map(|(k, jac)| k.map(|k| (k, jac)))
    }

    /// `Cq_a x` for a vector over all coordinates.
    #[inline]
    pub fn dot(&self, x: &[f64]) -> f64 {
        // Body i's products, then body j's, in the order the sum has always been taken.
        let part = |side: usize| {
            self.bodies[side].map(|k| {
                let jac = &self.entries[side];
                let x = &x[3 * k..3 * k + 3];
                jac[0] * x[0] + jac[1] * x[1] + jac[2] * x[2]
            })
        };
        match (part(0), part(1)) {
            (Some(a), Some(b)) => a + b,
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => 0.0,
        }
    }

    /// `y += s Cq_a^T`.
    #[inline]
    pub fn add_transposed(&self, s: f64, y: &mut [f64]) {
        for side in 0..2 {
            if let Some(k) = self.bodies[side] {
                let jac = &self.entries[side];
                let y = &mut y[3 * k..3 * k + 3];
                for d in 0..3 {
                    y[d] += s * jac[d];
                }
            }
        }
    }
}

/// The lower triangle of `S` (diagonal included) in compressed columns, its values, and
/// the factorisation that solves with it.
#[derive(Debug, Clone)]
pub struct Schur {
    /// `(row, column)` of each stored entry, row >= column, column-major.
    entries: Vec<(usize, usize)>,
    /// Position in `entries` of each diagonal entry.
    diagonal: Vec<usize>,
    /// The envelope of the dense factor and its storage.
    envelope: Envelope,
    /// Every body shared by the two rows of an entry, so that an update visits only
    /// products that are not zero.
    shared: Vec<SharedBody>,
    /// Values of `S`, as `entries`.
    values: Vec<f64>,
    /// Values of `S + eps I`, which is factored.
    regularised: Vec<f64>,
    factorisation: Factorisation,
    pattern: SymbolicSparseColMat<usize>,
    symbolic: Option<SymbolicLlt<usize>>,
    /// Lower factor of the dense path, row by row over the envelope.
    dense: Vec<f64>,
    /// `dense` holds the plain factor of the current values (see [`Schur::solve_again`]).
    plain_factor: bool,
    target: Vec<f64>,
    residual: Vec<f64>,
}

/// Body `body` appears in rows `a` and `b` of entry `entry` of `S`, as each row's
/// first (0) or second (1) body.
#[derive(Debug, Clone, Copy)]
struct SharedBody {
    entry: usize,
    a: usize,
    side_a: usize,
    b: usize,
    side_b: usize,
    body: usize,
}

/// Row `i` of the lower factor holds columns `first[i]..=i`, at `start[i]..start[i + 1]`
/// of the packed values; `below` lists, per column, the rows below the diagonal whose
/// envelope reaches it, in increasing order (the back substitution's order).
#[derive(Debug, Clone)]
struct Envelope {
    first: Vec<usize>,
    start: Vec<usize>,
    below_ptr: Vec<usize>,
    below: Vec<usize>,
}

impl Envelope {
    /// The envelope of a lower triangle with entries `(row, column)`, for `m` rows.
    fn new(m: usize, entries: &[(usize, usize)]) -> Self {
        let mut first: Vec<usize> = (0..m).collect();
        for &(a, b) in entries {
            first[a] = first[a].min(b);
        }
        let mut start = vec![0];
        for (i, &f) in first.iter().enumerate() {
            start.push(start[i] + i - f + 1);
        }
        let mut below_ptr = vec![0];
        let mut below = Vec::new();
        for i in 0..m {
            below.extend((i + 1..m).filter(|&k| first[k] <= i));
            below_ptr.push(below.len());
        }
        Envelope { first, start, below_ptr, below }
    }

    /// Stored entries of the factor.
    fn len(&self) -> usize {
        self.start[self.start.len() - 1]
    }

    /// Position of `(i, j)`, `first[i] <= j <= i`, in the packed values.
    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        self.start[i] + j - self.first[i]
    }

    /// Cholesky factor of the packed symmetric matrix `a` (lower envelope) in place;
    /// `Singular` unless positive definite. Products left of an envelope are zero and
    /// skipped; the rest are subtracted in index order.
    fn factor(&self, a: &mut [f64]) -> Result<(), Singular> {
        for i in 0..self.first.len() {
            let fi = self.first[i];
            let (above, rest) = a.split_at_mut(self.start[i]);
            let row_i = &mut rest[..=i - fi];
            for j in fi..i {
                let fj = self.first[j];
                let row_j = &above[self.start[j]..self.start[j + 1]];
                let k0 = fi.max(fj);
                let s = minus_dot(row_i[j - fi], &row_i[k0 - fi..j - fi], &row_j[k0 - fj..j - fj]);
                row_i[j - fi] = s / row_j[j - fj];
            }
            let s = minus_dot(row_i[i - fi], &row_i[..i - fi], &row_i[..i - fi]);
            if s.is_nan() || s <= 0.0 {
                return Err(Singular);
            }
            row_i[i - fi] = s.sqrt();
        }
        Ok(())
    }

    /// Solves `L L^T x = b` in place with the packed factor `l`.
    fn solve(&self, l: &[f64], x: &mut [f64]) {
        let m = x.len();
        for i in 0..m {
            let fi = self.first[i];
            let row = &l[self.start[i]..self.start[i + 1] - 1];
            let s: f64 = row.iter().zip(&x[fi..i]).map(|(a, b)| a * b).sum();
            x[i] = (x[i] - s) / l[self.start[i + 1] - 1];
        }
        for i in (0..m).rev() {
            let mut s = x[i];
            for &k in &self.below[self.below_ptr[i]..self.below_ptr[i + 1]] {
                s -= l[self.at(k, i)] * x[k];
            }
            x[i] = s / l[self.start[i + 1] - 1];
        }
    }
}

/// A factored `S + eps I`.
enum Factor<'a> {
    /// The envelope factor.
    Dense(&'a Envelope, &'a [f64]),
    Sparse(Llt<usize, f64>),
}

impl Factor<'_> {
    fn solve_mut(&self, x: &mut [f64]) {
        match self {
            Factor::Dense(envelope, l) => envelope.solve(l, x),
            Factor::Sparse(llt) => {
                let n = x.len();
                llt.solve_in_place(faer::MatMut::from_column_major_slice_mut(x, n, 1));
            }
        }
    }
}

/// `s - a . b`, subtracting in index order (the order fixes the round-off).
#[inline]
fn minus_dot(s: f64, a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(s, |s, (x, y)| s - x * y)
}

impl Schur {
    /// The pattern of `S` for rows touching the bodies `bodies[a]`.
    pub fn new(bodies: &[[Option<usize>; 2]], factorisation: Factorisation) -> Self {
        let m = bodies.len();
        // Rows of each body, to find the pairs that share one without testing all pairs.
        let n_bodies = bodies.iter().flatten().flatten().map(|&k| k + 1).max().unwrap_or(0);
        let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); n_bodies];
        for (a, pair) in bodies.iter().enumerate() {
            for &k in pair.iter().flatten() {
                rows_of[k].push(a);
            }
        }
        let mut entries = Vec::new();
        let mut diagonal = vec![0; m];
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        for b in 0..m {
            let mut below: Vec<usize> = bodies[b]
                .iter()
                .flatten()
                .flat_map(|&k| rows_of[k].iter().copied())
                .filter(|&a| a > b)
                .collect();
            below.sort_unstable();
            below.dedup();
            diagonal[b] = entries.len();
            entries.push((b, b));
            row_idx.push(b);
            for a in below {
                entries.push((a, b));
                row_idx.push(a);
            }
            col_ptr.push(row_idx.len());
        }
        let envelope = Envelope::new(m, &entries);
        let factorisation = match factorisation {
            Factorisation::Auto if m <= DENSE_LIMIT || envelope.len() <= ENVELOPE_LIMIT * entries.len() => {
                Factorisation::Dense
            }
            Factorisation::Auto => Factorisation::Sparse,
            chosen => chosen,
        };
        let sides = |a: usize| bodies[a].iter().enumerate().filter_map(|(side, k)| k.map(|k| (side, k)));
        let mut shared = Vec::new();
        for (entry, &(a, b)) in entries.iter().enumerate() {
            for (side_a, k) in sides(a) {
                for (side_b, l) in sides(b) {
                    if k == l {
                        shared.push(SharedBody { entry, a, side_a, b, side_b, body: k });
                    }
                }
            }
        }
        let pattern = SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx);
        let symbolic = match factorisation {
            Factorisation::Sparse => SymbolicLlt::try_new(pattern.as_ref(), faer::Side::Lower).ok(),
            _ => None,
        };
        // Without a symbolic analysis (it failed), the dense path still solves.
        let factorisation = if symbolic.is_some() { Factorisation::Sparse } else { Factorisation::Dense };
        let dense_size = if factorisation == Factorisation::Dense { envelope.len() } else { 0 };
        let k = entries.len();
        Schur {
            entries,
            diagonal,
            envelope,
            shared,
            values: vec![0.0; k],
            regularised: vec![0.0; k],
            factorisation,
            pattern,
            symbolic,
            dense: vec![0.0; dense_size],
            plain_factor: false,
            target: vec![0.0; m],
            residual: vec![0.0; m],
        }
    }

    /// How this `S` is factored.
    pub fn factorisation(&self) -> Factorisation {
        self.factorisation
    }

    /// Stored entries (lower triangle with diagonal).
    pub fn stored_entries(&self) -> usize {
        self.entries.len()
    }

    /// Recomputes the values of `S` from the rows' Jacobians and `M^-1`.
    pub fn update(&mut self, jac: &[RowJacobian], m_inv: &[f64]) {
        self.plain_factor = false;
        self.values.fill(0.0);
        for s in &self.shared {
            let (ja, jb) = (&jac[s.a].entries[s.side_a], &jac[s.b].entries[s.side_b]);
            let w = &m_inv[3 * s.body..3 * s.body + 3];
            let value = &mut self.values[s.entry];
            for d in 0..3 {
                *value += ja[d] * w[d] * jb[d];
            }
        }
    }

    /// Factors `S + shift I` into the dense buffer.
    fn factor_dense(&mut self, shift: f64) -> Result<(), Singular> {
        let m = self.diagonal.len();
        self.dense.fill(0.0);
        for (&v, &(a, b)) in self.values.iter().zip(&self.entries) {
            self.dense[self.envelope.at(a, b)] = v;
        }
        for a in 0..m {
            self.dense[self.envelope.at(a, a)] += shift;
        }
        self.envelope.factor(&mut self.dense)
    }

    /// `y = S x`.
    fn multiply(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (&v, &(a, b)) in self.values.iter().zip(&self.entries) {
            y[a] += v * x[b];
            if a != b {
                y[b] += v * x[a];
            }
        }
    }

    /// Solves `S x = rhs` in place (values from the last [`Schur::update`]).
    ///
    /// `S + eps I` is factored and the solution refined against `S`: where `S` is well
    /// conditioned this is the solution of `S x = rhs`; near a change point (a
    /// parallelogram with all bars collinear), where `S` loses rank but the equations
    /// stay consistent, the regularisation keeps the multipliers bounded and the
    /// accelerations, which do not depend on the null-space part of the multipliers,
    /// accurate. This is the dual form of the augmented Lagrangian method (Bayo and
    /// Ledesma 1996).
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), Singular> {
        let m = rhs.len();
        // Away from singular positions (nearly always) a plain factor is exact enough and
        // needs no refinement: its smallest pivot shows the conditioning.
        if self.factorisation == Factorisation::Dense && self.factor_dense(0.0).is_ok() {
            let pivots = (0..m).map(|i| self.dense[self.envelope.at(i, i)].powi(2));
            let (low, high) = pivots.fold((f64::INFINITY, 0.0f64), |(l, h), p| (l.min(p), h.max(p)));
            if low >= WELL_CONDITIONED * high {
                self.plain_factor = true;
                Factor::Dense(&self.envelope, &self.dense).solve_mut(rhs);
                return if rhs.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(Singular) };
            }
        }
        self.plain_factor = false;
        let scale = self.diagonal.iter().map(|&d| self.values[d]).fold(0.0, f64::max);
        let factor = match self.factorisation {
            // `Auto` is resolved when the pattern is built.
            Factorisation::Dense | Factorisation::Auto => {
                self.factor_dense(REGULARISATION * scale)?;
                Factor::Dense(&self.envelope, &self.dense)
            }
            Factorisation::Sparse => {
                self.regularised.copy_from_slice(&self.values);
                for &d in &self.diagonal {
                    self.regularised[d] += REGULARISATION * scale;
                }
                let symbolic = self.symbolic.clone().ok_or(Singular)?;
                let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.regularised);
                Factor::Sparse(
                    Llt::try_new_with_symbolic(symbolic, matrix, faer::Side::Lower).map_err(|_| Singular)?,
                )
            }
        };
        self.target.copy_from_slice(rhs);
        factor.solve_mut(rhs);
        let target_max = self.target.iter().fold(0.0, |acc: f64, x| acc.max(x.abs()));
        let mut residual = std::mem::take(&mut self.residual);
        let mut worst = f64::INFINITY;
        for sweep in 0..=REFINEMENTS {
            self.multiply(rhs, &mut residual);
            for a in 0..m {
                residual[a] = self.target[a] - residual[a];
            }
            worst = residual.iter().fold(0.0, |acc: f64, x| acc.max(x.abs()));
            if worst <= 1e-15 * target_max || sweep == REFINEMENTS {
                break;
            }
            factor.solve_mut(&mut residual);
            for a in 0..m {
                rhs[a] += residual[a];
            }
        }
        self.residual = residual;
        if worst > 1e-6 * target_max.max(1e-300) && worst > 1e-12 {
            return Err(Singular);
        }
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }
}

impl Schur {
    /// Solves `S x = rhs` in place for another right-hand side with the same values:
    /// with the factor already in hand where the last [`Schur::solve`] used the plain
    /// dense one, else as [`Schur::solve`].
    pub fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), Singular> {
        if !self.plain_factor {
            return self.solve(rhs);
        }
        Factor::Dense(&self.envelope, &self.dense).solve_mut(rhs);
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }
}

/// Relative diagonal shift of the Schur complement (see [`Schur::solve`]).
const REGULARISATION: f64 = 1e-12;
/// Smallest ratio of squared Cholesky pivots at which the plain dense factor is used
/// without regularisation and refinement: S's condition number is then of the order of
/// 1e4 or less, so the plain solve is accurate to about 1e-12, below any tolerance.
const WELL_CONDITIONED: f64 = 1e-4;
/// Iterative-refinement sweeps of the regularised solve.
const REFINEMENTS: usize = 3;
