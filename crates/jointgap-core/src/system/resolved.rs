//! Each clearance joint as the engine resolves it: the radii and clearance from the two
//! given, the stiffness from the materials, and the laws in force with every default
//! filled in (the exponent, ADAMS IMPACT's `d_max` from the bearing material). The front
//! ends read these values here instead of resolving them again.

use serde::Serialize;

use crate::mechanics::contact::normal::{NormalForce, NormalLaw};
use crate::mechanics::contact::planar_clearance::PlanarClearance;
use crate::mechanics::contact::spatial::SpatialGeometry;
use crate::mechanics::contact::ClearanceJoint;
use crate::mechanics::spatial::kind::Spatial;
use crate::model::spatial::SpatialModel;
use crate::model::{FrictionSpec, Model, NormalLawSpec};
use crate::output::ClearanceData;
use crate::system::System;

/// One clearance joint's resolved data.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ResolvedClearance {
    /// Name, radii, clearance, stiffness and exponent, as a run reports them.
    #[serde(flatten)]
    pub data: ClearanceData,
    /// Penetration of full damping of an ADAMS IMPACT law [m], given or the bearing
    /// material's; `None` for the other laws.
    pub d_max: Option<f64>,
    /// The normal law in force: the model's, every default filled in.
    pub normal_law: NormalLawSpec,
    /// The friction law in force.
    pub friction: FrictionSpec,
}

/// One clearance joint resolved: its model entry's `spec`, its normal law and friction
/// as compiled, and its data.
fn resolve(
    spec: &NormalLawSpec,
    normal: &NormalForce,
    friction: &FrictionSpec,
    data: ClearanceData,
) -> ResolvedClearance {
    let d_max = match normal.law {
        NormalLaw::AdamsImpact { d_max, .. } => Some(d_max),
        _ => None,
    };
    let mut normal_law = spec.clone();
    if let NormalLawSpec::AdamsImpact { d_max: given, .. } = &mut normal_law {
        *given = d_max;
    }
    ResolvedClearance { data, d_max, normal_law, friction: friction.clone() }
}

/// Every clearance joint of `model`, compiled as `system`, in model order.
pub fn clearances(model: &Model, system: &System) -> Vec<ResolvedClearance> {
    system
        .clearances
        .iter()
        .filter_map(|c| {
            let j = model.joints.iter().find(|j| j.name == c.name())?;
            let spec = match c {
                PlanarClearance::Play(_) => &j.play.as_ref()?.normal_law,
                PlanarClearance::Gear(_) => &j.gear.as_ref()?.normal_law,
                _ => &j.clearance.as_ref()?.normal_law,
            };
            Some(resolve(spec, c.normal(), c.friction(), c.data()))
        })
        .collect()
}

/// Every clearance joint of a spatial `model`, compiled as `system`, in model order.
pub fn spatial_clearances(model: &SpatialModel, system: &System<Spatial>) -> Vec<ResolvedClearance> {
    system
        .clearances
        .iter()
        .filter_map(|c| {
            let j = model.joints.iter().find(|j| j.name == c.name)?;
            let spec = match &c.geometry {
                SpatialGeometry::Play(_) => &j.play.as_ref()?.normal_law,
                _ => &j.clearance.as_ref()?.normal_law,
            };
            Some(resolve(spec, &c.normal, &c.friction, c.data()))
        })
        .collect()
}
