//! Forward-difference Jacobian `df/dy` of a right-hand side, shared by the
//! implicit methods (SDIRK4, Radau IIA).

use nalgebra::DMatrix;

use super::ode::{Rhs, Singular};

/// Fills `jac` ((n - first) x n, n = `y.len()`) with rows `first..n` of
/// `(f(t, y + d_j e_j) - f0) / d_j`, one force evaluation per column, increment
/// `d_j = sqrt(eps) max(|y_j|, 1e-5)`; `f0 = f(t, y)`. `first = nq` skips the rows of
/// `q' = G(q) v`, which a method then takes as `[0 G]` ([`Rhs::rate_jacobian`]: `[0 I]`
/// exactly for `q' = v`); `first = 0` gives all rows, `d(G(q) v)/d(q)` included. `work`
/// is scratch of length n.
pub fn forward_difference<R: Rhs + ?Sized>(
    ode: &mut R,
    t: f64,
    y: &[f64],
    f0: &[f64],
    first: usize,
    jac: &mut DMatrix<f64>,
    work: &mut [f64],
) -> Result<(), Singular> {
    let n = y.len();
    let mut yp = y.to_vec();
    for j in 0..n {
        let dy = f64::EPSILON.sqrt() * y[j].abs().max(1e-5);
        yp[j] = y[j] + dy;
        ode.eval(t, &yp, work)?;
        yp[j] = y[j];
        for i in first..n {
            jac[(i - first, j)] = (work[i] - f0[i]) / dy;
        }
    }
    Ok(())
}
