//! The translational clearance joint: a slider block (body j) in a guide (body i) with
//! lateral play, touching at its corners (docs/translational-clearance.md).

use super::geometry::{contact_slider_guide, corner_contact, SliderGuide};
use super::normal::NormalForce;
use super::point::{ContactPoint, ContactPoints, Tangential};
use super::{
    apply_point_forces, dry_force, friction, ClearanceJoint, ContactState, MAX_INITIAL_CONTACT_FORCE,
};
use crate::error::{Error, Named};
use crate::math::{rotate, Vec2};
use crate::mechanics::layout::Loads;
use crate::mechanics::planar_body::BodyState;
use crate::model::{Clearance, FrictionSpec, Joint};
use crate::output::ClearanceData;
use crate::scalar::Real;

/// A checked translational clearance joint: the block in its guide and the laws at each
/// corner.
#[derive(Debug, Clone)]
pub struct ClearanceTranslational {
    /// Joint name.
    pub name: String,
    /// The block, the guide and their sizes.
    pub geometry: SliderGuide,
    /// Normal law with its stiffness, at each corner.
    pub normal: NormalForce,
    /// Friction law (checked).
    pub friction: FrictionSpec,
}

/// A translational clearance joint's checked sizes and laws, planar or spatial.
#[derive(Debug, Clone)]
pub(crate) struct BlockData {
    /// The block's length along the guide [m].
    pub length: f64,
    /// The block's height and the guide's width across it [m].
    pub height: (f64, f64),
    /// The block's depth and the channel's across it [m] (spatial only).
    pub depth: Option<(f64, f64)>,
    /// The normal law at each contact point.
    pub normal: NormalForce,
    /// The friction law (checked).
    pub friction: FrictionSpec,
}

impl BlockData {
    /// Checks joint `name`'s contact data `c`: the depth's keys in space only
    /// (`spatial`). Errors name the joint and the key.
    pub(crate) fn new(name: &str, c: &Clearance, spatial: bool) -> Result<Self, Error> {
        let who = Named::joint(name);
        for (key, given) in [
            ("bearing_radius", c.bearing_radius.is_some()),
            ("journal_radius", c.journal_radius.is_some()),
            ("bearing_material", c.bearing_material.is_some()),
            ("journal_material", c.journal_material.is_some()),
            ("length", c.length.is_some()),
            ("bearing_wear", c.bearing_wear.is_some()),
            ("journal_wear", c.journal_wear.is_some()),
        ] {
            if given {
                return Err(who.error(
                    key,
                    format!(
                        "'{key}' belongs to a revolute clearance joint; a translational one takes \
                         block_length, block_height, guide_width or clearance, and a stiffness \
                         (a block's corner on a flat has no closed-form Hertz stiffness)"
                    ),
                ));
            }
        }
        if !spatial {
            for (key, given) in [
                ("block_depth", c.block_depth.is_some()),
                ("guide_depth", c.guide_depth.is_some()),
                ("depth_clearance", c.depth_clearance.is_some()),
            ] {
                if given {
                    return Err(who.error(
                        key,
                        format!(
                            "'{key}' belongs to a spatial block in its channel; a planar block has no depth"
                        ),
                    ));
                }
            }
        }
        let length = positive(who, "block_length", c.block_length)?.ok_or_else(|| {
            who.error("block_length", "a translational clearance joint needs block_length".into())
        })?;
        let height = fit(
            who,
            ["block_height", "guide_width", "clearance"],
            [c.block_height, c.guide_width, c.clearance],
        )?;
        let depth = if spatial {
            Some(fit(
                who,
                ["block_depth", "guide_depth", "depth_clearance"],
                [c.block_depth, c.guide_depth, c.depth_clearance],
            )?)
        } else {
            None
        };
        let stiffness = match c.stiffness {
            Some(k) if k.is_finite() && k > 0.0 => k,
            Some(k) => return Err(who.error("stiffness", format!("stiffness = {k} must be positive"))),
            None => {
                return Err(who.error("stiffness", "a translational clearance joint needs a stiffness".into()))
            }
        };
        friction::check(name, &c.friction)?;
        Ok(BlockData {
            length,
            height,
            depth,
            normal: NormalForce::new(name, &c.normal_law, stiffness, None)?,
            friction: c.friction.clone(),
        })
    }
}

/// `v` when it is absent or positive; an error naming `key` otherwise.
fn positive(who: Named, key: &str, v: Option<f64>) -> Result<Option<f64>, Error> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => {
            Err(who.error(key, format!("{key} = {x} m must be positive")))
        }
        _ => Ok(v),
    }
}

/// The block's size and the guide's across one direction from two (or three agreeing)
/// of the block's size, the guide's and the clearance `guide - block` (keys in that
/// order); the block must fit.
fn fit(who: Named, keys: [&str; 3], values: [Option<f64>; 3]) -> Result<(f64, f64), Error> {
    let [block_key, guide_key, clearance_key] = keys;
    let (block, guide) = match (
        positive(who, block_key, values[0])?,
        positive(who, guide_key, values[1])?,
        positive(who, clearance_key, values[2])?,
    ) {
        (Some(h), Some(w), None) => (h, w),
        (Some(h), None, Some(c)) => (h, h + c),
        (None, Some(w), Some(c)) => (w - c, w),
        (Some(h), Some(w), Some(c)) => {
            if ((w - h) - c).abs() > 1e-9 * w {
                return Err(who.error(
                    clearance_key,
                    format!("{guide_key} - {block_key} = {} m contradicts {clearance_key} = {c} m", w - h),
                ));
            }
            (h, w)
        }
        _ => {
            return Err(
                who.error_of_element(format!("give two of {block_key}, {guide_key} and {clearance_key}"))
            );
        }
    };
    if block >= guide {
        return Err(who.error(
            block_key,
            format!(
                "{block_key} = {block} m does not fit the guide: it must be smaller than \
                 {guide_key} = {guide} m (the clearance is {guide_key} - {block_key})"
            ),
        ));
    }
    Ok((block, guide))
}

