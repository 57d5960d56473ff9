//! The collision world of a cell: robot links, the hands on their tips, fixed surfaces and
//! obstacles, and the objects, checked against each other in one call.
//!
//! # Model
//!
//! A [`CollisionWorld`] is built once per cell by a [`CollisionWorldBuilder`] and never
//! changes afterwards; everything that moves is handed in per query as a
//! [`Configuration`] (the world poses of every robot's frames, as `Robot::fk_frames`
//! gives them, and the pose and holders of every object). A hand's solids are stored
//! composed with the robot's tip offset, so they move with the last frame like any link
//! and a state cannot give a tip that disagrees with its frames. The world is therefore
//! immutable and `Send + Sync`, and each thread keeps its own [`CollisionScratch`] for
//! the buffers a query needs, so rayon workers check states in parallel without locks and
//! without allocating per call.
//!
//! Every solid is a *body* ([`BodyId`]) with a human name for reports:
//! `left/lwr_link_4` (robot `left`, link `lwr_link_4`), `left/softhand` (a solid of the
//! hand on robot `left`'s tip), `table` (a fixed body), `cylinder` (an object).
//!
//! # Broad phase
//!
//! Sort and sweep: the world-space AABB of every body is computed (fixed bodies once, at
//! build), the bodies are sorted by the AABB's lower bound along the axis on which the
//! AABB centres spread the most in this state, and a sweep visits only pairs whose
//! intervals overlap on that axis; the other two axes are compared next, then the
//! allowed-collision rules, then the bodies' bounding spheres (which reject most of the
//! near-joint pairs of tilted cylinders whose AABBs overlap), and only the surviving pairs
//! reach the exact test (`parry3d_f64::query::intersection_test`). A cell has tens of
//! bodies, so a sort per query costs less than keeping a BVH up to date, and choosing the
//! axis per state keeps the sweep selective whether the arms stand side by side along x
//! or along y. Cylinders (every LWR link) get their AABB in closed form: parry's generic
//! support-map AABB was 70% of a check's time.
//!
//! # Allowed pairs
//!
//! A pair is never tested when:
//! - both bodies are fixed: the cell's furniture cannot move, so whatever it touches it
//!   touches in every state (a bin standing on a table is not a collision);
//! - both are links of one robot on the same frame or on frames joined by a joint
//!   (`adjacent` when the robot is added): adjacent links overlap at their joint by
//!   construction;
//! - one is a hand solid and the other a hand solid or a link of the same robot on the tip
//!   frame or a frame adjacent to it: the hand is bolted onto the tip frame, so it is
//!   treated as part of that frame's body;
//! - the cell allowed it by name ([`CollisionWorldBuilder::allow`]), e.g. an arm base
//!   standing on a bench;
//! - and, per state, an object and one of its holders ([`ObjectState::holders`]): an
//!   object held by a robot touches that robot's hand solids and its tip frame's links
//!   (for a conveyor, the carriage it rests on), never anything further up the arm; an
//!   object resting on a fixed surface touches that surface. A handoff lists both robots.
//!
//! Resting contact is handled by allowing the pair rather than by testing with a
//! negative margin: a rest pose puts the object's face exactly on the surface's top face,
//! where the exact test's answer is numerical noise, and no margin would be right for
//! both a box (face contact) and a tilted shape. The cost is that an object sunk into its
//! own support is not reported; its pose comes from the support and the resting pose, so
//! that is a modelling error for the compiler to catch, not a planning state.
//!
//! Two limits of the exact test are worth knowing: triangle meshes are surfaces to parry,
//! so a body entirely inside a mesh (without touching its triangles) is not reported; and
//! a pair of shapes parry has no algorithm for is an error
//! ([`CollisionError::Unsupported`]), never silently collision-free.
//!
//! # Files
//!
//! The types of a state and of a report are here; `error.rs` has the two error types,
//! `build.rs` the builder (bodies, names, the static allowed pairs), `world.rs` the
//! queries, `broad_phase.rs` the placing of bodies and the sweep, and `swept.rs` the
//! free radius of a state along a segment, for sound motion checks, with the bodies'
//! travel bounds in `bounds.rs`. `home.rs` places the cell at home once per scene (every
//! arm at home, the furniture) and `frozen.rs` answers queries that place only what is
//! not standing, so a check's cost follows the moving bodies, not the size of the cell;
//! `batch.rs` judges several states of one motion at once on the same standing set.

mod batch;
mod bounds;
mod boxes;
mod broad_phase;
mod build;
mod capsule;
mod error;
mod frozen;
mod home;
mod hull;
mod swept;
mod tip;
mod world;

use parry3d_f64::shape::SharedShape;

use crate::math::Iso;

pub(crate) use batch::BatchScratch;
pub(crate) use bounds::{AxisRef, JointReach, SweepBounds};
pub use build::CollisionWorldBuilder;
pub(crate) use build::Mount;
pub use error::{BuildError, CollisionError};
pub(crate) use frozen::{Frozen, Standing};
pub(crate) use home::Home;
pub use world::{CollisionScratch, CollisionWorld};

