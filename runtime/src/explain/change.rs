//! The changes a suggestion is made of: edits of named items of the cell's source, with
//! how the plan would use them, and the source places they concern.

use cellc_schema::{Aabb, Artifact, EndEffectorId, GraspId, ObjectId, SpanId, WorkspaceId};

use super::LostArc;

/// One change to the cell, with how the plan would use it. Each is an edit of a named item
/// of the cell's source (the object's transitions, an `adjacent` line, an end-effector's
/// `reaches` list, an arm's `reach` box, an `allow contact` line), never of a derived
/// workspace's name.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// Declare `transition from_grasp <-> to_grasp` in the object, or, when `reverse_of`
    /// is given, the missing direction `from_grasp -> to_grasp` of that declaration.
    AddTransition {
        /// Grasp given up on the way to the goal.
        from_grasp: GraspId,
        /// Grasp taken.
        to_grasp: GraspId,
        /// The existing one-way declaration `to_grasp -> from_grasp` to make two-way, if
        /// any.
        reverse_of: Option<SpanId>,
        /// Every distinct exchange the plan would make with it, in path order (one
        /// two-way declaration may serve twice).
        exchanges: Vec<Exchange>,
    },
    /// Declare `adjacent a b` (two declared workspaces).
    AddAdjacency {
        /// A workspace.
        a: WorkspaceId,
        /// The other.
        b: WorkspaceId,
        /// The hand the plan would carry the object with between them.
        carrier: Option<EndEffectorId>,
    },
    /// Add a declared workspace to the `reaches` list of a movable end-effector without
    /// geometry.
    ExtendReaches {
        /// The end-effector.
        end_effector: EndEffectorId,
        /// The workspace to add.
        workspace: WorkspaceId,
        /// The end-effectors it would exchange the object with there.
        meets: Vec<EndEffectorId>,
    },
    /// Grow one of an arm's reach boxes (a `reach` line) so that it covers the boxes of a
    /// workspace the arm does not reach. The workspace is given for the graph; when it is
    /// derived from reach its name changes with the edit, so what to cover is `region`.
    GrowReach {
        /// The arm.
        end_effector: EndEffectorId,
        /// The reach box to grow (index into the end-effector's `reach_boxes`, the one
        /// nearest the workspace); `None` when the arm has none (then a `reach` line with
        /// `grown` is added).
        reach_box: Option<u32>,
        /// The box it becomes: the smallest one holding the old box and `region`, metres.
        grown: Aabb,
        /// The workspace's boxes, which the reach must cover, metres.
        region: Vec<Aabb>,
        /// The workspace.
        workspace: WorkspaceId,
        /// How far the reach boxes are from the workspace's boxes, metres (None: the arm
        /// has no reach box).
        distance: Option<f64>,
        /// The end-effectors it would exchange the object with there.
        meets: Vec<EndEffectorId>,
    },
    /// Declare `allow contact a b`: arcs were lost because these two bodies collide, and
    /// verification and planning would ignore that contact.
    AllowContact {
        /// A body.
        a: BodyName,
        /// The other.
        b: BodyName,
        /// The arcs lost for that collision, which the plan would use again.
        arcs: Vec<LostArc>,
    },
}

/// A collision body as `allow contact` names it: an end-effector (an arm with its hand, a
/// surface's slab), an obstacle, an object, or a part of an arm (`left.lwr_link_7`,
/// `left.softhand`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct BodyName {
    /// The end-effector, obstacle or object.
    pub owner: String,
    /// The arm's link or hand kind.
    pub part: Option<String>,
}

impl BodyName {
    /// The body the collision world calls `name` (`arm/link` for a part of an arm), when
    /// the cell has something of that name to write.
    pub fn of(artifact: &Artifact, name: &str) -> Option<BodyName> {
        let (owner, part) = match name.split_once('/') {
            Some((owner, part)) if !part.is_empty() => (owner, Some(part)),
            Some(_) => return None,
            None => (name, None),
        };
        let end_effector = artifact.end_effectors.iter().any(|e| e.name == owner);
        let other = artifact.obstacles.iter().any(|(o, _)| o == owner)
            || artifact.objects.iter().any(|o| o.name == owner);
        let known = end_effector || (part.is_none() && other);
        known.then(|| BodyName {
            owner: owner.to_string(),
            part: part.map(str::to_string),
        })
    }
}

/// An exchange of the object between two end-effectors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Exchange {
    /// Who gives it up.
    pub giver: EndEffectorId,
    /// Who takes it.
    pub taker: EndEffectorId,
    /// Where.
    pub workspace: WorkspaceId,
}

impl Change {
    /// The source places the change edits or concerns: the one-way transition to make
    /// two-way or the two grasps to join, the two workspaces, the end-effector, or the
    /// end-effectors whose bodies collide.
    pub fn places(&self, artifact: &Artifact, object: ObjectId) -> Vec<SpanId> {
        let obj = artifact.objects.get(object.index());
        let grasp = |g: GraspId| obj.and_then(|o| o.grasps.get(g.index())).map(|x| x.span);
        let workspace = |w: WorkspaceId| artifact.workspaces.get(w.index()).map(|x| x.span);
        let end_effector = |e: EndEffectorId| artifact.end_effectors.get(e.index()).map(|x| x.span);
        let spans: Vec<Option<u32>> = match self {
            Change::AddTransition {
                reverse_of: Some(s),
                ..
            } => vec![Some(s.0)],
            Change::AddTransition {
                from_grasp,
                to_grasp,
                ..
            } => vec![grasp(*from_grasp), grasp(*to_grasp)],
            Change::AddAdjacency { a, b, .. } => vec![workspace(*a), workspace(*b)],
            Change::ExtendReaches {
                end_effector: e, ..
            }
            | Change::GrowReach {
                end_effector: e, ..
            } => vec![end_effector(*e)],
            // The end-effectors whose bodies collide (obstacles and objects have no line).
            Change::AllowContact { a, b, .. } => [a, b]
                .iter()
                .map(|body| {
                    let e = artifact.end_effectors.iter().find(|e| e.name == body.owner);
                    e.map(|e| e.span)
                })
                .collect(),
        };
        let mut out: Vec<SpanId> = spans.into_iter().flatten().map(SpanId).collect();
        out.dedup();
        out
    }
}

/// A set of changes that, together, connect the start to the goal.
#[derive(Clone, Debug, PartialEq)]
pub struct Suggestion {
    /// The changes, all needed.
    pub changes: Vec<Change>,
    /// Cost of the cheapest plan once the changes are made (sum of arc weights).
    pub cost: f64,
}
