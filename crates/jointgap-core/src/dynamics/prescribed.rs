//! Bodies whose motion their joints and drivers alone fix: a crank pinned to the ground
//! and driven, a slider driven along a guide, each link of an arm whose every joint is
//! driven. Their three rows touch only the body and bodies already fixed (or the ground),
//! so the augmented system is block triangular: such a body's acceleration follows from
//! its rows, `B a_p = gamma_p - (earlier fixed bodies' terms)` with `B` its 3x3 block of
//! the Jacobian, whatever the forces; the other bodies then see it as a moving support,
//! and its rows' multipliers (the driving torque, the pin reaction) follow from its
//! Newton-Euler equations. The Schur complement keeps only the remaining rows: on the
//! founding slider-crank 4 of 7.

use super::schur::{RowJacobian, Singular};
use crate::mechanics::kind::{Block, BodyKind};
use crate::mechanics::planar_body::{BodyRow, NV, PLANAR_BODY};
use crate::scalar::Real;
use crate::system::System;

/// A square block over one body's velocities: `B` of its own rows, and its inverse.
pub type BodyBlock = [BodyRow; NV];

/// A body fixed by its own rows, as many as its velocities.
#[derive(Debug, Clone)]
pub struct PrescribedBody {
    /// Body index.
    pub body: usize,
    /// Its velocities' place in `v` (and in `qe`, `qdd`).
    pub own: std::ops::Range<usize>,
    /// Positions of its own rows in the solve order, and the body's side in each.
    pub rows: [(usize, usize); NV],
    /// Every other row touching it, with the body's side: their forces on it enter its
    /// Newton-Euler equations.
    pub others: Vec<(usize, usize)>,
}

/// Active rows in solve order: the rows of the Schur complement first, then each
/// prescribed body's own three, bodies in the order their accelerations are found.
#[derive(Debug, Clone)]
pub struct Split {
    /// Row indices (into `System::rows`) in solve order.
    pub order: Vec<usize>,
    /// Number of leading rows that enter the Schur complement.
    pub dynamic: usize,
    /// Prescribed bodies, each after the bodies its rows refer to.
    pub bodies: Vec<PrescribedBody>,
}

/// Finds the prescribed bodies among the active rows `active` (model order kept within
/// each group). A body is prescribed when exactly three active rows touch it and only
/// the ground or bodies found before; assembly has already dropped dependent rows, so
/// the three are independent. The block solve is written for a planar body's three
/// rows: a spatial body's six go through the Schur complement.
pub fn split<K: BodyKind>(sys: &System<K>, active: &[usize]) -> Split {
    let n = if K::SHAPE == PLANAR_BODY { sys.bodies.len() } else { 0 };
    let mut fixed = vec![false; n];
    let mut taken = vec![false; active.len()];
    let mut groups: Vec<(usize, [usize; NV])> = Vec::new();
    let bodies_of = |a: usize| [sys.rows[active[a]].body_i, sys.rows[active[a]].body_j];
    loop {
        let mut found = false;
        for k in 0..n {
            if fixed[k] {
                continue;
            }
            let own: Vec<usize> = (0..active.len())
                .filter(|&a| !taken[a])
                .filter(|&a| {
                    let b = bodies_of(a);
                    b.contains(&Some(k)) && b.iter().all(|o| o.is_none_or(|o| o == k || fixed[o]))
                })
                .collect();
            if let Ok(rows) = <[usize; NV]>::try_from(own) {
                fixed[k] = true;
                rows.iter().for_each(|&r| taken[r] = true);
                groups.push((k, rows));
                found = true;
            }
        }
        if !found {
            break;
        }
    }
    let mut order: Vec<usize> = (0..active.len()).filter(|&a| !taken[a]).collect();
    let dynamic = order.len();
    let mut position = vec![0; active.len()];
    for &(_, rows) in &groups {
        order.extend(rows);
    }
    for (p, &a) in order.iter().enumerate() {
        position[a] = p;
    }
    let side = |a: usize, k: usize| usize::from(bodies_of(a)[0] != Some(k));
    let bodies = groups
        .iter()
        .map(|&(k, rows)| PrescribedBody {
            body: k,
            own: sys.layout.slot(k).v(),
            rows: rows.map(|a| (position[a], side(a, k))),
            others: (0..active.len())
                .filter(|a| !rows.contains(a) && bodies_of(*a).contains(&Some(k)))
                .map(|a| (position[a], side(a, k)))
                .collect(),
        })
        .collect();
    Split { order: order.iter().map(|&a| active[a]).collect(), dynamic, bodies }
}

impl PrescribedBody {
    /// `B^-1`, with `B` its own rows' entries for its coordinates (one row per
    /// equation); `Singular` where `B` is.
    pub fn inverse<R: Block>(&self, jac: &[RowJacobian<R>]) -> Result<BodyBlock, Singular> {
        self.inverse_of(|a, side| planar_row(&jac[a].entries[side]))
    }

