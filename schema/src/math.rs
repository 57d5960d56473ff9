//! The geometry types the compiler and the runtime compute with, and the one conversion
//! pair between each and its file form in the artifact ([`crate::Pose`], [`crate::Aabb`]).
//!
//! These are nalgebra's f64 types, the ones parry3d-f64 0.25 uses, so collision queries
//! take them with no conversion; the box is parry's [`Aabb`]. Box comparisons that must
//! tolerate rounding (a point on a face, a box inside another) go through the functions
//! here, which allow [`EPS`] of slack; parry's own methods are exact.

use nalgebra as na;
pub use parry3d_f64::bounding_volume::Aabb;

/// A rigid transform (rotation + translation), in metres.
pub type Iso = na::Isometry3<f64>;
/// A 3-vector, in metres.
pub type Vec3 = na::Vector3<f64>;
/// A point, in metres.
pub type Point = na::Point3<f64>;
/// A unit quaternion.
pub type Quat = na::UnitQuaternion<f64>;

/// Geometric tolerance for box comparisons: 1 µm.
pub const EPS: f64 = 1e-6;

/// From the artifact's pose.
pub fn iso_from_schema(p: &crate::Pose) -> Iso {
    let [x, y, z, w] = p.rotation;
    Iso::from_parts(
        na::Translation3::new(p.translation[0], p.translation[1], p.translation[2]),
        Quat::from_quaternion(na::Quaternion::new(w, x, y, z)),
    )
}

/// To the artifact's pose.
pub fn iso_to_schema(p: &Iso) -> crate::Pose {
    let t = p.translation.vector;
    let q = p.rotation.coords;
    crate::Pose {
        translation: [t.x, t.y, t.z],
        rotation: [q.x, q.y, q.z, q.w],
    }
}

/// From the artifact's box.
pub fn aabb_from_schema(b: &crate::Aabb) -> Aabb {
    Aabb::new(b.min.into(), b.max.into())
}

/// To the artifact's box.
pub fn aabb_to_schema(b: &Aabb) -> crate::Aabb {
    crate::Aabb {
        min: b.mins.into(),
        max: b.maxs.into(),
    }
}

/// The box with this centre and these edge lengths.
pub fn aabb_from_center_size(center: [f64; 3], size: [f64; 3]) -> Aabb {
    Aabb::new(
        [0, 1, 2].map(|i| center[i] - size[i] / 2.0).into(),
        [0, 1, 2].map(|i| center[i] + size[i] / 2.0).into(),
    )
}

/// True when `point` is inside `b` or on its boundary, within [`EPS`].
pub fn contains_point(b: &Aabb, point: &Point) -> bool {
    (0..3).all(|i| point[i] >= b.mins[i] - EPS && point[i] <= b.maxs[i] + EPS)
}

/// True when `inner` lies inside `outer`, within [`EPS`].
pub fn contains_box(outer: &Aabb, inner: &Aabb) -> bool {
    (0..3).all(|i| inner.mins[i] >= outer.mins[i] - EPS && inner.maxs[i] <= outer.maxs[i] + EPS)
}

/// The overlap of two boxes when it has positive volume (more than [`EPS`] along every
/// axis, so boxes that only touch do not overlap; parry's `intersection` keeps those).
pub fn overlap(a: &Aabb, b: &Aabb) -> Option<Aabb> {
    let mins = a.mins.coords.sup(&b.mins.coords);
    let maxs = a.maxs.coords.inf(&b.maxs.coords);
    (0..3)
        .all(|i| maxs[i] - mins[i] > EPS)
        .then(|| Aabb::new(mins.into(), maxs.into()))
}

/// True when every coordinate of the pose is a finite number.
pub fn is_finite(p: &Iso) -> bool {
    p.translation.vector.iter().all(|x| x.is_finite())
        && p.rotation.coords.iter().all(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_forms_round_trip() {
        let b = crate::Aabb {
            min: [-1.0, 0.0, 0.5],
            max: [1.0, 2.0, 0.75],
        };
        assert_eq!(aabb_to_schema(&aabb_from_schema(&b)), b);
        let p = crate::Pose {
            translation: [0.1, 0.2, 0.3],
            rotation: [0.0, 0.0, 0.0, 1.0],
        };
        assert_eq!(iso_to_schema(&iso_from_schema(&p)), p);
    }

    #[test]
    fn comparisons_allow_a_micrometre() {
        let b = aabb_from_center_size([0.0; 3], [2.0; 3]);
        assert!(contains_point(&b, &Point::new(1.0 + 0.5 * EPS, 0.0, 0.0)));
        assert!(!contains_point(&b, &Point::new(1.0 + 2.0 * EPS, 0.0, 0.0)));
        let right = aabb_from_center_size([2.0, 0.0, 0.0], [2.0; 3]);
        assert!(
            overlap(&b, &right).is_none(),
            "touching boxes do not overlap"
        );
        let inner = aabb_from_center_size([0.5, 0.0, 0.0], [1.0; 3]);
        assert_eq!(overlap(&b, &inner), Some(inner));
        assert!(contains_box(&b, &inner) && !contains_box(&inner, &b));
    }
}
