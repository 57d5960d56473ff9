//! Placing the bodies of a state (world poses, AABBs, bounding spheres) and the sort and
//! sweep that hands the exact test only the pairs that may touch (see [the module](super)
//! documentation for the order of the rejections).

use parry3d_f64::bounding_volume::Aabb;

use super::build::{Body, Mount};
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{BodyId, CollisionError, Configuration, Holder};
use crate::math::{Iso, Point, Vec3};

impl CollisionWorld {
    /// Checks the state's shape, then computes every present body's world pose and AABB
    /// (loosened by `margin(body index)`, which the sweep's sphere test adds too) into the
    /// scratch, and the list of present bodies.
    pub(super) fn place(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        margin: impl Fn(usize) -> f64,
    ) -> Result<(), CollisionError> {
        self.check_state(state)?;
        let n = self.bodies.len();
        scratch.poses.clear();
        scratch.aabbs.clear();
        scratch.centres.clear();
        scratch.margins.clear();
        scratch.order.clear();
        scratch.poses.reserve(n);
        scratch.aabbs.reserve(n);
        scratch.centres.reserve(n);
        scratch.margins.reserve(n);
        scratch.order.reserve(n);
        for i in 0..n {
            match self.place_body(state, i, margin(i))? {
                Some(placed) => {
                    scratch.margins.push(placed.margin);
                    scratch.centres.push(placed.centre);
                    scratch.poses.push(placed.pose);
                    scratch.aabbs.push(placed.aabb);
                    scratch.order.push(i as u32);
                }
                None => {
                    // Absent: kept in the buffers (indices stay body indices) but not in
                    // the sweep order.
                    scratch.poses.push(self.bodies[i].local);
                    scratch.aabbs.push(Aabb::new_invalid());
                    scratch.centres.push(Point::origin());
                    scratch.margins.push(0.0);
                }
            }
        }
        scratch.frozen = 0;
        Ok(())
    }

    /// Refuses a state whose shape is not this world's: robot, frame and object counts,
    /// and holders that exist.
    pub(super) fn check_state(&self, state: &Configuration<'_>) -> Result<(), CollisionError> {
        if state.robots.len() != self.robots.len() {
            return Err(CollisionError::RobotCount {
                expected: self.robots.len(),
                found: state.robots.len(),
            });
        }
        for (info, rs) in self.robots.iter().zip(state.robots) {
            if rs.len() != info.frames {
                return Err(CollisionError::FrameCount {
                    robot: info.name.clone(),
                    expected: info.frames,
                    found: rs.len(),
                });
            }
        }
        if state.objects.len() != self.objects.len() {
            return Err(CollisionError::ObjectCount {
                expected: self.objects.len(),
                found: state.objects.len(),
            });
        }
        for (o, os) in state.objects.iter().enumerate() {
            for h in os.holders.iter() {
                let known = match h {
                    Holder::Robot(r) => r < self.robots.len(),
                    Holder::Fixed(f) => f < self.fixed.len(),
                };
                if !known {
                    return Err(CollisionError::UnknownHolder {
                        object: self.object_names[o].clone(),
                        holder: h,
                    });
                }
            }
        }

        Ok(())
    }

    /// Body `i` placed in `state`: its world pose, its AABB grown by `margin` (when
    /// positive), its sphere's world centre; `None` when it belongs to an absent object.
    #[inline]
    pub(super) fn place_body(
        &self,
        state: &Configuration<'_>,
        i: usize,
        margin: f64,
    ) -> Result<Option<PlacedBody>, CollisionError> {
        let b = &self.bodies[i];
        let pose = match b.mount {
            Mount::Frame { robot, frame } => state.robots[robot][frame] * b.local,
            Mount::Fixed => b.local,
            Mount::Object { object } => match state.objects[object].pose {
                Some(p) => p * b.local,
                None => return Ok(None),
            },
        };
        self.placed_at(i, pose, margin).map(Some)
    }

