//! Contact geometries: where a clearance joint's two parts touch, as contact points
//! ([`super::point`]), apart from the laws that turn a point into forces. Each kernel is
//! named after its operands, as parry's `contact_ball_ball`: `contact_journal_bearing`
//! for a round journal in a round bearing. A kernel writes its points into the caller's
//! list ([`super::ContactPoints`]) and returns every point nearer than `reach` (the
//! laws' reach, [`super::ClearanceRevolute::reach`]: zero for a contact law, infinite
//! for whoever needs the gap itself, such as event location and the output), so a law
//! that acts apart (a fluid film) still gets its point.

mod ball_socket;
mod block_channel;
mod cylinder_bearing;
mod cylinder_section;
mod journal_bearing;
mod slider_guide;
#[cfg(test)]
mod spatial_checks;
pub mod worn;

pub use ball_socket::{contact_ball_socket, BallSocket};
pub use block_channel::{contact_block_channel, wall_contact, BlockChannel, Frames, Pose, CORNERS3};
pub use cylinder_bearing::{
    contact_cylinder_bearing, contact_round_cylinder, contact_worn_cylinder, radial_normal, search_cylinder,
    CylinderBearing,
};
pub use cylinder_section::{section_basis, Section};
pub use journal_bearing::{contact_journal_bearing, JournalBearing};
pub use slider_guide::{contact_slider_guide, corner_contact, SliderGuide, CORNERS};
pub use worn::{contact_worn, contact_worn_from, read_found, search_worn, write_found, Found, Worn, FOUND};
