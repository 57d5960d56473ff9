//! Geometry aliases used across the runtime (nalgebra, f64 — the same types parry3d-f64
//! 0.25 uses, so no conversion happens at the collision boundary).

use nalgebra as na;

/// A rigid transform.
pub type Iso = na::Isometry3<f64>;
/// A 3-vector.
pub type Vec3 = na::Vector3<f64>;
/// A point.
pub type Point = na::Point3<f64>;
/// A unit quaternion.
pub type Quat = na::UnitQuaternion<f64>;

/// From the artifact's pose.
pub fn iso_from_schema(p: &cellc_schema::Pose) -> Iso {
    let [x, y, z, w] = p.rotation;
    Iso::from_parts(
        na::Translation3::new(p.translation[0], p.translation[1], p.translation[2]),
        Quat::from_quaternion(na::Quaternion::new(w, x, y, z)),
    )
}

/// To the artifact's pose.
pub fn iso_to_schema(p: &Iso) -> cellc_schema::Pose {
    let t = p.translation.vector;
    let q = p.rotation.coords;
    cellc_schema::Pose {
        translation: [t.x, t.y, t.z],
        rotation: [q.x, q.y, q.z, q.w],
    }
}

/// True when every coordinate of the pose is a finite number.
pub fn is_finite(p: &Iso) -> bool {
    p.translation.vector.iter().all(|x| x.is_finite())
        && p.rotation.coords.iter().all(|x| x.is_finite())
}
