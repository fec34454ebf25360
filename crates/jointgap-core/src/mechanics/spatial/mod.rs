//! The spatial body kind and the spatial elements: rigid bodies whose orientation is a
//! unit quaternion (Euler parameters), the constraint rows of spatial joints, written
//! with the body's angular velocity in its own frame as the velocity coordinate
//! (Nikravesh 1988, chapter 6 and 11; docs/spatial.md).

pub mod body;
pub mod forces;
pub mod inertia;
pub mod joints;
pub mod kind;
pub mod orientation;
