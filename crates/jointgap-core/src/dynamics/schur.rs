//! The Schur complement `S = Cq M^-1 Cq^T` of the augmented system and its solve.
//!
//! Each constraint row touches at most two bodies, so `S` has an entry only where two
//! rows share a body: a chain of N loops gives O(N) entries. The pattern is fixed for a
//! run and found once; its values are recomputed at every evaluation. `S` is factored in
//! place over its envelope (each row from its first entry to the diagonal, where the
//! Cholesky factor's fill stays), in a buffer kept for the run, by lists of positions laid
//! out once that visit only the entries the factor can fill: small systems (the founding
//! slider-crank has 4 rows once its driven crank is set aside, see `prescribed`) and
//! mechanisms whose rows follow their topology (a chain's envelope is a band) cost
//! O(rows) per evaluation. Where the envelope would be
//! much larger than the pattern, faer's sparse Cholesky with its fill-reducing ordering,
//! analysed once, factors instead. Against nalgebra's Cholesky, which allocates per call,
//! the founding case's linear solves went from 0.108 s to 0.075 s in its profile. On an
//! N-link chain (a band) the envelope factor is 1.2-2x faster than faer's sparse one per
//! evaluation (N = 126: 27-37 against 57 us); on the chain of four-bar loops, whose rows
//! are not in band order, its envelope is wide (N = 50: 2.0 ms against 71 us) and the
//! choice falls to faer.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Par};

use crate::mechanics::kind::Block;
use crate::mechanics::layout::Layout;
use crate::mechanics::planar_body::BodyRow;
use crate::scalar::Real;

/// The augmented system is singular: the mechanism locks up or passes a singular
/// configuration (e.g. a four-bar at a change point). Kept with the Schur complement,
/// whose factorisation is where the equations of motion find it.
#[derive(Debug, Clone, Copy)]
pub struct Singular;

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

/// One active row's Jacobian `Cq_a`: at most two bodies, a block over each one's
/// velocities.
#[derive(Debug, Clone, Copy, Default)]
pub struct RowJacobian<R: Block = BodyRow> {
    /// The bodies i and j (`None`: the ground).
    pub bodies: [Option<usize>; 2],
    /// Where each body's velocities start in `v` (the layout's; unused for the ground).
    pub at: [usize; 2],
    /// The block of body i, then of body j.
    pub entries: [R; 2],
}

impl<R: Block> RowJacobian<R> {
    /// The row of bodies `bodies`, entries zero, placed by `layout`.
    pub fn new(bodies: [Option<usize>; 2], layout: &Layout) -> Self {
        let at = bodies.map(|b| b.map_or(0, |k| layout.slot(k).v_at));
        RowJacobian { bodies, at, entries: Default::default() }
    }

    /// `(body, entries)` of each body the row touches.
    pub fn blocks(&self) -> impl Iterator<Item = (usize, &R)> {
        self.bodies.iter().zip(&self.entries).filter_map(|(k, jac)| k.map(|k| (k, jac)))
    }

    /// `(velocity address, entries)` of each body the row touches.
    pub fn placed_blocks(&self) -> impl Iterator<Item = (usize, &R)> {
        (0..2).filter(|&side| self.bodies[side].is_some()).map(|side| (self.at[side], &self.entries[side]))
    }

    /// `Cq_a x` for a vector over all coordinates.
    #[inline(always)]
    pub fn dot(&self, x: &[f64]) -> f64 {
        self.dot_of([self.entries[0].as_ref(), self.entries[1].as_ref()], x)
    }

    /// `Cq_a x` with this row's bodies and the blocks `entries`, in any number type.
    #[inline(always)]
    pub fn dot_of<T: Real>(&self, entries: [&[T]; 2], x: &[T]) -> T {
        // Body i's products, then body j's, in the order the sum has always been taken.
        let part = |side: usize| {
            self.bodies[side].map(|_| {
                let jac = entries[side];
                let x = &x[self.at[side]..self.at[side] + jac.len()];
                jac[1..].iter().zip(&x[1..]).fold(jac[0] * x[0], |sum, (j, x)| sum + *j * *x)
            })
        };
        match (part(0), part(1)) {
            (Some(a), Some(b)) => a + b,
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => T::constant(0.0),
        }
    }

