//! Containment of the fitted capsules, the exact segment–box distance, and the capsule
//! bound against parry's exact distance.

use parry3d_f64::query;
use parry3d_f64::shape::{ConvexPolyhedron, Segment, SharedShape};
use proptest::prelude::*;

use super::*;

/// Every point within the capsule's radius (plus a nanometre) of its segment.
fn assert_contains(c: &Capsule, points: &[Point], what: &str) {
    for p in points {
        let d = point_segment_distance(p, &c.a, &c.b);
        assert!(
            d <= c.radius + 1e-9,
            "{what}: {p:?} is {d} from the segment, radius {}",
            c.radius
        );
    }
}

/// Every collision mesh of the shipped robots (the Panda's and the UR5's, as the runtime
/// turns them into hulls): every hull vertex lies in the link's capsule, and the capsule
/// is tighter than the bounding sphere.
#[test]
fn shipped_link_hulls_lie_in_their_capsules() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cells/robots");
    let mut stack = vec![root];
    let mut meshes = 0;
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("readable") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let name = path.to_string_lossy().to_string();
            let lower = name.to_ascii_lowercase();
            if !(lower.ends_with(".stl") || lower.ends_with(".obj")) {
                continue;
            }
            let bytes = std::fs::read(&path).expect("readable");
            let shape = crate::mesh::hull(&name, &bytes, [1.0; 3]).expect("a hull");
            let hull = shape.as_convex_polyhedron().expect("a convex polyhedron");
            let capsule = Capsule::of_shape(shape.as_ref()).expect("a capsule");
            assert_contains(&capsule, hull.points(), &name);
            let sphere = shape.compute_local_bounding_sphere();
            assert!(
                volume(&capsule) < 4.0 / 3.0 * std::f64::consts::PI * sphere.radius.powi(3),
                "{name}"
            );
            meshes += 1;
        }
    }
    assert!(meshes >= 17, "{meshes} meshes");
}

fn point() -> impl Strategy<Value = Point> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| Point::new(x, y, z))
}

