//! A model of either body kind, as a front end holds it: read from JSON by its
//! `dimension` (3: spatial, else planar), prepared once, then checked, measured and run
//! through the one engine instantiated for its kind.

use super::{
    check_prepared, prepare, prepare_model, record, recorded_channels_of, run_prepared, Monitor, Prepared,
    SimOptions,
};
use crate::mechanics::spatial::kind::Spatial;
use crate::model::spatial::SpatialModel;
use crate::output::SimResult;
use crate::system::resolved::{self, ResolvedClearance};
use crate::{Error, Model, System};

/// A planar or a spatial model.
#[derive(Debug, Clone)]
pub enum AnyModel {
    /// A planar mechanism.
    Planar(Model),
    /// A spatial mechanism.
    Spatial(SpatialModel),
}

/// Only the key that tells the kinds apart; the rest of the text is read by the kind's
/// own model, which rejects unknown keys.
#[derive(serde::Deserialize)]
struct Dimension {
    #[serde(default)]
    dimension: Option<serde_json::Value>,
}

impl AnyModel {
    /// Reads a model from JSON (SI units): spatial where it says `"dimension": 3`.
    pub fn from_json(text: &str) -> Result<Self, Error> {
        let dimension = serde_json::from_str::<Dimension>(text)
            .map_err(|e| Error::Model(format!("model JSON: {e}")))?
            .dimension;
        match dimension {
            None => Model::from_json(text).map(AnyModel::Planar),
            Some(d) if d == 2 => {
                // A planar model may say so; its own reader knows no such key.
                let mut value: serde_json::Value =
                    serde_json::from_str(text).map_err(|e| Error::Model(format!("model JSON: {e}")))?;
                value.as_object_mut().map(|o| o.remove("dimension"));
                Model::from_json(&value.to_string()).map(AnyModel::Planar)
            }
            Some(d) if d == 3 => SpatialModel::from_json(text).map(AnyModel::Spatial),
            Some(d) => {
                Err(Error::Model(format!("model: dimension = {d}: a model is planar (2) or spatial (3)")))
            }
        }
    }
}

/// A model of either kind with consistent initial conditions, ready to run.
pub enum AnyPrepared {
    /// A planar one.
    Planar(Prepared),
    /// A spatial one.
    Spatial(Prepared<Spatial>),
}

impl AnyPrepared {
    /// Checks, compiles and assembles a model ([`prepare`]).
    pub fn new(model: &AnyModel) -> Result<Self, Error> {
        Ok(match model {
            AnyModel::Planar(m) => AnyPrepared::Planar(prepare(m)?),
            AnyModel::Spatial(m) => AnyPrepared::Spatial(prepare_model::<Spatial>(m)?),
        })
    }

    /// [`check_prepared`]: the warnings of a model that a run would accept.
    pub fn check(&self) -> Result<Vec<String>, Error> {
        match self {
            AnyPrepared::Planar(p) => check_prepared(p),
            AnyPrepared::Spatial(p) => check_prepared(p),
        }
    }

    /// The channels a run with `opts` records ([`recorded_channels_of`]).
    pub fn recorded_channels(&self, opts: &SimOptions) -> Result<Vec<String>, Error> {
        match self {
            AnyPrepared::Planar(p) => recorded_channels_of(&p.system, opts),
            AnyPrepared::Spatial(p) => recorded_channels_of(&p.system, opts),
        }
    }

    /// One run from t = 0; `started` is when its wall time starts.
    pub fn run(
        &self,
        opts: &SimOptions,
        monitor: &mut dyn Monitor,
        started: std::time::Instant,
    ) -> Result<SimResult, Error> {
        match self {
            AnyPrepared::Planar(p) => run_prepared(p, opts, monitor, started),
            AnyPrepared::Spatial(p) => run_prepared(p, opts, monitor, started),
        }
    }
}

/// Every channel of a model (in model order), without assembling it.
pub fn channel_names(model: &AnyModel) -> Result<Vec<String>, Error> {
    Ok(match model {
        AnyModel::Planar(m) => record::channel_names(&System::new(m)?, false),
        AnyModel::Spatial(m) => record::channel_names(&System::spatial(m)?, false),
    })
}

/// Each clearance joint as the engine resolves it ([`resolved`]), without running.
pub fn clearances(model: &AnyModel) -> Result<Vec<ResolvedClearance>, Error> {
    Ok(match model {
        AnyModel::Planar(m) => resolved::clearances(m, &System::new(m)?),
        AnyModel::Spatial(m) => resolved::spatial_clearances(m, &System::spatial(m)?),
    })
}
