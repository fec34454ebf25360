//! Generic methods for first-order ODEs `y' = f(t, y)` with `y = (q, v)` and
//! `f = (G(q) v, a)`: the right-hand side they step ([`ode::Rhs`]), the error norm and
//! dense output they share, and the three methods' inner steps behind one
//! [`stepper::Stepper`] trait.
//! They know nothing of mechanics: the equations of motion reach them through
//! [`ode::Rhs`], implemented by the simulation loop's `Ode`.

pub mod dopri5;
pub mod jacobian;
pub mod ode;
pub mod radau5;
#[cfg(test)]
mod rotor;
pub mod sdirk4;
pub mod stepper;
