//! Values inside items: shapes, solids, poses, boxes, vectors, quantities, names and
//! strings.

use pest::iterators::Pair;

use super::{span_of, Builder};
use crate::ast::*;
use crate::grammar::Rule;
use crate::phrases;

impl Builder<'_, '_> {
    pub(super) fn shape(&mut self, pair: Pair<'_, Rule>) -> Option<Shape> {
        let pair = pair.into_inner().next()?;
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        Some(match rule {
            Rule::box_shape => {
                let _box = inner.next();
                let _size = inner.next();
                Shape::Box {
                    size: self.vec3(inner.next()?)?,
                }
            }
            Rule::cylinder_shape => {
                let _cyl = inner.next();
                let _radius = inner.next();
                let radius = self.quantity(inner.next()?)?;
                let _height = inner.next();
                let height = self.quantity(inner.next()?)?;
                Shape::Cylinder { radius, height }
            }
            Rule::sphere_shape => {
                let _sphere = inner.next();
                let _radius = inner.next();
                Shape::Sphere {
                    radius: self.quantity(inner.next()?)?,
                }
            }
            Rule::mesh_shape => {
                let _mesh = inner.next();
                Shape::Mesh {
                    path: self.string(inner.next()?)?,
                }
            }
            _ => return None,
        })
    }

    pub(super) fn solid(&mut self, pair: Pair<'_, Rule>) -> Option<Solid> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let shape = self.shape(inner.next()?)?;
        let pose = match inner.next() {
            Some(p) => Some(self.pose(p)?),
            None => None,
        };
        Some(Solid { shape, pose, span })
    }

    pub(super) fn pose(&mut self, pair: Pair<'_, Rule>) -> Option<Pose> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let _at = inner.next();
        let at = self.vec3(inner.next()?)?;
        let rotation = match inner.next() {
            Some(rotation) => {
                let r = rotation.into_inner().next()?;
                let rspan = span_of(&r);
                let rule = r.as_rule();
                let mut parts = r.into_inner();
                let _kw = parts.next();
                let values = parts.next()?;
                Some(if rule == Rule::rpy {
                    Rotation::Rpy(self.vec3(values)?, rspan)
                } else {
                    let q = values
                        .into_inner()
                        .map(|p| self.quantity(p))
                        .collect::<Option<Vec<_>>>()?;
                    Rotation::Quat(q.try_into().ok()?, rspan)
                })
            }
            None => None,
        };
        Some(Pose { at, rotation, span })
    }

    pub(super) fn aabb(&mut self, pair: Pair<'_, Rule>) -> Option<Aabb> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let _box = inner.next();
        let _center = inner.next();
        let center = self.vec3(inner.next()?)?;
        let _size = inner.next();
        let size = self.vec3(inner.next()?)?;
        Some(Aabb { center, size, span })
    }

    pub(super) fn vec3(&mut self, pair: Pair<'_, Rule>) -> Option<Vec3> {
        let span = span_of(&pair);
        let parts = pair
            .into_inner()
            .map(|p| self.quantity(p))
            .collect::<Option<Vec<_>>>()?;
        Some(Vec3 {
            parts: parts.try_into().ok()?,
            span,
        })
    }

    /// `every STEP about AXIS` or `along AXIS at (D1, ...)`.
    pub(super) fn family_clause(&mut self, pair: Pair<'_, Rule>) -> Option<FamilyClause> {
        let clause = pair.into_inner().next()?;
        let span = span_of(&clause);
        let rule = clause.as_rule();
        let mut step = None;
        let mut axis = None;
        let mut offsets = Vec::new();
        for p in clause.into_inner() {
            match p.as_rule() {
                Rule::quantity => step = Some(self.quantity(p)?),
                Rule::axis => axis = Some(axis_of(p.as_str())),
                Rule::quantity_list => {
                    offsets = p
                        .into_inner()
                        .map(|q| self.quantity(q))
                        .collect::<Option<Vec<_>>>()?;
                }
                _ => {}
            }
        }
        Some(match rule {
            Rule::every_clause => FamilyClause::Every {
                step: step?,
                axis: axis?,
                span,
            },
            _ => FamilyClause::Along {
                axis: axis?,
                offsets,
                span,
            },
        })
    }

    pub(super) fn quantity(&mut self, pair: Pair<'_, Rule>) -> Option<Quantity> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let number = inner.next()?;
        let unit = match inner.next() {
            Some(u) => Some(Unit::parse(u.as_str())?),
            None => None,
        };
        Some(Quantity {
            number: number.as_str().to_string(),
            value: number.as_str().parse().ok()?,
            unit,
            span,
        })
    }

    pub(super) fn rate(&mut self, pair: Pair<'_, Rule>) -> Option<Rate> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let number = inner.next()?;
        let unit = match inner.next() {
            Some(u) => Some(RateUnit::parse(u.as_str())?),
            None => None,
        };
        Some(Rate {
            number: number.as_str().to_string(),
            value: number.as_str().parse().ok()?,
            unit,
            span,
        })
    }

    pub(super) fn integer(&mut self, pair: &Pair<'_, Rule>) -> Option<u32> {
        match pair.as_str().parse() {
            Ok(value) => Some(value),
            Err(_) => {
                self.diagnostics
                    .push(phrases::integer_too_large(self.file_id, span_of(pair)));
                Some(u32::MAX)
            }
        }
    }

    pub(super) fn name(&mut self, pair: Pair<'_, Rule>) -> Option<Name> {
        let span = span_of(&pair);
        let text = pair.as_str();
        let text = text
            .strip_prefix('`')
            .and_then(|t| t.strip_suffix('`'))
            .unwrap_or(text);
        Some(Name {
            text: text.to_string(),
            span,
        })
    }

    pub(super) fn qualified(&mut self, pair: Pair<'_, Rule>) -> Option<Qualified> {
        let span = span_of(&pair);
        let mut names = pair
            .into_inner()
            .map(|p| self.name(p))
            .collect::<Option<Vec<_>>>()?;
        let name = names.pop()?;
        Some(Qualified {
            object: names.pop(),
            name,
            span,
        })
    }

    pub(super) fn name_list(&mut self, pair: Pair<'_, Rule>) -> Option<Vec<Name>> {
        pair.into_inner().map(|p| self.name(p)).collect()
    }

    pub(super) fn string(&mut self, pair: Pair<'_, Rule>) -> Option<StringLit> {
        let span = span_of(&pair);
        let raw = pair.into_inner().next()?.as_str();
        let mut value = String::with_capacity(raw.len());
        let mut chars = raw.chars();
        while let Some(c) = chars.next() {
            if c == '\\' {
                match chars.next() {
                    Some('n') => value.push('\n'),
                    Some('t') => value.push('\t'),
                    Some(other) => value.push(other),
                    None => {}
                }
            } else {
                value.push(c);
            }
        }
        Some(StringLit { value, span })
    }
}

/// An axis as the grammar's `axis` rule matched it.
pub(super) fn axis_of(text: &str) -> Axis {
    match text {
        "x" => Axis::X,
        "y" => Axis::Y,
        _ => Axis::Z,
    }
}
