//! Names to ids, once, at the edge.
//!
//! People and task planners name things (`cylinder`, `left.top`, `ws_left_table`); the
//! planner works on typed ids. This module is the one place where a name becomes an id.
//! An unknown name is a [`LocateError`] that carries the name and every name it could
//! have been, so the caller can say "did you mean" without the runtime choosing words.

use cellc_schema::{Artifact, EndEffectorId, GraspId, ObjectId, WorkspaceId};

use super::{Goal, GoalByName, LocateError, Placement, PlacementByName, Request};

/// The object named `name`.
pub fn object(artifact: &Artifact, name: &str) -> Result<ObjectId, LocateError> {
    position(artifact.objects.iter().map(|o| o.name.as_str()), name)
        .map(ObjectId)
        .ok_or_else(|| LocateError::UnknownObject {
            name: name.to_string(),
            known: artifact.objects.iter().map(|o| o.name.clone()).collect(),
        })
}

/// The end-effector named `name`.
pub fn end_effector(artifact: &Artifact, name: &str) -> Result<EndEffectorId, LocateError> {
    position(artifact.end_effectors.iter().map(|e| e.name.as_str()), name)
        .map(EndEffectorId)
        .ok_or_else(|| LocateError::UnknownHolder {
            name: name.to_string(),
            known: artifact
                .end_effectors
                .iter()
                .map(|e| e.name.clone())
                .collect(),
        })
}

/// The workspace named `name`.
pub fn workspace(artifact: &Artifact, name: &str) -> Result<WorkspaceId, LocateError> {
    position(artifact.workspaces.iter().map(|w| w.name.as_str()), name)
        .map(WorkspaceId)
        .ok_or_else(|| LocateError::UnknownWorkspace {
            name: name.to_string(),
            known: artifact.workspaces.iter().map(|w| w.name.clone()).collect(),
        })
}

/// The grasp (or resting pose) of `object` named `name`, which `holder` must be able to
/// hold: grasps are scoped per object, and the error lists the holder's own.
pub fn grasp(
    artifact: &Artifact,
    object: ObjectId,
    holder: EndEffectorId,
    name: &str,
) -> Result<GraspId, LocateError> {
    let holdable = super::locate::grasps_of(artifact, object, holder);
    let grasps = &artifact.objects[object.index()].grasps;
    holdable
        .iter()
        .copied()
        .find(|&g| grasps[g.index()].name == name)
        .ok_or_else(|| LocateError::UnknownGrasp {
            holder: artifact.end_effectors[holder.index()].name.clone(),
            name: name.to_string(),
            known: holdable
                .iter()
                .map(|&g| grasps[g.index()].name.clone())
                .collect(),
        })
}

/// A placement of `object` with its names resolved.
pub fn placement(
    artifact: &Artifact,
    object: ObjectId,
    p: &PlacementByName,
) -> Result<Placement, LocateError> {
    let holder = end_effector(artifact, &p.holder)?;
    let workspace = p
        .workspace
        .as_deref()
        .map(|w| workspace(artifact, w))
        .transpose()?;
    let grasp = p
        .grasp
        .as_deref()
        .map(|g| grasp(artifact, object, holder, g))
        .transpose()?;
    Ok(Placement {
        holder,
        grasp,
        workspace,
        pose: p.pose,
    })
}

/// A goal for `object` with its names resolved.
pub fn goal(artifact: &Artifact, object: ObjectId, g: &GoalByName) -> Result<Goal, LocateError> {
    Ok(match g {
        GoalByName::Placement(p) => Goal::Placement(placement(artifact, object, p)?),
        GoalByName::Workspace {
            workspace: w,
            holder,
        } => Goal::Workspace {
            workspace: workspace(artifact, w)?,
            holder: holder
                .as_deref()
                .map(|h| end_effector(artifact, h))
                .transpose()?,
        },
    })
}

/// Checks that every id of a request exists in the artifact, so that nothing after it
/// indexes with an id a caller made up.
pub fn check_request(artifact: &Artifact, request: &Request) -> Result<(), LocateError> {
    let object = request.object;
    let Some(obj) = artifact.objects.get(object.index()) else {
        return Err(LocateError::NoSuchId {
            kind: IdKind::Object,
            id: object.0,
        });
    };
    let placement = |p: &Placement| -> Result<(), LocateError> {
        if p.holder.index() >= artifact.end_effectors.len() {
            return Err(LocateError::NoSuchId {
                kind: IdKind::EndEffector,
                id: p.holder.0,
            });
        }
        if let Some(w) = p
            .workspace
            .filter(|w| w.index() >= artifact.workspaces.len())
        {
            return Err(LocateError::NoSuchId {
                kind: IdKind::Workspace,
                id: w.0,
            });
        }
        if let Some(g) = p.grasp.filter(|g| g.index() >= obj.grasps.len()) {
            return Err(LocateError::NoSuchId {
                kind: IdKind::Grasp,
                id: g.0,
            });
        }
        if p.pose.is_some_and(|pose| !crate::math::is_finite(&pose)) {
            return Err(LocateError::NonFinitePose);
        }
        Ok(())
    };
    placement(&request.start)?;
    match &request.goal {
        Goal::Placement(p) => placement(p),
        Goal::Workspace { workspace, holder } => {
            if workspace.index() >= artifact.workspaces.len() {
                return Err(LocateError::NoSuchId {
                    kind: IdKind::Workspace,
                    id: workspace.0,
                });
            }
            match holder.filter(|h| h.index() >= artifact.end_effectors.len()) {
                Some(h) => Err(LocateError::NoSuchId {
                    kind: IdKind::EndEffector,
                    id: h.0,
                }),
                None => Ok(()),
            }
        }
    }
}

/// What kind of element an id that does not exist was meant to name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IdKind {
    /// An object.
    Object,
    /// An end-effector.
    EndEffector,
    /// A workspace.
    Workspace,
    /// A grasp of the object.
    Grasp,
}

impl std::fmt::Display for IdKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            IdKind::Object => "object",
            IdKind::EndEffector => "end-effector",
            IdKind::Workspace => "workspace",
            IdKind::Grasp => "grasp",
        })
    }
}

fn position<'a>(mut names: impl Iterator<Item = &'a str>, name: &str) -> Option<u32> {
    names.position(|n| n == name).map(|i| i as u32)
}
