//! The world: where the objects are and where the arms stand, as a cell declares it
//! (`world` and `task` items, lowered into the artifact) and as a caller hands it to the
//! runtime (the world document, JSON, `docs/world.md`).
//!
//! Both say *where*, by name, the way people write placements; the runtime turns them into
//! its typed world once (`cellc_runtime::World`), checking names, joint values and poses
//! there. The document is untrusted input: [`WorldDocument::from_json`] reads it within a
//! byte budget and refuses unknown fields, so a misspelt key is an error rather than
//! silently ignored data.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::ids::ObjectId;
use crate::RequestPlacement;

/// The most bytes a world document may have (a cell with a hundred arms of a dozen joints
/// and a thousand objects is well under 1 MiB).
pub const MAX_WORLD_BYTES: usize = 4 << 20;

/// Where an object starts, as the cell's `world` item says.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InitialPlacement {
    /// The object.
    pub object: ObjectId,
    /// Where it is: a holder, and a workspace or a pose (a hand's pose follows from its
    /// arm's joints, so a held object needs neither).
    pub placement: RequestPlacement,
    /// The line in the `world` item.
    pub span: u32,
}

/// A task declared in the cell: moves planned and executed one after the other, each from
/// where the world has the object then.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NamedTask {
    /// Name.
    pub name: String,
    /// The moves, in order.
    pub steps: Vec<TaskStep>,
    /// The `task` item.
    pub span: u32,
}

/// One move of a task: `OBJECT to PLACEMENT`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskStep {
    /// The object moved.
    pub object: ObjectId,
    /// Where it must go.
    pub to: RequestPlacement,
    /// The step's line.
    pub span: u32,
}

/// A world document: every arm's joints (by URDF joint name, radians or metres; joints
/// not named stay at home, arms not named stand at home) and every object's placement
/// (objects not named are absent from the scene).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WorldDocument {
    /// Arm name -> joint name -> value.
    #[serde(default)]
    pub arms: BTreeMap<String, BTreeMap<String, f64>>,
    /// Object name -> where it is.
    #[serde(default)]
    pub objects: BTreeMap<String, ObjectEntry>,
}

/// Where one object of a world document is. Read through a JSON value so that a wrong
/// entry is reported as what is wrong with it (an unknown field, a missing holder), not
/// as "matches neither form".
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged, try_from = "serde_json::Value")]
pub enum ObjectEntry {
    /// `"absent"`: not in the scene (the same as leaving the object out).
    Absent(AbsentWord),
    /// Held or resting: the same parts as a placement in the cell language.
    Placed(PlacedEntry),
}

impl TryFrom<serde_json::Value> for ObjectEntry {
    type Error = String;

    fn try_from(value: serde_json::Value) -> Result<ObjectEntry, String> {
        match value {
            serde_json::Value::String(word) if word == "absent" => {
                Ok(ObjectEntry::Absent(AbsentWord::Absent))
            }
            serde_json::Value::String(word) => Err(format!(
                "`{word}` is not a placement: write \"absent\" or an object with a `holder`"
            )),
            other => serde_json::from_value(other)
                .map(ObjectEntry::Placed)
                .map_err(|e| e.to_string()),
        }
    }
}

/// Written by hand: the entry is read through a JSON value (for its errors), so a derived
/// schema would say "any value"; this one says what the reader accepts.
impl JsonSchema for ObjectEntry {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "ObjectEntry".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let absent = generator.subschema_for::<AbsentWord>();
        let placed = generator.subschema_for::<PlacedEntry>();
        schemars::json_schema!({
            "description": "`\"absent\"`, or where the object is: a holder and a grasp, workspace or pose",
            "anyOf": [absent, placed],
        })
    }
}

/// The one word an absent object's entry may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AbsentWord {
    /// Not in the scene.
    Absent,
}

