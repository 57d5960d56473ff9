//! What is wrong with a cell's geometry before any arc is checked: an arm whose link
//! touches a fixed body whatever its joints do (a base standing on a table), an arm whose
//! home collides, and a grasp that leaves the object away from the hand or deep inside
//! it.
//!
//! Verification judges every state with the arms that do not move standing at home, so
//! a home that collides makes every check fail for a reason that has nothing to do with
//! the arc, and a base sunk into its table makes every check of that arm fail with the
//! same pair. Both are found here once, named, and reported as such (`cellc build`
//! refuses them, E0421 and E0420, before it verifies anything); the grasps are warnings
//! (W0010), since a grasp may be meant as written.

use cellc_schema::{self as schema, Artifact, EndEffectorId, GraspId, ObjectId};
use parry3d_f64::query;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::collision::{BodyId, Collision};
use crate::math::{iso_from_schema, Iso};
use crate::scene::{Holder, ObjectPlacement, PlacedShape, Scene, SceneScratch};

/// Configurations tried per arm, besides its home, to tell a contact that never goes
/// away from one the arm can move out of.
pub const CONTACT_SAMPLES: u32 = 32;

/// A grasp whose object is farther than this from every solid of the hand, metres, is
/// reported (W0010): a hand holds what it touches (every grasp of the shipped cells
/// touches a solid of the SoftHand model), so 3 cm leaves room for a hand modelled
/// coarsely while a tip frame moved by a link (10 cm and more) is caught.
pub const GRASP_FAR: f64 = 0.03;

/// A grasp whose object's centre lies inside a solid of the hand, more than this from
/// the solid's surface (metres), is reported (W0010). Fingers modelled open overlap what
/// they close on (the SoftHand's thumb sinks 4 cm into the cylinder it holds from the
/// side), so overlap is no sign of a wrong grasp; a centre inside the palm is.
pub const GRASP_DEEP: f64 = 0.001;

/// The seed of the configurations tried, fixed so that the same cell always gives the
/// same findings (it is not the build's seed: these are facts of the cell, not of a run).
const SEED: u64 = 0x5EED_C0DE;

/// A link of an arm that touches a body that never moves (a surface, an obstacle, another
/// arm's base link) in every configuration tried.
#[derive(Clone, Debug, PartialEq)]
pub struct PermanentContact {
    /// The arm.
    pub end_effector: EndEffectorId,
    /// The link, as the collision world names it (`left/lwr_base_link`).
    pub link: String,
    /// The body that never moves (`table`, `right/lwr_base_link`).
    pub fixed: String,
    /// Configurations tried (its home and [`CONTACT_SAMPLES`] others).
    pub tried: u32,
}

/// Two bodies that collide with every arm at home (and no object in the cell), other than
/// the permanent contacts.
#[derive(Clone, Debug, PartialEq)]
pub struct HomeCollision {
    /// The arm whose home it is (the first one of the pair when both are arms).
    pub end_effector: EndEffectorId,
    /// The other arm, when the pair joins two arms.
    pub other: Option<EndEffectorId>,
    /// One body (of `end_effector`).
    pub a: String,
    /// The other.
    pub b: String,
}

/// How a grasp's object sits against its hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Offset {
    /// Farther than [`GRASP_FAR`] from every solid of the hand, by this distance.
    Far {
        /// Metres to the nearest solid.
        distance: f64,
    },
    /// The object's centre inside a solid of the hand, deeper than [`GRASP_DEEP`].
    Deep {
        /// Metres from the centre to the solid's surface.
        depth: f64,
        /// The solid (index into the hand kind's solids, in declaration order).
        solid: usize,
    },
}

/// A grasp that puts its object away from the hand, or deep inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspOffset {
    /// The object.
    pub object: ObjectId,
    /// The grasp.
    pub grasp: GraspId,
    /// The hand kind it is for (index into the artifact's holder kinds).
    pub kind: u32,
    /// How far off.
    pub offset: Offset,
}

/// Everything found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Preflight {
    /// Links that touch a fixed body whatever the arm does.
    pub contacts: Vec<PermanentContact>,
    /// Homes that collide.
    pub homes: Vec<HomeCollision>,
    /// Grasps away from their hands.
    pub grasps: Vec<GraspOffset>,
}

