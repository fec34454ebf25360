//! Model names to the mechanism's indices: bodies by name, points by name or
//! coordinates, each error naming the element and field that refer to them. Every
//! element kind is built from its model entry through one [`Resolver`].

use std::collections::{BTreeMap, HashMap};

use crate::error::{Error, Named};
use crate::math::Vec2;
use crate::model::{Model, PointRef, GROUND};

/// Looks up bodies by name and resolves points on them, naming the element in errors.
pub(crate) struct Resolver<'a> {
    model: &'a Model,
    index: HashMap<&'a str, usize>,
}

impl<'a> Resolver<'a> {
    /// Resolves names of `model`, whose bodies are indexed by `index` (name -> body).
    pub(crate) fn new(model: &'a Model, index: HashMap<&'a str, usize>) -> Self {
        Resolver { model, index }
    }

    pub(crate) fn body(&self, who: Named, field: &str, name: &str) -> Result<Option<usize>, Error> {
        if name == GROUND {
            return Ok(None);
        }
        self.index.get(name).copied().map(Some).ok_or_else(|| {
            let mut known: Vec<&str> = vec![GROUND];
            known.extend(self.model.bodies.iter().map(|b| b.name.as_str()));
            who.error(
                field,
                format!("{field} '{name}' is not a body of the model (bodies: {})", known.join(", ")),
            )
        })
    }

    pub(crate) fn point(
        &self,
        who: Named,
        field: &str,
        body: Option<usize>,
        p: &PointRef,
    ) -> Result<Vec2, Error> {
        let (points, body_name): (&BTreeMap<String, [f64; 2]>, &str) = match body {
            None => (&self.model.ground_points, GROUND),
            Some(k) => (&self.model.bodies[k].points, &self.model.bodies[k].name),
        };
        let v = match p {
            PointRef::Local(v) => *v,
            PointRef::Named(n) => *points.get(n).ok_or_else(|| {
                let known: Vec<&str> = points.keys().map(|s| s.as_str()).collect();
                who.error(
                    field,
                    format!(
                        "{field} '{n}' is not a point of body '{body_name}' (points: {})",
                        if known.is_empty() { "none".to_string() } else { known.join(", ") }
                    ),
                )
            })?,
        };
        if !(v[0].is_finite() && v[1].is_finite()) {
            return Err(who.error(field, format!("{field} {v:?} is not finite")));
        }
        Ok(Vec2::new(v[0], v[1]))
    }
}
