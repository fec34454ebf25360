//! Model names to the mechanism's indices: bodies by name, points by name or
//! coordinates, each error naming the element and field that refer to them. Every
//! element kind is built from its model entry through one [`Resolver`], planar (points
//! of 2 coordinates) or spatial (3).

use std::collections::{BTreeMap, HashMap};

use crate::error::{Error, Named};
use crate::math::Vec2;
use crate::model::{Model, PointRef, GROUND};

/// Looks up bodies by name and resolves points on them, naming the element in errors.
pub(crate) struct Resolver<'a, const N: usize = 2> {
    /// Each body's name and named points, in model order.
    bodies: Vec<(&'a str, &'a BTreeMap<String, [f64; N]>)>,
    /// The ground's named points.
    ground: &'a BTreeMap<String, [f64; N]>,
    index: HashMap<&'a str, usize>,
}

impl<'a> Resolver<'a> {
    /// Resolves names of `model`, whose bodies are indexed by `index` (name -> body).
    pub(crate) fn new(model: &'a Model, index: HashMap<&'a str, usize>) -> Self {
        let bodies = model.bodies.iter().map(|b| (b.name.as_str(), &b.points)).collect();
        Resolver::of(bodies, &model.ground_points, index)
    }

    pub(crate) fn point(
        &self,
        who: Named,
        field: &str,
        body: Option<usize>,
        p: &PointRef,
    ) -> Result<Vec2, Error> {
        let v = match p {
            PointRef::Local(v) => self.coordinates(who, field, *v)?,
            PointRef::Named(n) => self.named(who, field, body, n)?,
        };
        Ok(Vec2::new(v[0], v[1]))
    }
}

impl<'a, const N: usize> Resolver<'a, N> {
    /// Resolves names among `bodies` (name and named points, in model order) and the
    /// ground's points `ground`, the bodies indexed by `index` (name -> body).
    pub(crate) fn of(
        bodies: Vec<(&'a str, &'a BTreeMap<String, [f64; N]>)>,
        ground: &'a BTreeMap<String, [f64; N]>,
        index: HashMap<&'a str, usize>,
    ) -> Self {
        Resolver { bodies, ground, index }
    }

    pub(crate) fn body(&self, who: Named, field: &str, name: &str) -> Result<Option<usize>, Error> {
        if name == GROUND {
            return Ok(None);
        }
        self.index.get(name).copied().map(Some).ok_or_else(|| {
            let mut known: Vec<&str> = vec![GROUND];
            known.extend(self.bodies.iter().map(|(name, _)| *name));
            who.error(
                field,
                format!("{field} '{name}' is not a body of the model (bodies: {})", known.join(", ")),
            )
        })
    }

    /// The named point `name` of body `body` (the ground's for `None`).
    pub(crate) fn named(
        &self,
        who: Named,
        field: &str,
        body: Option<usize>,
        name: &str,
    ) -> Result<[f64; N], Error> {
        let (points, body_name) = match body {
            None => (self.ground, GROUND),
            Some(k) => (self.bodies[k].1, self.bodies[k].0),
        };
        let v = *points.get(name).ok_or_else(|| {
            let known: Vec<&str> = points.keys().map(|s| s.as_str()).collect();
            who.error(
                field,
                format!(
                    "{field} '{name}' is not a point of body '{body_name}' (points: {})",
                    if known.is_empty() { "none".to_string() } else { known.join(", ") }
                ),
            )
        })?;
        self.coordinates(who, field, v)
    }

    /// Coordinates given in the model, checked finite.
    pub(crate) fn coordinates(&self, who: Named, field: &str, v: [f64; N]) -> Result<[f64; N], Error> {
        if v.iter().any(|x| !x.is_finite()) {
            return Err(who.error(field, format!("{field} {v:?} is not finite")));
        }
        Ok(v)
    }
}
