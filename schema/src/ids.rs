//! Typed ids of an artifact's elements.
//!
//! An artifact stores plain `u32` indices so the file stays language-neutral; code that
//! handles artifacts passes these newtypes instead, so an object index can never be used
//! where a workspace index is meant. Each id is an index into one list: [`ObjectId`] into
//! [`Artifact::objects`](crate::Artifact::objects), [`GraspId`] into one object's
//! `grasps`, [`NodeId`] into one object's graph nodes. They serialise as the bare number.

use serde::{Deserialize, Serialize};

macro_rules! typed_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(
            Clone,
            Copy,
            Debug,
            Default,
            PartialEq,
            Eq,
            Hash,
            PartialOrd,
            Ord,
            Serialize,
            Deserialize,
        )]
        #[serde(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The index as a `usize`, for indexing the list this id points into.
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl From<u32> for $name {
            fn from(i: u32) -> $name {
                $name(i)
            }
        }

        impl From<$name> for u32 {
            fn from(id: $name) -> u32 {
                id.0
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}#{}", stringify!($name), self.0)
            }
        }
    };
}

typed_id!(
    /// An object: index into `Artifact::objects`.
    ObjectId
);
typed_id!(
    /// An end-effector (hand or fixed surface): index into `Artifact::end_effectors`.
    EndEffectorId
);
typed_id!(
    /// A workspace: index into `Artifact::workspaces`.
    WorkspaceId
);
typed_id!(
    /// A grasp or resting pose of one object: index into that object's `grasps`.
    GraspId
);
typed_id!(
    /// A state of one object's graph: index into that graph's `nodes`.
    NodeId
);
typed_id!(
    /// A robot model: index into `Artifact::robots`.
    RobotId
);
typed_id!(
    /// A span: index into `Artifact::spans`.
    SpanId
);