    /// `y += s Cq_a^T`.
    #[inline(always)]
    pub fn add_transposed(&self, s: f64, y: &mut [f64]) {
        self.add_transposed_of([self.entries[0].as_ref(), self.entries[1].as_ref()], s, y);
    }

    /// `y += s Cq_a^T` with this row's bodies and the blocks `entries`, in any number
    /// type.
    #[inline(always)]
    pub fn add_transposed_of<T: Real>(&self, entries: [&[T]; 2], s: T, y: &mut [T]) {
        for side in 0..2 {
            if self.bodies[side].is_some() {
                let y = &mut y[self.at[side]..self.at[side] + entries[side].len()];
                for (y, e) in y.iter_mut().zip(entries[side]) {
                    *y += s * *e;
                }
            }
        }
    }
}

/// The lower triangle of `S` (diagonal included) in compressed columns, its values, and
/// the factorisation that solves with it.
#[derive(Debug, Clone)]
pub struct Schur<R: Block = BodyRow> {
    /// `(row, column)` of each stored entry, row >= column, column-major.
    entries: Vec<(usize, usize)>,
    /// Position in `entries` of each diagonal entry.
    diagonal: Vec<usize>,
    /// The envelope of the dense factor and its storage.
    envelope: Envelope,
    /// Every body shared by the two rows of an entry, so that an update visits only
    /// products that are not zero.
    shared: Vec<SharedBody>,
    /// Each row's entries for its first and second body (`2 row + side`), as they are
    /// and times that body's inverse mass: an update's products are then one lookup each.
    plain: Vec<R>,
    scaled: Vec<R>,
    /// Values of `S`, as `entries`; computed from `plain` and `scaled` when a path
    /// needs them (the plain dense factor sums straight into its buffer).
    values: Vec<f64>,
    values_current: bool,
    /// Values of `S + eps I`, which is factored.
    regularised: Vec<f64>,
    factorisation: Factorisation,
    pattern: SymbolicSparseColMat<usize>,
    /// The sparse path's analysis (ordering and the factor's pattern), done once.
    symbolic: Option<Arc<SymbolicCholesky<usize>>>,
    /// Values of the sparse path's factor, laid out by `symbolic`.
    sparse: Vec<f64>,
    /// Lower factor of the dense path, row by row over the envelope.
    dense: Vec<f64>,
    /// The diagonal of the matrix the dense path factored last (its pivots' measure).
    dense_diagonal: Vec<f64>,
    /// `dense` or `sparse` holds the plain factor of the current values (see
    /// [`Schur::solve_again`]).
    plain_factor: bool,
    /// The last [`Schur::solve`] found `S` ill-conditioned (see [`Schur::ill_conditioned`]).
    ill_conditioned: bool,
    /// The last [`Schur::solve`] found `S` rank deficient (see [`Schur::solve`]).
    rank_deficient: bool,
    target: Vec<f64>,
    residual: Vec<f64>,
}

/// Rows `a` and `b` of entry `entry` of `S` share a body, as row-sides
/// `2 row + side` (side 0: the row's first body, 1: its second); `packed` is the entry's
/// place in the dense factor's buffer.
#[derive(Debug, Clone, Copy)]
struct SharedBody {
    entry: usize,
    packed: u32,
    a: usize,
    b: usize,
}

