//! PLACEHOLDER (not committed): replaced by the film module.
use crate::model::FilmModel;
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Film {
    pub radius: f64,
    pub clearance: f64,
    pub length: f64,
    pub viscosity: f64,
    pub model: FilmModel,
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmMotion {
    pub eccentricity: f64,
    pub eccentricity_rate: f64,
    pub attitude_rate: f64,
    pub omega_journal: f64,
    pub omega_bearing: f64,
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmForce {
    pub along: f64,
    pub across: f64,
    pub torque_journal: f64,
    pub peak_pressure: f64,
}
impl Film {
    pub fn force(&self, _m: &FilmMotion) -> FilmForce {
        FilmForce { along: 0.0, across: 0.0, torque_journal: 0.0, peak_pressure: 0.0 }
    }
}
