//! The number type the mechanics is written over. The kernels that one evaluation runs
//! (body kinematics, constraint rows, contact geometry, force and contact laws) take any
//! [`Real`]: `f64` for the interpreted engine, and [`Traced`], which records the
//! evaluation as a graph that [`crate::codegen`] compiles to native code and that
//! [`Graph::jacobian`] differentiates (docs/compiled.md).
//!
//! A kernel written over `Real` performs, on `f64`, exactly the operations it performed
//! before it was generic, in the same order: the compiled code repeats them operation for
//! operation, so both paths give the same bits.

mod derivative;
mod traced;

pub use derivative::Sweep;
#[cfg(test)]
pub(crate) use traced::tests as traced_tests;
pub use traced::{record, Block, Cmp, Func, Graph, Guard, Implicit, Node, Traced};

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use nalgebra::SVector;

/// A real number the mechanics can be evaluated with.
///
/// Constants of the model (lengths, masses, law parameters) stay `f64`; the operators
/// with an `f64` on the right take them. An `f64` on the left is written
/// [`Real::constant`]`(x) - y`, so that the operation is the one the `f64` code does
/// (`-(y - x)` would differ in the sign of a zero).
pub trait Real:
    nalgebra::Scalar
    + Copy
    + Debug
    + num_traits::Zero
    + num_traits::One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + PartialOrd
    + PartialOrd<f64>
    + PartialEq<f64>
{
    /// A constant of the model.
    fn constant(x: f64) -> Self;
    /// The value it holds now.
    fn value(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine and cosine.
    fn sin_cos(self) -> (Self, Self);
    /// `self^n`.
    fn powf(self, n: Self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// `1` or `-1` by the sign, as `f64::signum`.
    fn signum(self) -> Self;
    /// The larger, as `f64::max`.
    fn max(self, other: Self) -> Self;
    /// The smaller, as `f64::min`.
    fn min(self, other: Self) -> Self;
    /// Hyperbolic tangent.
    fn tanh(self) -> Self;
    /// Hyperbolic cosine.
    fn cosh(self) -> Self;
    /// The angle of the point `(x, self)`, as `f64::atan2`.
    fn atan2(self, x: Self) -> Self;
    /// The remainder in `[0, |m|)`, as `f64::rem_euclid`.
    fn rem_euclid(self, m: Self) -> Self;
    /// `f` at `(self, y)`: a function computed by a method of its own ([`Implicit`]).
    fn implicit(self, y: Self, f: &'static Implicit) -> Self;
    /// `f(values)`, a part of the evaluation with branches of its own (a clearance
    /// joint's contact): [`Traced`] records it as a block, whose ways through its
    /// branches add to the evaluation's instead of multiplying them.
    #[inline(always)]
    fn block(values: &[Self], f: impl FnOnce(&[Self]) -> Option<Vec<Self>>) -> Option<Vec<Self>> {
        f(values)
    }
}

impl Real for f64 {
    #[inline(always)]
    fn constant(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn value(self) -> f64 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    #[inline(always)]
    fn powf(self, n: Self) -> Self {
        f64::powf(self, n)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn signum(self) -> Self {
        f64::signum(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline(always)]
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
    #[inline(always)]
    fn cosh(self) -> Self {
        f64::cosh(self)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline(always)]
    fn rem_euclid(self, m: Self) -> Self {
        f64::rem_euclid(self, m)
    }
    #[inline(always)]
    fn implicit(self, y: Self, f: &'static Implicit) -> Self {
        (f.value)(self, y)
    }
}

/// The constant `x` as a `T`.
#[inline(always)]
pub fn c<T: Real>(x: f64) -> T {
    T::constant(x)
}

/// Euclidean norm `sqrt(v . v)`: for `f64` the bits of nalgebra's `norm()`, whose sum of
/// squares starts from a zero that adds nothing to a sum that is not negative.
#[inline(always)]
pub fn norm<T: Real, const N: usize>(v: &SVector<T, N>) -> T {
    v.dot(v).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// The generic norm gives nalgebra's bits on `f64`, zero and signed components too.
    #[test]
    fn norm_is_nalgebras() {
        for (x, y) in [(3e-3, -4e-7), (0.0, -0.0), (1e-160, 1e-170), (-2.5, 7.25), (1e150, 3e150)] {
            let v = Vector2::new(x, y);
            assert_eq!(norm(&v).to_bits(), v.norm().to_bits(), "({x}, {y})");
        }
    }
}