/// The dense path's factor: row `i` of `L` is stored from its first entry to the
/// diagonal (its envelope), packed row after row. The pattern is fixed for a run, so the
/// factorisation and both substitutions are laid out once as lists of packed positions
/// of the entries that can be non-zero: an evaluation then runs over flat lists, not
/// over row bounds. On the founding case this took the factor from about 1900 to 900
/// instructions and the solve from 830 to 660 (callgrind); the arithmetic is the same,
/// in the same order.
#[derive(Debug, Clone, Default)]
struct Envelope {
    /// Stored entries (the envelope's size).
    size: usize,
    /// Packed position of each entry of `S` given to [`Envelope::new`], and of each
    /// diagonal entry.
    position: Vec<u32>,
    diagonal: Vec<u32>,
    /// One per stored entry of the factor, in the row-by-row Cholesky order.
    steps: Vec<FactorStep>,
    /// Positions `(L_ik, L_jk)` of the products each step subtracts, in index order `k`.
    products: Vec<(u32, u32)>,
    /// Per row `i`, `(k, position of L_ik)` for the columns `k < i` where the factor
    /// can be non-zero, in increasing `k` (the forward substitution's order).
    ahead_ptr: Vec<usize>,
    ahead: Vec<(u32, u32)>,
    /// Per column `i`, `(k, position of L_ki)` for the rows `k > i` where the factor
    /// can be non-zero, in increasing `k` (the back substitution's order).
    below_ptr: Vec<usize>,
    below: Vec<(u32, u32)>,
}

/// Entry `target` of the factor: its value minus `products[from..to]`, divided by the
/// pivot at `pivot`, or its square root on the diagonal (`pivot` = `None`).
#[derive(Debug, Clone, Copy)]
struct FactorStep {
    target: u32,
    from: u32,
    to: u32,
    pivot: Option<u32>,
}

/// First column of each row's envelope, and where each row starts in the packed
/// values (`m + 1` entries, the last the envelope's size), for `m` rows with entries
/// `(row, column)` of a lower triangle.
fn envelope_rows(m: usize, entries: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let mut first: Vec<usize> = (0..m).collect();
    for &(a, b) in entries {
        first[a] = first[a].min(b);
    }
    let mut start = vec![0];
    for (i, &f) in first.iter().enumerate() {
        start.push(start[i] + i - f + 1);
    }
    (first, start)
}

impl Envelope {
    /// The factor's layout for a lower triangle with entries `(row, column)`, `m` rows.
    fn new(m: usize, entries: &[(usize, usize)]) -> Self {
        let (first, start) = envelope_rows(m, entries);
        let at = |i: usize, j: usize| (start[i] + j - first[i]) as u32;
        // Which entries of the factor can be non-zero: those of S and their fill (L_ij
        // where some k < j has L_ik and L_jk). The rest of the envelope stays zero, and
        // products with a zero factor are skipped: subtracting them changes nothing.
        let mut nonzero = vec![false; start[m]];
        for &(a, b) in entries {
            nonzero[at(a, b) as usize] = true;
        }
        let mut steps = Vec::with_capacity(start[m]);
        let mut products = Vec::new();
        for i in 0..m {
            for j in first[i]..=i {
                let from = products.len() as u32;
                let shared = (first[i].max(first[j])..j)
                    .map(|k| (at(i, k), at(j, k)))
                    .filter(|&(x, y)| nonzero[x as usize] && nonzero[y as usize]);
                products.extend(shared);
                let target = at(i, j);
                if products.len() as u32 == from && !nonzero[target as usize] {
                    continue;
                }
                nonzero[target as usize] = true;
                let pivot = (j < i).then(|| at(j, j));
                steps.push(FactorStep { target, from, to: products.len() as u32, pivot });
            }
        }
        let is_nonzero = |i: usize, k: usize| first[i] <= k && nonzero[at(i, k) as usize];
        let (mut ahead_ptr, mut ahead) = (vec![0], Vec::new());
        let (mut below_ptr, mut below) = (vec![0], Vec::new());
        for i in 0..m {
            ahead.extend((0..i).filter(|&k| is_nonzero(i, k)).map(|k| (k as u32, at(i, k))));
            ahead_ptr.push(ahead.len());
            below.extend((i + 1..m).filter(|&k| is_nonzero(k, i)).map(|k| (k as u32, at(k, i))));
            below_ptr.push(below.len());
        }
        let position = entries.iter().map(|&(a, b)| at(a, b)).collect();
        let diagonal = (0..m).map(|i| at(i, i)).collect();
        let size = start[m];
        Envelope { size, position, diagonal, steps, products, ahead_ptr, ahead, below_ptr, below }
    }