/// A placement by name: `HOLDER[.GRASP] in WORKSPACE` or `HOLDER[.GRASP] at POSE`, or, for
/// a hand, just `HOLDER.GRASP` (the pose follows from the arm's joints; a pose given as
/// well is checked against it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlacedEntry {
    /// The end-effector that holds it or that it rests on.
    pub holder: String,
    /// The grasp or resting pose, when named.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grasp: Option<String>,
    /// The workspace, when named.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workspace: Option<String>,
    /// Position of the object frame in the cell, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 3]>,
    /// Orientation as roll, pitch, yaw about fixed x, y, z, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy: Option<[f64; 3]>,
    /// Orientation as a unit quaternion (w, x, y, z).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quat: Option<[f64; 4]>,
}

/// Why a world document could not be read.
#[derive(Clone, Debug, PartialEq)]
pub enum WorldDocumentError {
    /// Over [`MAX_WORLD_BYTES`].
    TooLarge {
        /// Its size.
        bytes: usize,
    },
    /// Not JSON of the document's shape: where (1-based line and column; 0 when the text
    /// ended early) and what serde_json says.
    Syntax {
        /// Line, 1-based.
        line: usize,
        /// Column, 1-based.
        column: usize,
        /// What was wrong.
        message: String,
    },
}

impl WorldDocument {
    /// Reads a world document.
    ///
    /// # Errors
    /// Too large, or not a document of this shape (unknown fields included).
    pub fn from_json(bytes: &[u8]) -> Result<WorldDocument, WorldDocumentError> {
        if bytes.len() > MAX_WORLD_BYTES {
            return Err(WorldDocumentError::TooLarge { bytes: bytes.len() });
        }
        serde_json::from_slice(bytes).map_err(|e| WorldDocumentError::Syntax {
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })
    }

    /// The document as pretty JSON (what `cellc run` prints as the final world).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_document_reads_placements_and_joints() {
        let doc = WorldDocument::from_json(
            br#"{
                "arms": { "left": { "a1": 0.5 } },
                "objects": {
                    "cylinder": { "holder": "table", "at": [0.4, 0.4, 1.0], "rpy": [0, 0, 90] },
                    "ball": { "holder": "right", "grasp": "top" },
                    "pitcher": "absent"
                }
            }"#,
        )
        .expect("a valid document");
        assert_eq!(doc.arms["left"]["a1"], 0.5);
        assert_eq!(
            doc.objects["pitcher"],
            ObjectEntry::Absent(AbsentWord::Absent)
        );
        let ObjectEntry::Placed(ball) = &doc.objects["ball"] else {
            panic!("the ball is placed");
        };
        assert_eq!(ball.grasp.as_deref(), Some("top"));
        assert_eq!(ball.at, None);
        let again = WorldDocument::from_json(doc.to_json().as_bytes()).expect("round trip");
        assert_eq!(again, doc);
    }

    #[test]
    fn unknown_fields_and_bad_shapes_are_refused_with_a_place() {
        for (text, line) in [
            (
                &b"{\"objects\": {\"c\": {\"holder\": \"t\", \"pos\": [0, 0, 0]}}}"[..],
                1,
            ),
            (b"{\n\"arms\": {\"left\": {\"a1\": \"zero\"}}}", 2),
            (b"{\"objects\": {\"c\": \"gone\"}}", 1),
            (
                b"{\"objects\": {\"c\": {\"holder\": \"t\", \"at\": [0, 0]}}}",
                1,
            ),
            (b"[1, 2]", 1),
        ] {
            match WorldDocument::from_json(text) {
                Err(WorldDocumentError::Syntax { line: l, .. }) => {
                    assert_eq!(l, line, "{}", String::from_utf8_lossy(text))
                }
                other => panic!("{}: {other:?}", String::from_utf8_lossy(text)),
            }
        }
        let huge = vec![b' '; MAX_WORLD_BYTES + 1];
        assert!(matches!(
            WorldDocument::from_json(&huge),
            Err(WorldDocumentError::TooLarge { .. })
        ));
    }
}
