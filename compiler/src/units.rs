//! Quantities to SI values: applies written units or the file's `units` defaults, and
//! reports missing and wrong units.

use cellc_lang::ast::{self, Unit};
use cellc_lang::{Diagnostic, FileId};
use nalgebra as na;

use crate::diagnostics::{self, Dimension};
use crate::math::{aabb_from_center_size, Aabb, Iso, Quat};

/// Default units of one file, from its `units` line.
#[derive(Clone, Copy, Debug, Default)]
pub struct FileUnits {
    /// For bare lengths.
    pub length: Option<Unit>,
    /// For bare angles.
    pub angle: Option<Unit>,
}

impl FileUnits {
    /// Reads a file's `units` items.
    pub fn of(file: FileId, items: &[ast::Item], diagnostics: &mut Vec<Diagnostic>) -> FileUnits {
        let mut units = FileUnits::default();
        let mut length_span = None;
        let mut angle_span = None;
        for item in items {
            let ast::Item::Units(item) = item else {
                continue;
            };
            for &(unit, span) in &item.units {
                let (slot, seen, what) = if unit.is_length() {
                    (&mut units.length, &mut length_span, "length")
                } else {
                    (&mut units.angle, &mut angle_span, "angle")
                };
                if let Some(first) = *seen {
                    diagnostics.push(diagnostics::conflicting_units(file, span, first, what));
                } else {
                    *slot = Some(unit);
                    *seen = Some(span);
                }
            }
        }
        units
    }
}

/// Evaluates quantities of one file.
pub struct Eval<'d> {
    /// File the quantities are in.
    pub file: FileId,
    /// Its defaults.
    pub units: FileUnits,
    /// Where problems go.
    pub diagnostics: &'d mut Vec<Diagnostic>,
}