impl Preflight {
    /// Whether verification would judge states against a scene that is wrong whatever
    /// the arc (a permanent contact or a colliding home).
    pub fn blocks_verification(&self) -> bool {
        !self.contacts.is_empty() || !self.homes.is_empty()
    }
}

/// Checks the scene of `artifact` as described in the module documentation.
pub fn preflight(artifact: &Artifact, scene: &Scene) -> Preflight {
    let mut scratch = SceneScratch::default();
    let contacts = permanent_contacts(scene, &mut scratch);
    let permanent: Vec<(&str, &str)> = contacts
        .iter()
        .flat_map(|c| {
            [
                (c.link.as_str(), c.fixed.as_str()),
                (c.fixed.as_str(), c.link.as_str()),
            ]
        })
        .collect();
    let homes = home_collisions(scene, &permanent, &mut scratch);
    Preflight {
        contacts,
        homes,
        grasps: grasp_offsets(artifact, scene),
    }
}

/// The colliding pairs of a state with `arms` moved and everything else at home, no
/// object in the cell. A state the world cannot evaluate gives no pairs: the scene was
/// built from a validated artifact, so that would be a configuration of the wrong length,
/// which the callers never make.
fn collisions(scene: &Scene, arms: &[(u32, &[f64])], scratch: &mut SceneScratch) -> Vec<Collision> {
    let mut out = Vec::new();
    let arms: Vec<(EndEffectorId, &[f64])> =
        arms.iter().map(|&(e, q)| (EndEffectorId(e), q)).collect();
    if scene
        .all_collisions(
            &arms,
            ObjectId(0),
            ObjectPlacement::Absent,
            scratch,
            &mut out,
        )
        .is_err()
    {
        out.clear();
    }
    out
}

/// Whether `body` stays where it is whatever any arm does: a fixed body, or a link on an
/// arm's base frame (frame 0, before the first joint).
fn immobile(scene: &Scene, body: BodyId) -> bool {
    match body {
        BodyId::Fixed(_) => true,
        BodyId::Link { shape, .. } => {
            let robot = scene
                .arm_of(body)
                .and_then(|e| match &scene.holders[e.index()] {
                    Holder::Arm { robot, .. } => scene.robots.get(*robot),
                    _ => None,
                });
            robot
                .and_then(|r| r.shapes().get(shape))
                .is_some_and(|s| s.frame == 0)
        }
        BodyId::Hand { .. } | BodyId::Object(_) => false,
    }
}

fn permanent_contacts(scene: &Scene, scratch: &mut SceneScratch) -> Vec<PermanentContact> {
    let mut found: Vec<PermanentContact> = Vec::new();
    for (e, holder) in scene.holders.iter().enumerate() {
        let Holder::Arm { robot, home, .. } = holder else {
            continue;
        };
        let e = e as u32;
        let robot = &scene.robots[*robot];
        // A body of this arm against one that never moves (a fixed body, another arm's
        // base link): nothing this arm does can part them.
        let against_immobile = |c: &Collision| {
            let ours = |b: BodyId| scene.arm_of(b) == Some(EndEffectorId(e));
            (ours(c.a) && !ours(c.b) && immobile(scene, c.b))
                || (ours(c.b) && !ours(c.a) && immobile(scene, c.a))
        };
        // The pairs at home, then kept only while every other configuration has them too.
        let mut always: Vec<Collision> = collisions(scene, &[(e, home)], scratch)
            .into_iter()
            .filter(against_immobile)
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(SEED ^ u64::from(e));
        let mut q = home.clone();
        for _ in 0..CONTACT_SAMPLES {
            if always.is_empty() {
                break;
            }
            robot.sample_configuration(&mut rng, &mut q);
            let now = collisions(scene, &[(e, &q)], scratch);
            always.retain(|c| now.contains(c));
        }
        for c in always {
            let (a, b) = scene.world.names(&c);
            let (link, other) = if scene.arm_of(c.a) == Some(EndEffectorId(e)) {
                (a, b)
            } else {
                (b, a)
            };
            // A link of several solids, or two base links found from either arm, once.
            let seen = found.iter().any(|f| {
                (f.link == link && f.fixed == other) || (f.link == other && f.fixed == link)
            });
            if !seen {
                found.push(PermanentContact {
                    end_effector: EndEffectorId(e),
                    link: link.to_string(),
                    fixed: other.to_string(),
                    tried: CONTACT_SAMPLES + 1,
                });
            }
        }
    }
    found
}