/// One solid of the collision world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyId {
    /// Shape `shape` of robot `robot`'s link list (the robot's `shapes()` order).
    Link {
        /// Robot index, in the order robots were added.
        robot: usize,
        /// Index into the robot's shape list.
        shape: usize,
    },
    /// Solid `solid` of the hand on robot `robot`'s tip.
    Hand {
        /// Robot index.
        robot: usize,
        /// Index into the hand's solids.
        solid: usize,
    },
    /// A fixed body (surface or obstacle), in the order added.
    Fixed(usize),
    /// An object, in the order added (any of its solids: an object is one body to
    /// reports, whatever it is made of).
    Object(usize),
}

/// A shape placed in a frame (a hand solid in the hand frame, for instance).
#[derive(Clone, Debug)]
pub struct Solid {
    /// Pose of the shape in the frame.
    pub local: Iso,
    /// The shape.
    pub shape: SharedShape,
}

/// The hand mounted on a robot's tip: its kind's name (for reports) and its solids in the
/// hand frame, which is the robot's tip link (`frames[n] * tip_offset`).
#[derive(Clone, Debug)]
pub struct Hand {
    /// Name of the hand kind, e.g. `softhand`; solids are reported as `robot/name`.
    pub name: String,
    /// Collision solids in the hand frame.
    pub solids: Vec<Solid>,
}

/// Who holds or supports an object in a state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Holder {
    /// Robot `i`: the object may touch its hand's solids and the links on its last frame
    /// (the flange, or a conveyor's carriage), nothing further up the chain.
    Robot(usize),
    /// Fixed body `i` (the surface the object rests on).
    Fixed(usize),
}

/// Up to [`Holders::CAPACITY`] holders of one object, stored inline so a state costs no
/// allocation. Two cover most cases of the method (one holder; a handoff, two hands; a
/// pick or place, a hand and the surface); a carry from one surface onto another touches
/// both at its ends, and a hand that could not retreat may still be on it: four.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Holders {
    items: [Option<Holder>; Holders::CAPACITY],
}

impl Holders {
    /// How many holders fit.
    pub const CAPACITY: usize = 4;

    /// No holder (an object lying free, e.g. a start pose given as a world pose).
    pub const NONE: Holders = Holders {
        items: [None; Holders::CAPACITY],
    };

    /// One holder.
    pub fn one(h: Holder) -> Holders {
        Holders::NONE.with(h)
    }

    /// These holders plus `h`. Adding a holder already present, or more than
    /// [`Holders::CAPACITY`], changes nothing.
    pub fn with(mut self, h: Holder) -> Holders {
        if self.contains(h) {
            return self;
        }
        if let Some(slot) = self.items.iter_mut().find(|s| s.is_none()) {
            *slot = Some(h);
        }
        self
    }

    /// Whether `h` is one of them.
    pub fn contains(&self, h: Holder) -> bool {
        self.items.contains(&Some(h))
    }

    /// The holders.
    pub fn iter(&self) -> impl Iterator<Item = Holder> + '_ {
        self.items.iter().flatten().copied()
    }
}

/// The moving part of a state for one object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectState {
    /// World pose of the object frame; `None` leaves the object out of the check (not in
    /// the cell yet, or irrelevant to the question asked).
    pub pose: Option<Iso>,
    /// Who holds or supports it; the object is allowed to touch them.
    pub holders: Holders,
}

impl ObjectState {
    /// Not in the scene.
    pub fn absent() -> ObjectState {
        ObjectState {
            pose: None,
            holders: Holders::NONE,
        }
    }

    /// At `pose`, touching nothing on purpose.
    pub fn free(pose: Iso) -> ObjectState {
        ObjectState {
            pose: Some(pose),
            holders: Holders::NONE,
        }
    }

    /// Resting at `pose` on fixed body `surface`.
    pub fn resting(pose: Iso, surface: usize) -> ObjectState {
        ObjectState {
            pose: Some(pose),
            holders: Holders::one(Holder::Fixed(surface)),
        }
    }

    /// Held by robot `robot` whose tip is at `tip`, in grasp `grasp` (the object pose in
    /// the hand frame): the object is at `tip * grasp`.
    pub fn held(robot: usize, tip: &Iso, grasp: &Iso) -> ObjectState {
        ObjectState {
            pose: Some(tip * grasp),
            holders: Holders::one(Holder::Robot(robot)),
        }
    }

    /// The same object, also touched by `h` (the second hand of a handoff, the surface
    /// of a pick).
    pub fn also_held_by(mut self, h: Holder) -> ObjectState {
        self.holders = self.holders.with(h);
        self
    }
}

/// A state to check, robots and objects in the order they were added to the world.
#[derive(Clone, Copy, Debug)]
pub struct Configuration<'a> {
    /// Per robot, the world poses of its frames `0..=n` (what `Robot::fk_frames` gives
    /// for the robot's base placement and joint values).
    pub robots: &'a [&'a [Iso]],
    /// Per object.
    pub objects: &'a [ObjectState],
}

/// Two bodies that intersect, `a < b` (so a pair has one spelling). Names:
/// [`CollisionWorld::name`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Collision {
    /// One body.
    pub a: BodyId,
    /// The other.
    pub b: BodyId,
}

/// The closest non-allowed pair found by [`CollisionWorld::clearance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proximity {
    /// One body.
    pub a: BodyId,
    /// The other.
    pub b: BodyId,
    /// Their distance in metres; 0 when they intersect.
    pub distance: f64,
}