impl Eval<'_> {
    fn value(&mut self, q: &ast::Quantity, dimension: Dimension) -> Option<f64> {
        let unit = match (q.unit, dimension) {
            (None, Dimension::Number) => return self.finite(q, q.value),
            (Some(unit), Dimension::Number) => {
                self.diagnostics.push(diagnostics::wrong_unit(
                    dimension,
                    unit.as_str(),
                    self.file,
                    q.span,
                ));
                return None;
            }
            (Some(unit), _) => unit,
            // Rates are read by `limit`, never here.
            (_, Dimension::Rate { .. }) => {
                self.diagnostics
                    .push(diagnostics::missing_unit(dimension, self.file, q.span));
                return None;
            }
            (None, Dimension::Length) => match self.units.length {
                Some(unit) => unit,
                None => {
                    self.diagnostics
                        .push(diagnostics::missing_unit(dimension, self.file, q.span));
                    return None;
                }
            },
            (None, Dimension::Angle) => match self.units.angle {
                Some(unit) => unit,
                None => {
                    self.diagnostics
                        .push(diagnostics::missing_unit(dimension, self.file, q.span));
                    return None;
                }
            },
        };
        let right = match dimension {
            Dimension::Length => unit.is_length(),
            _ => !unit.is_length(),
        };
        if !right {
            self.diagnostics.push(diagnostics::wrong_unit(
                dimension,
                unit.as_str(),
                self.file,
                q.span,
            ));
            return None;
        }
        self.finite(q, q.value * unit.to_si())
    }

    fn finite(&mut self, q: &ast::Quantity, value: f64) -> Option<f64> {
        if value.is_finite() {
            Some(value)
        } else {
            self.diagnostics
                .push(diagnostics::not_finite(self.file, q.span));
            None
        }
    }

    /// A length in metres.
    pub fn length(&mut self, q: &ast::Quantity) -> Option<f64> {
        self.value(q, Dimension::Length)
    }

    /// An angle in radians.
    pub fn angle(&mut self, q: &ast::Quantity) -> Option<f64> {
        self.value(q, Dimension::Angle)
    }

    /// A strictly positive length in metres.
    pub fn positive_length(&mut self, q: &ast::Quantity, what: &str) -> Option<f64> {
        let value = self.length(q)?;
        if value > 0.0 {
            Some(value)
        } else {
            self.diagnostics
                .push(diagnostics::not_positive(what, q.value, self.file, q.span));
            None
        }
    }

    /// A joint limit in SI (rad/s^n or m/s^n; `linear` for a prismatic joint), positive
    /// and finite. A bare number takes the file's angle unit (revolute joints) or length
    /// unit (prismatic) per second to the limit's power.
    pub fn limit(&mut self, r: &ast::Rate, kind: ast::LimitKind, linear: bool) -> Option<f64> {
        let dimension = Dimension::Rate {
            linear,
            order: kind.order(),
        };
        let base = match r.unit {
            Some(unit) => {
                if unit.base.is_length() != linear || unit.order != kind.order() {
                    self.diagnostics.push(diagnostics::wrong_unit(
                        dimension,
                        &unit.as_string(),
                        self.file,
                        r.span,
                    ));
                    return None;
                }
                unit.base
            }
            None => {
                let default = if linear {
                    self.units.length
                } else {
                    self.units.angle
                };
                match default {
                    Some(unit) => unit,
                    None => {
                        self.diagnostics
                            .push(diagnostics::missing_unit(dimension, self.file, r.span));
                        return None;
                    }
                }
            }
        };
        let value = r.value * base.to_si();
        if !value.is_finite() {
            self.diagnostics
                .push(diagnostics::not_finite(self.file, r.span));
            return None;
        }
        if value <= 0.0 {
            let article = if kind == ast::LimitKind::Acceleration {
                "an"
            } else {
                "a"
            };
            let what = format!("{article} {} limit", kind.as_str());
            self.diagnostics
                .push(diagnostics::not_positive(&what, r.value, self.file, r.span));
            return None;
        }
        Some(value)
    }

    /// Three lengths (all are checked, so every bad component is reported).
    pub fn lengths(&mut self, v: &ast::Vec3) -> Option<[f64; 3]> {
        let parts = v.parts.each_ref().map(|q| self.length(q));
        Some([parts[0]?, parts[1]?, parts[2]?])
    }

    /// Three positive lengths.
    pub fn sizes(&mut self, v: &ast::Vec3, what: &str) -> Option<[f64; 3]> {
        let parts = v.parts.each_ref().map(|q| self.positive_length(q, what));
        Some([parts[0]?, parts[1]?, parts[2]?])
    }

    /// A box in metres.
    pub fn aabb(&mut self, b: &ast::Aabb) -> Option<Aabb> {
        let center = self.lengths(&b.center);
        let size = self.sizes(&b.size, "a box size");
        Some(aabb_from_center_size(center?, size?))
    }

    /// A pose.
    pub fn pose(&mut self, p: &ast::Pose) -> Option<Iso> {
        let at = self.lengths(&p.at);
        let rotation = match &p.rotation {
            None => Some(Quat::identity()),
            Some(ast::Rotation::Rpy(v, _)) => {
                let angles = v.parts.each_ref().map(|q| self.value(q, Dimension::Angle));
                match angles {
                    [Some(r), Some(p), Some(y)] => Some(Quat::from_euler_angles(r, p, y)),
                    _ => None,
                }
            }
            Some(ast::Rotation::Quat(parts, span)) => {
                let values = parts.each_ref().map(|q| self.value(q, Dimension::Number));
                match values {
                    [Some(w), Some(x), Some(y), Some(z)] => {
                        let q = na::Quaternion::new(w, x, y, z);
                        let norm = q.norm();
                        if (norm - 1.0).abs() > 1e-3 || !norm.is_finite() {
                            self.diagnostics
                                .push(diagnostics::not_a_rotation(norm, self.file, *span));
                            None
                        } else {
                            Some(Quat::from_quaternion(q))
                        }
                    }
                    _ => None,
                }
            }
        };
        let at = at?;
        Some(Iso::from_parts(
            na::Translation3::new(at[0], at[1], at[2]),
            rotation?,
        ))
    }
}