fn home_collisions(
    scene: &Scene,
    permanent: &[(&str, &str)],
    scratch: &mut SceneScratch,
) -> Vec<HomeCollision> {
    let mut found = Vec::new();
    for c in collisions(scene, &[], scratch) {
        let (a, b) = scene.world.names(&c);
        if permanent.contains(&(a, b)) {
            continue;
        }
        // Fixed bodies never collide with each other (their pairs are allowed), so one
        // side of every pair is an arm's.
        let (arm, other) = match (scene.arm_of(c.a), scene.arm_of(c.b)) {
            (Some(x), y) => (x, y),
            (None, Some(y)) => (y, None),
            (None, None) => continue,
        };
        let (a, b) = if scene.arm_of(c.a) == Some(arm) {
            (a, b)
        } else {
            (b, a)
        };
        // A link of several solids collides once in a report.
        if found.iter().any(|f: &HomeCollision| f.a == a && f.b == b) {
            continue;
        }
        found.push(HomeCollision {
            end_effector: arm,
            other: other.filter(|&o| o != arm),
            a: a.to_string(),
            b: b.to_string(),
        });
    }
    found
}

/// The hand kind a grasp is for: its kind, or the kind of the one end-effector it names,
/// when that kind is a hand with solids.
fn hand_of(artifact: &Artifact, scene: &Scene, grasp: &schema::Grasp) -> Option<u32> {
    let kind = match grasp.holder {
        schema::Holder::Kind(k) => k,
        schema::Holder::EndEffector(e) => artifact.end_effectors.get(e as usize)?.kind?,
    };
    let hand = artifact.holder_kinds.get(kind as usize)?;
    let solids = scene.kind_solids.get(kind as usize)?;
    (hand.class == schema::HolderClass::Hand && !solids.is_empty()).then_some(kind)
}

fn grasp_offsets(artifact: &Artifact, scene: &Scene) -> Vec<GraspOffset> {
    let mut found = Vec::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        let shapes = &scene.object_shapes[o];
        if shapes.is_empty() {
            continue;
        }
        for (g, grasp) in object.grasps.iter().enumerate() {
            let (Some(kind), Some(pose), false) = (
                hand_of(artifact, scene, grasp),
                grasp.pose.as_ref(),
                grasp.rest,
            ) else {
                continue;
            };
            let pose = iso_from_schema(pose);
            let Some(offset) = offset(&scene.kind_solids[kind as usize], shapes, &pose) else {
                continue;
            };
            found.push(GraspOffset {
                object: ObjectId(o as u32),
                grasp: GraspId(g as u32),
                kind,
                offset,
            });
        }
    }
    found
}

/// How an object placed at `pose` in the hand frame sits against the hand's `solids`:
/// [`Offset::Far`] when its nearest solid is more than [`GRASP_FAR`] away, [`Offset::Deep`]
/// when its centre (the middle of its bounding box) is inside a solid more than
/// [`GRASP_DEEP`] from that solid's surface. Fingers modelled open overlap what they
/// close on, so overlap alone is no sign of a wrong grasp; a centre inside the palm is.
/// A pair parry cannot measure is left out rather than guessed.
fn offset(solids: &[PlacedShape], shapes: &[PlacedShape], pose: &Iso) -> Option<Offset> {
    let mut nearest = f64::INFINITY;
    let mut deepest: Option<(f64, usize)> = None;
    for shape in shapes {
        let at = pose * shape.local;
        let centre = at * shape.shape.compute_local_aabb().center();
        for (s, solid) in solids.iter().enumerate() {
            if let Ok(d) = query::distance(
                &solid.local,
                solid.shape.as_ref(),
                &at,
                shape.shape.as_ref(),
            ) {
                nearest = nearest.min(d);
            }
            let projection = solid.shape.project_point(&solid.local, &centre, false);
            if projection.is_inside {
                let depth = (projection.point - centre).norm();
                if deepest.is_none_or(|(d, _)| depth > d) {
                    deepest = Some((depth, s));
                }
            }
        }
    }
    match deepest {
        Some((depth, solid)) if depth > GRASP_DEEP => Some(Offset::Deep { depth, solid }),
        _ if nearest.is_finite() && nearest > GRASP_FAR => Some(Offset::Far { distance: nearest }),
        _ => None,
    }
}