    /// Cholesky factor of the packed symmetric matrix `a` (lower envelope) in place;
    /// `Singular` unless positive definite. Products are subtracted in index order.
    fn factor<T: Real>(&self, a: &mut [T]) -> Result<(), Singular> {
        for step in &self.steps {
            let products = &self.products[step.from as usize..step.to as usize];
            let target = step.target as usize;
            let s = products.iter().fold(a[target], |s, &(x, y)| s - a[x as usize] * a[y as usize]);
            a[target] = match step.pivot {
                Some(p) => s / a[p as usize],
                // `s != s`: NaN.
                #[allow(clippy::eq_op)]
                None if s != s || s <= 0.0 => return Err(Singular),
                None => s.sqrt(),
            };
        }
        Ok(())
    }

    /// Solves `L L^T x = b` in place with the packed factor `l`.
    fn solve<T: Real>(&self, l: &[T], x: &mut [T]) {
        let m = x.len();
        for i in 0..m {
            let ahead = &self.ahead[self.ahead_ptr[i]..self.ahead_ptr[i + 1]];
            // As `Iterator::sum` of f64, from -0.
            let s = ahead.iter().fold(T::constant(-0.0), |s, &(k, p)| s + l[p as usize] * x[k as usize]);
            x[i] = (x[i] - s) / l[self.diagonal[i] as usize];
        }
        for i in (0..m).rev() {
            let below = &self.below[self.below_ptr[i]..self.below_ptr[i + 1]];
            let s = below.iter().fold(x[i], |s, &(k, p)| s - l[p as usize] * x[k as usize]);
            x[i] = s / l[self.diagonal[i] as usize];
        }
    }
}

/// A factored `S + eps I`.
enum Factor<'a> {
    /// The envelope factor.
    Dense(&'a Envelope, &'a [f64]),
    /// faer's sparse factor.
    Sparse(LltRef<'a, usize, f64>),
}

impl Factor<'_> {
    fn solve_mut(&self, x: &mut [f64]) {
        match self {
            Factor::Dense(envelope, l) => envelope.solve(l, x),
            Factor::Sparse(llt) => {
                let n = x.len();
                let mut stack = MemBuffer::new(llt.symbolic().solve_in_place_scratch::<f64>(1, Par::Seq));
                llt.solve_in_place_with_conj(
                    Conj::No,
                    faer::MatMut::from_column_major_slice_mut(x, n, 1),
                    Par::Seq,
                    MemStack::new(&mut stack),
                );
            }
        }
    }
}

/// The pivots of a sparse Cholesky factor `values` of `S` (in its fill-reducing order),
/// `s_diagonal(k)` the diagonal entry of `S`'s row `k` (in the rows' order).
fn sparse_pivots(
    symbolic: &SymbolicCholesky<usize>,
    values: &[f64],
    s_diagonal: impl Fn(usize) -> f64,
) -> Pivots<f64> {
    let diagonal: Vec<f64> = match symbolic.raw() {
        // Each column's first stored entry is its diagonal.
        SymbolicCholeskyRaw::Simplicial(s) => s.col_ptr()[..s.nrows()].iter().map(|&p| values[p]).collect(),
        // Each supernode's columns start with their dense diagonal block.
        SymbolicCholeskyRaw::Supernodal(s) => {
            let factor = SupernodalLltRef::new(s, values);
            (0..s.n_supernodes())
                .flat_map(|k| {
                    let block = factor.supernode(k).val();
                    (0..block.ncols()).map(move |j| block[(j, j)])
                })
                .collect()
        }
    };
    // Pivot j is of the rows' row `forward[j]` (faer: permuted row j is row forward[j]).
    let row = |j: usize| symbolic.perm().map_or(j, |p| p.arrays().0[j]);
    Pivots::of(diagonal.iter().enumerate().map(|(j, &d)| (d * d, s_diagonal(row(j)))))
}

/// The spread of a Cholesky factor's squared pivots.
#[derive(Debug, Clone, Copy)]
struct Pivots<T> {
    /// The smallest and the largest.
    low: T,
    high: T,
    /// The smallest relative to its row's diagonal entry of `S`, `L_kk^2 / S_kk`: the
    /// sine squared of the angle between that row and the rows before it, in the metric
    /// of `M^-1`, whatever the rows' units.
    relative: T,
}

