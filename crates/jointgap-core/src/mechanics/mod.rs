//! The mechanism's element kinds, each built from its model entry (points resolved by
//! `resolve::Resolver`) and evaluated as a pure function of the bodies' states: the
//! vocabulary the compiled system is written in. Nothing here knows how elements are
//! indexed in a mechanism or how its equations are solved.

pub mod contact;
pub mod drivers;
pub mod forces;
pub mod kind;
pub mod layout;
pub mod planar;
pub mod planar_body;
pub(crate) mod resolve;
pub mod spatial;