    /// [`Self::inverse`] in any number type, `entries(a, side)` the block of row `a` on
    /// its side `side`.
    pub fn inverse_of<T: Real>(
        &self,
        entries: impl Fn(usize, usize) -> [T; NV],
    ) -> Result<[[T; NV]; NV], Singular> {
        inverse3(self.rows.map(|(a, side)| entries(a, side)))
    }

    /// Sets its coordinates' part of `x` so that its own rows give `rhs`:
    /// `x_p = B^-1 (rhs_p - the rows' terms in every other coordinate of x)`. Callers set
    /// the bodies in order, so the earlier ones are in place.
    pub fn solve_rows<R: Block>(
        &self,
        jac: &[RowJacobian<R>],
        b_inv: &BodyBlock,
        rhs: impl Fn(usize) -> f64,
        x: &mut [f64],
    ) {
        self.solve_rows_of(|a, x| jac[a].dot(x), b_inv, rhs, x);
    }

    /// [`Self::solve_rows`] in any number type, `dot(a, x)` row `a`'s `Cq_a x`.
    pub fn solve_rows_of<T: Real>(
        &self,
        dot: impl Fn(usize, &[T]) -> T,
        b_inv: &[[T; NV]; NV],
        rhs: impl Fn(usize) -> T,
        x: &mut [T],
    ) {
        x[self.own.clone()].fill(T::constant(0.0));
        let r = self.rows.map(|(a, _)| rhs(a) - dot(a, x));
        for (x, b) in x[self.own.clone()].iter_mut().zip(b_inv) {
            *x = b[0] * r[0] + b[1] * r[1] + b[2] * r[2];
        }
    }

    /// Multipliers of its own rows from its Newton-Euler equations
    /// `M_p qdd_p + Cq_p^T lambda = Qe_p`, given the other rows' multipliers:
    /// `lambda_own = B^-T (Qe_p - M_p qdd_p - others' Cq_p^T lambda)`.
    pub fn multipliers<R: Block>(
        &self,
        jac: &[RowJacobian<R>],
        b_inv: &BodyBlock,
        mass: &R,
        qe: &[f64],
        qdd: &[f64],
        lambda: &mut [f64],
    ) {
        let (qe, qdd) = (&qe[self.own.clone()], &qdd[self.own.clone()]);
        let mass = planar_row(mass);
        let mut r: BodyRow = std::array::from_fn(|d| qe[d] - mass[d] * qdd[d]);
        for &(a, side) in &self.others {
            for (r, e) in r.iter_mut().zip(jac[a].entries[side].as_ref()) {
                *r -= e * lambda[a];
            }
        }
        for (i, &(a, _)) in self.rows.iter().enumerate() {
            lambda[a] = b_inv[0][i] * r[0] + b_inv[1][i] * r[1] + b_inv[2][i] * r[2];
        }
    }
}

/// A planar body's block: only planar bodies are prescribed ([`split`]).
#[inline(always)]
fn planar_row<R: Block>(r: &R) -> BodyRow {
    *<&BodyRow>::try_from(r.as_ref()).expect("prescribed bodies are planar")
}

/// Inverse of a 3x3 matrix by its cofactors; `Singular` when the determinant vanishes
/// against the entries' scale.
#[inline(always)]
fn inverse3<T: Real>(a: [[T; NV]; NV]) -> Result<[[T; NV]; NV], Singular> {
    // Written out: the compiler does not always unroll index arithmetic here (measured:
    // 2.4x the instructions when it did not).
    let cof = |[r0, r1]: [usize; 2], [c0, c1]: [usize; 2]| a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0];
    let (n0, n1, n2) = ([1, 2], [2, 0], [0, 1]);
    let c = [
        [cof(n0, n0), cof(n0, n1), cof(n0, n2)],
        [cof(n1, n0), cof(n1, n1), cof(n1, n2)],
        [cof(n2, n0), cof(n2, n1), cof(n2, n2)],
    ];
    let det = a[0][0] * c[0][0] + a[0][1] * c[0][1] + a[0][2] * c[0][2];
    let scale = a.iter().flatten().fold(T::constant(0.0), |m, x| m.max(x.abs()));
    // Also catches a NaN determinant (`det != det`).
    #[allow(clippy::eq_op)]
    if det != det || det.abs() <= scale * scale * scale * 1e-12 {
        return Err(Singular);
    }
    // The inverse is the transposed cofactor matrix over the determinant.
    Ok([
        [c[0][0] / det, c[1][0] / det, c[2][0] / det],
        [c[0][1] / det, c[1][1] / det, c[2][1] / det],
        [c[0][2] / det, c[1][2] / det, c[2][2] / det],
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse3_times_the_matrix_is_the_identity() {
        let a = [[0.0, 2.0, 1.0], [1.0, -1.0, 0.5], [3.0, 0.0, -2.0]];
        let inv = inverse3(a).unwrap();
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| a[i][k] * inv[k][j]).sum();
                assert!((p - f64::from(u8::from(i == j))).abs() < 1e-14, "({i}, {j}): {p}");
            }
        }
        assert!(inverse3([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]).is_err());
    }
}