impl<T: Real> Pivots<T> {
    /// From each squared pivot and its row's diagonal entry of `S`.
    fn of(pivots: impl Iterator<Item = (T, T)>) -> Self {
        let (inf, zero) = (T::constant(f64::INFINITY), T::constant(0.0));
        pivots.fold(Pivots { low: inf, high: zero, relative: inf }, |p, (d, s)| Pivots {
            low: p.low.min(d),
            high: p.high.max(d),
            relative: p.relative.min(d / s),
        })
    }

    /// Whether the plain factor solves accurately enough: the smallest relative pivot is
    /// at least [`WELL_CONDITIONED`]. A Cholesky factor's accuracy is that of `S` with
    /// its diagonal scaled to one (van der Sluis 1969), so rows in metres and rows in
    /// radians, and light links beside heavy ones, count alike.
    fn well_conditioned(&self) -> bool {
        self.relative >= WELL_CONDITIONED
    }

    /// Whether `S` counts as rank deficient ([`RANK_LOSS`]).
    fn rank_deficient(&self) -> bool {
        self.low < self.high * RANK_LOSS
    }
}

impl<R: Block> Schur<R> {
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
        let envelope_size = envelope_rows(m, &entries).1[m];
        let factorisation = match factorisation {
            Factorisation::Auto if m <= DENSE_LIMIT || envelope_size <= ENVELOPE_LIMIT * entries.len() => {
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
                        shared.push(SharedBody { entry, packed: 0, a: 2 * a + side_a, b: 2 * b + side_b });
                    }
                }
            }
        }
        let pattern = SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx);
        let symbolic = match factorisation {
            Factorisation::Sparse => factorize_symbolic_cholesky(
                pattern.as_ref(),
                faer::Side::Lower,
                Default::default(),
                Default::default(),
            )
            .ok()
            .map(Arc::new),
            _ => None,
        };
        let sparse = vec![0.0; symbolic.as_ref().map_or(0, |s| s.len_val())];
        // Without a symbolic analysis (it failed), the dense path still solves.
        let factorisation = if symbolic.is_some() { Factorisation::Sparse } else { Factorisation::Dense };
        // The dense layout costs O(envelope x bandwidth) to build: only where it is used.
        let envelope = if factorisation == Factorisation::Dense {
            Envelope::new(m, &entries)
        } else {
            Envelope::default()
        };
        let dense_size = envelope.size;
        for s in shared.iter_mut().filter(|_| factorisation == Factorisation::Dense) {
            s.packed = envelope.position[s.entry];
        }
        let k = entries.len();
        Schur {
            entries,
            diagonal,
            envelope,
            shared,
            plain: vec![R::default(); 2 * m],
            scaled: vec![R::default(); 2 * m],
            values: vec![0.0; k],
            values_current: false,
            regularised: vec![0.0; k],
            factorisation,
            pattern,
            symbolic,
            sparse,
            dense: vec![0.0; dense_size],
            dense_diagonal: Vec::with_capacity(m),
            plain_factor: false,
            ill_conditioned: false,
            rank_deficient: false,
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

    /// Takes the rows' Jacobians and `M^-1` from which `S` is computed.
    pub fn update(&mut self, jac: &[RowJacobian<R>], m_inv: &[f64]) {
        self.plain_factor = false;
        self.values_current = false;
        for (a, row) in jac.iter().enumerate() {
            for (side, k) in row.bodies.iter().enumerate() {
                if k.is_some() {
                    let (e, w) = (row.entries[side], R::of(m_inv, row.at[side]));
                    self.plain[2 * a + side] = e;
                    self.scaled[2 * a + side] = e.scaled(w);
                }
            }
        }
    }

    /// `values` from the last update.
    fn compute_values(&mut self) {
        if self.values_current {
            return;
        }
        self.values.fill(0.0);
        for s in &self.shared {
            add_shared(&mut self.values[s.entry], &self.scaled[s.a], &self.plain[s.b]);
        }
        self.values_current = true;
    }

    /// Factors `S + shift I` into the dense buffer, summing `S` straight into it.
    fn factor_dense(&mut self, shift: f64) -> Result<(), Singular> {
        let mut dense = std::mem::take(&mut self.dense);
        let mut diagonal = std::mem::take(&mut self.dense_diagonal);
        let factored = self.factor_dense_into(&self.scaled, &self.plain, shift, &mut dense, &mut diagonal);
        self.dense_diagonal = diagonal;
        self.dense = dense;
        factored
    }

    /// Factors `S + shift I` of the rows' Jacobian blocks `plain` and their products with
    /// `M^-1`, `scaled` (two per row), into `dense`, in any number type, its diagonal
    /// kept in `diagonal`.
    fn factor_dense_into<T: Real, B: AsRef<[T]>>(
        &self,
        scaled: &[B],
        plain: &[B],
        shift: f64,
        dense: &mut [T],
        diagonal: &mut Vec<T>,
    ) -> Result<(), Singular> {
        dense.fill(T::constant(0.0));
        for s in &self.shared {
            add_shared(&mut dense[s.packed as usize], &scaled[s.a], &plain[s.b]);
        }
        for &d in &self.envelope.diagonal {
            dense[d as usize] += T::constant(shift);
        }
        diagonal.clear();
        diagonal.extend(self.envelope.diagonal.iter().map(|&d| dense[d as usize]));
        self.envelope.factor(dense)
    }

    /// Solves `S x = rhs` in place by the plain factor of `S`, in any number type, where
    /// `S` is factored over its envelope and well conditioned, as [`Schur::solve`] does
    /// there; `None` elsewhere (the regularised solve is then [`Schur::solve`]'s). `jac`
    /// holds each row's two blocks (the ground's side too, unused), `m_inv` the inverse
    /// mass; `rows` the rows' bodies and places, as [`Schur::update`] takes them.
    pub(super) fn solve_plain<T: Real, const N: usize>(
        &self,
        rows: &[RowJacobian<R>],
        jac: &[[[T; N]; 2]],
        m_inv: &[f64],
        rhs: &mut [T],
    ) -> Option<Result<(), Singular>> {
        if self.factorisation == Factorisation::Sparse {
            return None;
        }
        let zero = [T::constant(0.0); N];
        let (mut plain, mut scaled) = (vec![zero; 2 * jac.len()], vec![zero; 2 * jac.len()]);
        for (a, (entries, row)) in jac.iter().zip(rows).enumerate() {
            for side in (0..2).filter(|&side| row.bodies[side].is_some()) {
                let w = &m_inv[row.at[side]..row.at[side] + N];
                plain[2 * a + side] = entries[side];
                scaled[2 * a + side] = std::array::from_fn(|d| entries[side][d] * w[d]);
            }
        }
        let mut dense = vec![T::constant(0.0); self.envelope.size];
        let mut diagonal = Vec::with_capacity(jac.len());
        self.factor_dense_into(&scaled, &plain, 0.0, &mut dense, &mut diagonal).ok()?;
        if !dense_pivots(&self.envelope, &dense, &diagonal).well_conditioned() {
            return None;
        }
        self.envelope.solve(&dense, rhs);
        Some(if rhs.iter().all(|x| x.abs() < f64::INFINITY) { Ok(()) } else { Err(Singular) })
    }

    /// Factors `S + shift I` with faer's sparse Cholesky into `sparse` (the values of `S`
    /// must be current).
    fn factor_sparse(&mut self, shift: f64) -> Result<(), Singular> {
        self.regularised.copy_from_slice(&self.values);
        for &d in &self.diagonal {
            self.regularised[d] += shift;
        }
        let symbolic = self.symbolic.as_deref().ok_or(Singular)?;
        let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.regularised);
        let mut stack =
            MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut self.sparse,
                matrix,
                faer::Side::Lower,
                LltRegularization { dynamic_regularization_delta: 0.0, dynamic_regularization_epsilon: 0.0 },
                Par::Seq,
                MemStack::new(&mut stack),
                Default::default(),
            )
            .map_err(|_| Singular)?;
        Ok(())
    }

    /// Factors `S + shift I` by the chosen factorisation and returns the factor.
    fn factor(&mut self, shift: f64) -> Result<Factor<'_>, Singular> {
        match self.factorisation {
            // `Auto` is resolved when the pattern is built.
            Factorisation::Dense | Factorisation::Auto => {
                self.factor_dense(shift)?;
                Ok(Factor::Dense(&self.envelope, &self.dense))
            }
            Factorisation::Sparse => {
                self.compute_values();
                self.factor_sparse(shift)?;
                self.factored()
            }
        }
    }

    /// The factor last computed.
    fn factored(&self) -> Result<Factor<'_>, Singular> {
        Ok(match self.factorisation {
            Factorisation::Dense | Factorisation::Auto => Factor::Dense(&self.envelope, &self.dense),
            Factorisation::Sparse => {
                Factor::Sparse(LltRef::new(self.symbolic.as_deref().ok_or(Singular)?, &self.sparse))
            }
        })
    }

    /// The pivots of the plain factor last computed.
    fn pivots(&self) -> Pivots<f64> {
        match (self.factorisation, self.symbolic.as_deref()) {
            (Factorisation::Sparse, Some(symbolic)) => {
                sparse_pivots(symbolic, &self.sparse, |k| self.regularised[self.diagonal[k]])
            }
            _ => dense_pivots(&self.envelope, &self.dense, &self.dense_diagonal),
        }
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
    /// `S + eps I` is factored and the solution refined against `S` (iterated Tikhonov
    /// regularisation): where `S` is well conditioned this is the solution of `S x = rhs`.
    /// Where `S` loses rank (a parallelogram with all bars collinear: its loop rows
    /// become dependent for an instant) the shift is raised to [`RANK_LOSS_SHIFT`]: each
    /// eigen-direction of `S` with eigenvalue `s` is then solved with the weight
    /// `1 - (eps / (s + eps))^4`, exactly for `s >> eps` and released smoothly for
    /// `s << eps`, so the multipliers stay bounded, their part along the lost rank is
    /// not imposed, and the mechanism moves through the singular position as its forces
    /// take it. With a consistent right-hand side the result is the minimum-norm
    /// solution. This is the dual form of the augmented Lagrangian method (Bayo and
    /// Ledesma 1996); docs/formulation.md gives the thresholds and what the multipliers
    /// mean there.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), Singular> {
        // Away from singular positions (nearly always) a plain factor is exact enough and
        // needs no refinement: its smallest pivot shows the conditioning. Both
        // factorisations read it the same way (the sparse one in its own ordering), so a
        // large mechanism enters and leaves the rank-loss treatment as a small one does.
        let mut rank_deficient = true;
        if self.factor(0.0).is_ok() {
            let pivots = self.pivots();
            if pivots.well_conditioned() {
                self.plain_factor = true;
                self.ill_conditioned = false;
                self.rank_deficient = false;
                self.factored()?.solve_mut(rhs);
                return if rhs.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(Singular) };
            }
            rank_deficient = pivots.rank_deficient();
        }
        self.plain_factor = false;
        self.ill_conditioned = true;
        self.compute_values();
        self.target.copy_from_slice(rhs);
        if !self.solve_regularised(rhs, rank_deficient)? && !rank_deficient {
            // Pivots above the rank-loss threshold, but the refinement cannot meet the
            // equations: treat the rank as lost.
            rhs.copy_from_slice(&self.target);
            rank_deficient = true;
            self.solve_regularised(rhs, rank_deficient)?;
        }
        self.rank_deficient = rank_deficient;
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }

    /// Whether the last [`Schur::solve`] found `S` ill-conditioned (a squared pivot of
    /// its plain factor below [`WELL_CONDITIONED`] of its row's diagonal entry): the
    /// mechanism is near a singular position, where the projection takes its residual
    /// down further ([`super::project`]).
    pub fn ill_conditioned(&self) -> bool {
        self.ill_conditioned
    }

    /// Records that the equations were solved by compiled code with the plain factor of
    /// a well-conditioned `S` ([`Schur::solve_plain`]): what [`Schur::solve`] leaves
    /// there, but that its buffers do not hold that factor.
    pub(super) fn solved_elsewhere(&mut self) {
        self.plain_factor = false;
        self.values_current = false;
        self.ill_conditioned = false;
        self.rank_deficient = false;
    }

    /// Whether the last [`Schur::solve`] treated `S` as rank deficient.
    pub fn rank_deficient(&self) -> bool {
        self.rank_deficient
    }

    /// Solves `S x = rhs` (`rhs` is `target` on entry) by the factor of `S + eps I` and
    /// refinement against `S`, with `eps` for rank loss or not; `Ok(false)` when the
    /// refinement leaves a residual above 1e-6 of the right-hand side (and above 1e-12):
    /// the equations are not consistent at full rank.
    fn solve_regularised(&mut self, rhs: &mut [f64], rank_deficient: bool) -> Result<bool, Singular> {
        let m = rhs.len();
        let scale = self.diagonal.iter().map(|&d| self.values[d]).fold(0.0, f64::max);
        let shift = if rank_deficient { RANK_LOSS_SHIFT } else { REGULARISATION } * scale;
        self.factor(shift)?;
        let mut residual = std::mem::take(&mut self.residual);
        let factor = self.factored()?;
        factor.solve_mut(rhs);
        let target_max = self.target.iter().fold(0.0, |acc: f64, x| acc.max(x.abs()));
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
        Ok(worst <= 1e-6 * target_max.max(1e-300) || worst <= 1e-12)
    }
}