    /// Body `i` at world pose `pose`: [`CollisionWorld::place_body`] once the pose is
    /// known.
    #[inline]
    pub(super) fn placed_at(
        &self,
        i: usize,
        pose: Iso,
        margin: f64,
    ) -> Result<PlacedBody, CollisionError> {
        let b = &self.bodies[i];
        let aabb = match (b.fixed_aabb, b.cylinder, b.hull_aabb) {
            (Some(a), _, _) => a,
            (None, Some((h, r)), _) => cylinder_aabb(&pose, h, r),
            (None, None, Some(local)) => local.transform_by(&pose),
            (None, None, None) => b.shape.compute_aabb(&pose),
        };
        if !aabb_finite(&aabb) {
            return Err(CollisionError::NonFinite {
                body: b.name.clone(),
            });
        }
        Ok(PlacedBody {
            pose,
            aabb: grow(&aabb, margin),
            centre: pose * b.sphere_centre,
            margin: margin.max(0.0),
        })
    }

    /// Sort and sweep over the placed bodies; calls `visit` for every pair whose AABBs
    /// overlap and that is not allowed, until it says stop.
    pub(super) fn sweep(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        mut visit: impl FnMut(usize, usize, &CollisionScratch) -> Result<Visit, CollisionError>,
    ) -> Result<(), CollisionError> {
        let axis = spread_axis(&scratch.aabbs, &scratch.order);
        let (o1, o2) = ((axis + 1) % 3, (axis + 2) % 3);
        {
            let aabbs = &scratch.aabbs;
            scratch.order.sort_unstable_by(|&a, &b| {
                aabbs[a as usize].mins[axis].total_cmp(&aabbs[b as usize].mins[axis])
            });
        }
        let scratch = &*scratch;
        let order = &scratch.order;
        for (k, &i) in order.iter().enumerate() {
            let i = i as usize;
            let ai = &scratch.aabbs[i];
            for &j in &order[k + 1..] {
                let j = j as usize;
                let aj = &scratch.aabbs[j];
                if aj.mins[axis] > ai.maxs[axis] {
                    break;
                }
                if aj.mins[o1] > ai.maxs[o1]
                    || ai.mins[o1] > aj.maxs[o1]
                    || aj.mins[o2] > ai.maxs[o2]
                    || ai.mins[o2] > aj.maxs[o2]
                {
                    continue;
                }
                if self.allowed.get(i, j) || self.held_pair(state, i, j) {
                    continue;
                }
                // Bounding spheres last: links are long cylinders whose AABBs overlap
                // near every joint once tilted, and this rejects most of those pairs for
                // the price of a distance instead of a GJK run.
                let reach = self.bodies[i].sphere_radius
                    + self.bodies[j].sphere_radius
                    + scratch.margins[i]
                    + scratch.margins[j];
                if (scratch.centres[i] - scratch.centres[j]).norm_squared() > reach * reach {
                    continue;
                }
                // Exact tests always see the pair in body order, so a borderline answer
                // (touching, a distance's last bits) does not depend on the sweep axis.
                if let Visit::Stop = visit(i.min(j), i.max(j), scratch)? {
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// The per-state rule: an object may touch its holders.
    #[inline]
    pub(super) fn held_pair(&self, state: &Configuration<'_>, i: usize, j: usize) -> bool {
        let check = |o: &Body, other: &Body| -> bool {
            let Mount::Object { object } = o.mount else {
                return false;
            };
            let holders = &state.objects[object].holders;
            match other.id {
                BodyId::Fixed(f) => holders.contains(Holder::Fixed(f)),
                _ => other
                    .grips_for
                    .is_some_and(|r| holders.contains(Holder::Robot(r))),
            }
        };
        let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
        check(bi, bj) || check(bj, bi)
    }
}

/// One body where a state puts it (see [`CollisionWorld::place_body`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct PlacedBody {
    pub(super) pose: Iso,
    pub(super) aabb: Aabb,
    pub(super) centre: Point,
    pub(super) margin: f64,
}

/// `aabb` grown by `margin` on every side (unchanged when `margin` is not positive): how
/// every query grows a body by how far it may travel or by half a clearance cutoff.
pub(super) fn grow(aabb: &Aabb, margin: f64) -> Aabb {
    let mut a = *aabb;
    if margin > 0.0 {
        a.mins -= Vec3::repeat(margin);
        a.maxs += Vec3::repeat(margin);
    }
    a
}

/// The exact AABB of a parry cylinder (axis along its local y) at `pose`: along world
/// axis i it reaches `h |a_i| + r sqrt(1 - a_i²)` from its centre, for the unit axis `a`.
fn cylinder_aabb(pose: &Iso, half_height: f64, radius: f64) -> Aabb {
    let a = pose.rotation * Vec3::y();
    let c = Point::from(pose.translation.vector);
    let e = Vec3::from_fn(|i, _| {
        half_height * a[i].abs() + radius * (1.0 - a[i] * a[i]).max(0.0).sqrt()
    });
    Aabb::new(c - e, c + e)
}

pub(super) fn aabb_finite(a: &Aabb) -> bool {
    a.mins.iter().chain(a.maxs.iter()).all(|v| v.is_finite())
}

/// The axis along which the AABB centres of the listed bodies spread the most (largest
/// variance), so the sweep along it separates the most pairs.
fn spread_axis(aabbs: &[Aabb], order: &[u32]) -> usize {
    if order.len() < 2 {
        return 0;
    }
    let mut sum = Vec3::zeros();
    let mut sq = Vec3::zeros();
    for &i in order {
        let a = &aabbs[i as usize];
        let c = (a.mins.coords + a.maxs.coords) / 2.0;
        sum += c;
        sq += c.component_mul(&c);
    }
    let n = order.len() as f64;
    let var = sq / n - (sum / n).component_mul(&(sum / n));
    let mut axis = 0;
    for k in 1..3 {
        if var[k] > var[axis] {
            axis = k;
        }
    }
    axis
}

#[cfg(test)]
mod tests {
    //! The broad phase against brute force, and the closed-form cylinder AABB against
    //! parry's.

    use parry3d_f64::query;
    use parry3d_f64::shape::SharedShape;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::super::{Collision, CollisionWorldBuilder, Hand, ObjectState, Solid};
    use super::*;
    use crate::robot::LinkShape;

    fn random_pose(rng: &mut ChaCha8Rng, spread: f64) -> Iso {
        let t = Vec3::from_fn(|_, _| rng.random_range(-spread..spread));
        let axis = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        Iso::new(t, axis * rng.random_range(0.0..3.0))
    }

    fn random_shape(rng: &mut ChaCha8Rng) -> SharedShape {
        let s: [f64; 3] = std::array::from_fn(|_| rng.random_range(0.02..0.3));
        match rng.random_range(0..3) {
            0 => SharedShape::ball(s[0]),
            1 => SharedShape::cuboid(s[0], s[1], s[2]),
            _ => SharedShape::cylinder(s[0], s[1]),
        }
    }

    #[test]
    fn cylinder_aabb_is_parrys() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for _ in 0..1000 {
            let pose = random_pose(&mut rng, 2.0);
            let (h, r) = (rng.random_range(0.01..1.0), rng.random_range(0.01..1.0));
            let ours = cylinder_aabb(&pose, h, r);
            let parry = SharedShape::cylinder(h, r).compute_aabb(&pose);
            assert!((ours.mins - parry.mins).norm() < 1e-9, "{ours:?} {parry:?}");
            assert!((ours.maxs - parry.maxs).norm() < 1e-9, "{ours:?} {parry:?}");
        }
    }

    /// Every pair, no broad phase: the reference for the sweep.
    fn brute_force(
        world: &CollisionWorld,
        state: &Configuration<'_>,
        cutoff: Option<f64>,
    ) -> (Vec<Collision>, Option<(f64, Collision)>) {
        let mut scratch = CollisionScratch::default();
        world
            .place(state, &mut scratch, |_| 0.0)
            .expect("well-formed");
        let mut hits = Vec::new();
        let mut best: Option<(f64, Collision)> = None;
        for i in 0..world.bodies.len() {
            for j in (i + 1)..world.bodies.len() {
                let present = |k: usize| match world.bodies[k].mount {
                    Mount::Object { object } => state.objects[object].pose.is_some(),
                    _ => true,
                };
                if !present(i)
                    || !present(j)
                    || world.allowed.get(i, j)
                    || world.held_pair(state, i, j)
                {
                    continue;
                }
                let (pi, pj) = (&scratch.poses[i], &scratch.poses[j]);
                let (si, sj) = (
                    world.bodies[i].shape.as_ref(),
                    world.bodies[j].shape.as_ref(),
                );
                let pair = world.collision(i, j);
                if query::intersection_test(pi, si, pj, sj).expect("supported") {
                    hits.push(pair);
                }
                if let Some(cutoff) = cutoff {
                    let d = query::distance(pi, si, pj, sj).expect("supported");
                    if d <= cutoff && best.is_none_or(|(bd, bp)| d < bd || (d == bd && pair < bp)) {
                        best = Some((d, pair));
                    }
                }
            }
        }
        hits.sort_unstable();
        hits.dedup();
        (hits, best)
    }

    #[test]
    fn sweep_finds_what_brute_force_finds() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut scratch = CollisionScratch::default();
        let mut out = Vec::new();
        let mut collisions_seen = 0;
        for _ in 0..200 {
            let mut b = CollisionWorldBuilder::new();
            // A four-frame chain with two solids per frame and a hand.
            let shapes = (0..8)
                .map(|k| LinkShape {
                    link: format!("link_{}", k / 2),
                    frame: k / 2,
                    local: random_pose(&mut rng, 0.2),
                    shape: random_shape(&mut rng),
                })
                .collect();
            let hand = Hand {
                name: "hand".into(),
                solids: (0..2)
                    .map(|_| Solid {
                        local: random_pose(&mut rng, 0.1),
                        shape: random_shape(&mut rng),
                    })
                    .collect(),
            };
            b.add_chain(
                "arm",
                4,
                random_pose(&mut rng, 0.1),
                shapes,
                |a, c| a.abs_diff(c) <= 1,
                Some(hand),
            );
            for k in 0..4 {
                b.add_fixed(
                    &format!("f{k}"),
                    random_pose(&mut rng, 1.0),
                    random_shape(&mut rng),
                );
            }
            for k in 0..6 {
                // Object 5 has no solids; the others one or two.
                let solids = (0..[1, 2, 1, 2, 1, 0][k])
                    .map(|_| Solid {
                        local: random_pose(&mut rng, 0.1),
                        shape: random_shape(&mut rng),
                    })
                    .collect();
                b.add_object(&format!("o{k}"), solids);
            }
            b.allow("o0", "arm");
            let world = b.build().expect("valid world");
            let frames: Vec<Iso> = (0..4).map(|_| random_pose(&mut rng, 1.0)).collect();
            let objects: Vec<ObjectState> = (0..6)
                .map(|k| {
                    let pose = random_pose(&mut rng, 1.0);
                    match k {
                        0 => ObjectState::absent(),
                        1 => ObjectState::held(0, &frames[3], &pose),
                        2 => ObjectState::resting(pose, 1).also_held_by(Holder::Robot(0)),
                        _ => ObjectState::free(pose),
                    }
                })
                .collect();
            let robots: [&[Iso]; 1] = [&frames];
            let state = Configuration {
                robots: &robots,
                objects: &objects,
            };
            let (expected, closest) = brute_force(&world, &state, Some(0.3));
            world
                .all_collisions(&state, &mut scratch, &mut out)
                .expect("well-formed");
            assert_eq!(out, expected);
            let first = world
                .first_collision(&state, &mut scratch)
                .expect("well-formed");
            assert_eq!(first.is_some(), !expected.is_empty());
            if let Some(c) = first {
                assert!(expected.contains(&c));
            }
            let near = world
                .clearance(&state, &mut scratch, 0.3)
                .expect("well-formed");
            assert_eq!(near.map(|p| (p.a, p.b)), closest.map(|(_, p)| (p.a, p.b)));
            if let (Some(p), Some((d, _))) = (near, closest) {
                assert_eq!(p.distance, d);
            }
            collisions_seen += expected.len();
        }
        // The scenes are dense enough to exercise both answers.
        assert!(collisions_seen > 100, "{collisions_seen}");
    }
}