impl ClearanceTranslational {
    /// Checks joint `j`'s contact data `c`, the guide on body `guide` along `axis` (unit,
    /// its frame), the block on body `block`, whose long axis is the guide's at the
    /// model's placement, `rel_angle` the block body's angle less the guide body's there.
    /// Errors name the joint and the key.
    pub(crate) fn new(
        j: &Joint,
        c: &Clearance,
        (guide, s_guide, axis): (Option<usize>, Vec2, Vec2),
        (block, s_block): (Option<usize>, Vec2),
        rel_angle: f64,
    ) -> Result<Self, Error> {
        let data = BlockData::new(&j.name, c, false)?;
        let (height, width) = data.height;
        Ok(ClearanceTranslational {
            name: j.name.clone(),
            geometry: SliderGuide {
                guide,
                s_guide,
                axis,
                block,
                s_block,
                block_axis: rotate(-rel_angle, axis),
                half_length: 0.5 * data.length,
                half_height: 0.5 * height,
                half_width: 0.5 * width,
            },
            normal: data.normal,
            friction: data.friction,
        })
    }
}

impl ClearanceTranslational {
    /// Adds the contact loads of corner `index` in any number type, as
    /// [`ClearanceJoint::add_to`] adds each corner's: `frames` are
    /// [`SliderGuide::frames`]', `onset(k, rate)` the impact onset speed of point `k` at
    /// penetration rate `rate` ([`ContactState::onset_for`]).
    #[inline]
    pub fn add_corner_loads<T: Real>(
        &self,
        frames: ([Vec2<T>; 2], [Vec2<T>; 2]),
        (guide, block): (&BodyState<T>, &BodyState<T>),
        index: usize,
        onset: impl Fn(usize, T) -> T,
        qe: &mut Loads<T>,
    ) {
        if let Some(p) = corner_contact(&self.geometry, frames, guide, block, index, self.reach()) {
            let force = |p: &ContactPoint<T>| {
                dry_force(&self.normal, &self.friction, p, onset(p.index, p.penetration_rate))
            };
            apply_point_forces(&[p], force, guide, block, qe);
        }
    }
}

impl ClearanceJoint for ClearanceTranslational {
    type State = BodyState;
    type Point = ContactPoint;
    type Points = ContactPoints;
    type Friction = Tangential;

    fn name(&self) -> &str {
        &self.name
    }

    fn parts(&self) -> [Option<usize>; 2] {
        [self.geometry.guide, self.geometry.block]
    }

    /// The block's half height as the "journal", the guide's half width as the
    /// "bearing", the lateral play on each side as the clearance.
    fn data(&self) -> ClearanceData {
        let g = &self.geometry;
        ClearanceData {
            joint: self.name.clone(),
            bearing_radius: g.half_width,
            journal_radius: g.half_height,
            clearance: g.half_width - g.half_height,
            stiffness: self.normal.stiffness,
            exponent: self.normal.exponent,
        }
    }

    fn check_initial_penetration(&self, guide: &BodyState, block: &BodyState) -> Result<(), Error> {
        let limit = (MAX_INITIAL_CONTACT_FORCE / self.normal.stiffness).powf(1.0 / self.normal.exponent);
        match self.contacts(guide, block, f64::INFINITY).iter().find(|p| p.penetration > limit) {
            None => Ok(()),
            Some(p) => Err(Named::joint(&self.name).error_of_element(format!(
                "corner {} of the block starts {:.4} mm deep in the guide's surface (lateral play \
                 {:.4} mm per side), deeper than any elastic contact: this joint's normal law \
                 (K = {:.4e} N/m^{}) presses {:.4} mm deep only under {:.0e} N; likely a wrong \
                 point (point_i, point_j), axis, block_height or guide_width, or a length in the \
                 wrong unit",
                p.index + 1,
                1e3 * p.penetration,
                1e3 * (self.geometry.half_width - self.geometry.half_height),
                self.normal.stiffness,
                self.normal.exponent,
                1e3 * limit,
                MAX_INITIAL_CONTACT_FORCE,
            ))),
        }
    }

    fn points(&self) -> usize {
        SliderGuide::POINTS
    }

    fn reach(&self) -> f64 {
        self.normal.reach()
    }

    #[inline]
    fn contacts(&self, guide: &BodyState, block: &BodyState, reach: f64) -> ContactPoints {
        let mut out = ContactPoints::new();
        contact_slider_guide(&self.geometry, guide, block, reach, &mut out);
        out
    }

    #[inline]
    fn force(&self, p: &ContactPoint, onset_speed: f64) -> (f64, Tangential) {
        super::dry_force(&self.normal, &self.friction, p, onset_speed)
    }

    fn losses(&self, guide: &BodyState, block: &BodyState, states: &[ContactState]) -> (f64, f64) {
        super::dry_losses(self, &self.normal, guide, block, states)
    }

    fn elastic_energy(&self, p: &ContactPoint) -> f64 {
        self.normal.elastic_energy(p.penetration)
    }

    #[inline]
    fn add_to(&self, guide: &BodyState, block: &BodyState, states: &[ContactState], qe: &mut Loads) {
        super::add_point_forces(self, guide, block, states, qe);
    }
}