fn pose(spread: f64) -> impl Strategy<Value = Iso> {
    (
        (-spread..spread, -spread..spread, -spread..spread),
        (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    )
        .prop_map(|((x, y, z), (a, b, c))| Iso::new(Vec3::new(x, y, z), Vec3::new(a, b, c)))
}

/// A hull of random points squeezed along two axes (long like a link), or a box, a
/// cylinder, a ball.
fn shape() -> impl Strategy<Value = SharedShape> {
    prop_oneof![
        (
            prop::collection::vec(point(), 4..40),
            0.05..1.0f64,
            0.05..1.0f64,
            0.05..0.5f64
        )
            .prop_filter_map("a solid hull", |(points, sy, sz, s)| {
                let points: Vec<Point> = points
                    .iter()
                    .map(|p| Point::new(p.x * s, p.y * s * sy, p.z * s * sz))
                    .collect();
                ConvexPolyhedron::from_convex_hull(&points).map(SharedShape::new)
            }),
        (0.01..0.3f64, 0.01..0.3f64, 0.01..0.3f64)
            .prop_map(|(a, b, c)| SharedShape::cuboid(a, b, c)),
        (0.01..0.3f64, 0.01..0.3f64).prop_map(|(h, r)| SharedShape::cylinder(h, r)),
        (0.01..0.3f64).prop_map(SharedShape::ball),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// Random clouds (long, flat, round): every point lies in the fitted capsule.
    #[test]
    fn random_clouds_lie_in_their_capsules(
        points in prop::collection::vec(point(), 1..60),
        sx in 0.001..2.0f64, sy in 0.001..2.0f64, sz in 0.001..2.0f64,
    ) {
        let points: Vec<Point> = points.iter().map(|p| Point::new(p.x * sx, p.y * sy, p.z * sz)).collect();
        let capsule = Capsule::around(&points).expect("points");
        assert_contains(&capsule, &points, "cloud");
    }

    /// The segment–box distance is parry's.
    #[test]
    fn segment_box_distance_is_exact(
        a in point(), b in point(), hx in 0.01..0.5f64, hy in 0.01..0.5f64, hz in 0.01..0.5f64,
    ) {
        let half = Vec3::new(hx, hy, hz);
        let ours = segment_box_distance(&a, &b, &half);
        let theirs = query::distance(
            &Iso::identity(),
            &Segment::new(a, b),
            &Iso::identity(),
            &parry3d_f64::shape::Cuboid::new(half),
        )
        .expect("supported");
        prop_assert!((ours - theirs).abs() < 1e-9, "{} vs {}", ours, theirs);
    }

    /// The capsule bound never exceeds the exact distance, on pairs placed far, near,
    /// touching (moved until their distance is nil) and overlapping.
    #[test]
    fn the_capsule_bound_is_below_the_exact_distance(
        si in shape(), sj in shape(), pi in pose(1.0), pj in pose(1.0), squeeze in 0.0..1.0f64,
    ) {
        let (ci, cj) = (
            Capsule::of_shape(si.as_ref()).expect("a capsule"),
            Capsule::of_shape(sj.as_ref()).expect("a capsule"),
        );
        let (bi, bj) = (si.as_cuboid().map(|c| c.half_extents), sj.as_cuboid().map(|c| c.half_extents));
        let d = query::distance(&pi, si.as_ref(), &pj, sj.as_ref()).expect("supported");
        // Move `j` towards `i` by all of the distance (touching) or past it (overlap).
        let towards = (pi.translation.vector - pj.translation.vector).try_normalize(1e-9).unwrap_or(Vec3::x());
        for shift in [0.0, d * squeeze, d, d + 0.05 * squeeze] {
            let pj = Iso::from_parts((pj.translation.vector + towards * shift).into(), pj.rotation);
            let exact = query::distance(&pi, si.as_ref(), &pj, sj.as_ref()).expect("supported");
            let bound = capsule_bound((&ci, &pi, bi.as_ref()), (&cj, &pj, bj.as_ref()));
            prop_assert!(bound <= exact + 1e-9, "bound {} exact {} shift {}", bound, exact, shift);
        }
    }
}

/// Two rods, 1 m long and 2 cm thick, side by side and turned 45 degrees about z, so
/// that their AABBs and bounding spheres overlap: `gap` metres apart.
fn rods(gap: f64) -> (crate::collision::CollisionWorld, Iso) {
    use crate::collision::{CollisionWorldBuilder, Solid};
    let turn = Iso::rotation(Vec3::z() * std::f64::consts::FRAC_PI_4);
    let rod = || {
        let corners: Vec<Point> = (0..8)
            .map(|k| {
                let s = |bit: usize| if k & (1 << bit) == 0 { -1.0 } else { 1.0 };
                Point::new(s(0) * 0.5, s(1) * 0.01, s(2) * 0.01)
            })
            .collect();
        SharedShape::convex_hull(&corners).expect("a hull")
    };
    let mut b = CollisionWorldBuilder::new();
    b.add_fixed("fixed_rod", turn, rod());
    b.add_object(
        "moving_rod",
        vec![Solid {
            local: Iso::identity(),
            shape: rod(),
        }],
    );
    let at = turn * Iso::translation(0.0, 0.02 + gap, 0.0);
    (b.build().expect("a world"), at)
}

/// A pair whose boxes and spheres overlap but whose capsules are apart is settled
/// without an exact query; a pair closer than the capsules' radii still gets one.
#[test]
fn far_links_are_rejected_without_an_exact_query() {
    use crate::collision::{CollisionScratch, Configuration, ObjectState};
    let mut scratch = CollisionScratch::default();
    let mut ask = |gap: f64| {
        let (world, at) = rods(gap);
        let objects = [ObjectState::free(at)];
        let state = Configuration {
            robots: &[],
            objects: &objects,
        };
        let before = scratch.exact_queries();
        let free = world.is_free(&state, &mut scratch).expect("well-formed");
        let clearance = world
            .clearance(&state, &mut scratch, 0.05)
            .expect("well-formed");
        (
            free,
            clearance.map(|p| p.distance),
            scratch.exact_queries() - before,
        )
    };
    // 10 cm apart: free, farther than the cutoff, and no exact query at all.
    assert_eq!(ask(0.1), (true, None, 0));
    // 1 mm apart (the capsules overlap, the rods do not): both queries run one.
    let (free, distance, queries) = ask(0.001);
    assert!(free);
    assert!((distance.expect("within the cutoff") - 0.001).abs() < 1e-9);
    assert_eq!(queries, 2);
}
