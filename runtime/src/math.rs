//! Geometry types used across the runtime: the ones the compiler uses too, defined once in
//! [`cellc_schema::math`] (nalgebra f64, the same types parry3d-f64 0.25 uses, so no
//! conversion happens at the collision boundary; boxes are parry's `Aabb`).

pub use cellc_schema::math::*;
