//! Which rotations of an object leave it looking the same.
//!
//! A cell declares `symmetry about z` (any angle) or `symmetry about z order 4` (multiples
//! of 90°). Two poses of a symmetric object that differ by such a rotation are the same
//! physical placement, which matters in two places: a handoff may close its chain up to a
//! symmetry (a ball passed between two hands with the same grasp is held from opposite
//! sides), and matching an observed pose to a grasp or resting pose must not tell
//! symmetric poses apart.

use crate::Symmetry;

use crate::math::{Quat, Vec3};

/// Rotations by which a continuous symmetry is sampled when a finite set is needed.
const CONTINUOUS_SAMPLES: u32 = 6;

fn axis(s: &Symmetry) -> Option<nalgebra::Unit<Vec3>> {
    nalgebra::Unit::try_new(Vec3::new(s.axis[0], s.axis[1], s.axis[2]), 1e-9)
}

/// A finite set of symmetry rotations, the identity first: every discrete element, and
/// continuous symmetries sampled at 60° steps. Used to try the symmetric variants of a
/// grasp one after another.
pub fn candidates(symmetries: &[Symmetry]) -> Vec<Quat> {
    let mut out = vec![Quat::identity()];
    for s in symmetries {
        let Some(a) = axis(s) else { continue };
        let n = s.order.unwrap_or(CONTINUOUS_SAMPLES).max(1);
        let existing = out.clone();
        for k in 1..n {
            let r = Quat::from_axis_angle(&a, std::f64::consts::TAU * f64::from(k) / f64::from(n));
            for e in &existing {
                let c = r * e;
                if !out.iter().any(|o| o.angle_to(&c) < 1e-9) {
                    out.push(c);
                }
            }
        }
    }
    out
}

/// How far (radians) the rotation `relative` is from the nearest symmetry of the object.
/// Zero when the object looks the same after `relative`.
pub fn residual(relative: &Quat, symmetries: &[Symmetry]) -> f64 {
    let continuous: Vec<nalgebra::Unit<Vec3>> = symmetries
        .iter()
        .filter(|s| s.order.is_none())
        .filter_map(axis)
        .collect();
    // Two different continuous axes generate every rotation (a sphere).
    let independent = continuous
        .iter()
        .any(|a| continuous.iter().any(|b| a.cross(b).norm() > 1e-6));
    if independent {
        return 0.0;
    }
    let discrete: Vec<Symmetry> = symmetries
        .iter()
        .filter(|s| s.order.is_some())
        .copied()
        .collect();
    candidates(&discrete)
        .iter()
        .map(|d| {
            let rest = relative * d.inverse();
            match continuous.first() {
                // Free twist about the axis: only the swing away from it counts.
                Some(a) => swing_angle(&rest, a),
                None => rest.angle(),
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// The angle of the part of `q` that is not a rotation about `axis` (swing-twist
/// decomposition).
fn swing_angle(q: &Quat, axis: &nalgebra::Unit<Vec3>) -> f64 {
    let v = q.imag();
    let projected = axis.into_inner() * v.dot(axis);
    let twist = nalgebra::Quaternion::from_parts(q.w, projected);
    if twist.norm() < 1e-12 {
        // A half turn about an axis perpendicular to `axis`.
        return std::f64::consts::PI;
    }
    let twist = Quat::from_quaternion(twist);
    (q * twist.inverse()).angle()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sym(axis: [f64; 3], order: Option<u32>) -> Symmetry {
        Symmetry { axis, order }
    }

    #[test]
    fn a_cylinder_turns_freely_about_its_axis_only() {
        let cylinder = [sym([0.0, 0.0, 1.0], None)];
        let about_z = Quat::from_axis_angle(&Vec3::z_axis(), 1.234);
        let about_x = Quat::from_axis_angle(&Vec3::x_axis(), 0.5);
        assert!(residual(&about_z, &cylinder) < 1e-9);
        assert!((residual(&about_x, &cylinder) - 0.5).abs() < 1e-9);
        assert!((residual(&(about_z * about_x), &cylinder) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn a_sphere_looks_the_same_every_way() {
        let ball = [sym([1.0, 0.0, 0.0], None), sym([0.0, 0.0, 1.0], None)];
        let any = Quat::from_euler_angles(0.3, -1.1, 2.0);
        assert_eq!(residual(&any, &ball), 0.0);
    }

    #[test]
    fn discrete_symmetry_allows_its_multiples_only() {
        let square = [sym([0.0, 0.0, 1.0], Some(4))];
        let quarter = Quat::from_axis_angle(&Vec3::z_axis(), std::f64::consts::FRAC_PI_2);
        let eighth = Quat::from_axis_angle(&Vec3::z_axis(), std::f64::consts::FRAC_PI_4);
        assert!(residual(&quarter, &square) < 1e-9);
        assert!((residual(&eighth, &square) - std::f64::consts::FRAC_PI_4).abs() < 1e-9);
        assert_eq!(candidates(&square).len(), 4);
        assert!(candidates(&square)[0].angle() < 1e-12);
    }
}
