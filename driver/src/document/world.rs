//! The world document the service and `cellc plan`/`run` answer with: every object's
//! whereabouts and every arm's joints, by name.

use cellc_runtime::{Cell, ObjectId, Whereabouts, World as RuntimeWorld};
use cellc_schema::EndEffectorId;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::plan::{Joints, Pose, State};

/// The world: every object's whereabouts and every arm's joints.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct World {
    /// Every object of the cell, in the cell's order.
    pub objects: Vec<Placed>,
    /// Every arm whose joints the world knows.
    pub arms: Vec<Joints>,
    /// The service's store this world is kept in (absent from the command line's
    /// documents, whose worlds are kept nowhere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<String>,
    /// The world's revision in that store: one more for every write.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revision: Option<u64>,
    /// Executions a stop of the service interrupted, whose objects and arms are
    /// uncertain until a client confirms them (docs/service.md).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub uncertain: Vec<super::state::Interrupted>,
}

/// Where one object is.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Placed {
    /// The object.
    pub object: String,
    /// Its state (`null` when the object is absent from the scene).
    pub state: Option<State>,
    /// Its pose (`null` when absent or not located).
    pub pose: Option<Pose>,
}

impl World {
    /// `world` of `cell` by names.
    pub fn of(cell: &Cell, world: &RuntimeWorld) -> World {
        let a = cell.artifact();
        let objects = (0..a.objects.len())
            .map(|i| {
                let id = ObjectId(i as u32);
                let object = a.object_name(id).to_string();
                match world.whereabouts(id) {
                    Whereabouts::Absent => Placed {
                        object,
                        state: None,
                        pose: None,
                    },
                    Whereabouts::Placed { state: s, .. } => Placed {
                        object,
                        state: Some(State::of(a, id, *s)),
                        pose: world.pose(a, cell.scene(), id).as_ref().map(Pose::of),
                    },
                }
            })
            .collect();
        let arms = world
            .arms()
            .iter()
            .enumerate()
            .filter_map(|(e, q)| Some(Joints::of(a, EndEffectorId(e as u32), q.as_ref()?)))
            .collect();
        World {
            objects,
            arms,
            instance: None,
            revision: None,
            uncertain: Vec::new(),
        }
    }
}