impl<R: Block> Schur<R> {
    /// Solves `S x = rhs` in place for another right-hand side with the same values:
    /// with the factor already in hand where the last [`Schur::solve`] used the plain
    /// dense one, else as [`Schur::solve`].
    pub fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), Singular> {
        if !self.plain_factor {
            return self.solve(rhs);
        }
        self.factored()?.solve_mut(rhs);
        if rhs.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Singular)
        }
    }
}

/// Adds one shared body's part of an entry of `S`, `(Cq_a,d / m_d) Cq_b,d`, to `value`
/// term by term in the order `d` = x, y, angle, as every path of the factor sums it.
#[inline]
fn add_shared<T: Real, B: AsRef<[T]>>(value: &mut T, scaled: &B, plain: &B) {
    for (s, p) in scaled.as_ref().iter().zip(plain.as_ref()) {
        *value += *s * *p;
    }
}

/// The pivots of the envelope factor `l` of a matrix of diagonal `diagonal`.
fn dense_pivots<T: Real>(envelope: &Envelope, l: &[T], diagonal: &[T]) -> Pivots<T> {
    Pivots::of(envelope.diagonal.iter().zip(diagonal).map(|(&d, &s)| (l[d as usize] * l[d as usize], s)))
}

/// Relative diagonal shift of the Schur complement (see [`Schur::solve`]).
const REGULARISATION: f64 = 1e-12;
/// Smallest ratio of squared Cholesky pivots above which `S` counts as of full rank;
/// below it (or where the plain factor fails) `S` is rank deficient.
const RANK_LOSS: f64 = 1e-8;
/// Relative diagonal shift where `S` is rank deficient: eigen-directions of `S` below
/// about this fraction of its largest diagonal entry are released, those well above it
/// kept exactly. Measured on the two-loop parallelogram chain (benchmark A02, N = 2),
/// 10 s through 10 singular positions, dopri5 and radau5 at rtol 1e-10 and 1e-12,
/// largest error of the rocker angle: 3e-2 rad with 1e-12 (the state turns towards the
/// other branch), 4e-10 to 7e-9 rad with 1e-9, up to 3e-5 rad with 1e-8 (the constraint
/// force is released over too long a stretch).
const RANK_LOSS_SHIFT: f64 = 1e-9;
/// Smallest squared Cholesky pivot, relative to its row's diagonal entry of `S`, at
/// which the plain factor is used without regularisation and refinement: no row is then
/// within 1e-2 rad of the others' span, the condition number of `S` scaled to a unit
/// diagonal is of the order of 1e4 or less, and the plain solve is accurate to about
/// 1e-12, below any tolerance.
const WELL_CONDITIONED: f64 = 1e-4;
/// Iterative-refinement sweeps of the regularised solve.
const REFINEMENTS: usize = 3;
