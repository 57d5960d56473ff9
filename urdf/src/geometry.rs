//! Collision geometry of links, and the paths of the mesh files it names.

use std::fmt;

use cellc_schema::files::join;
use cellc_schema::math::Iso;

use crate::description::{iso, Description};

/// One `<collision>` of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Collision {
    /// Its pose in the link's frame.
    pub origin: Iso,
    /// Its solid.
    pub geometry: Geometry,
}

/// A URDF solid, with dimensions as written (metres; nothing checked yet).
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A box centred on the origin.
    Box {
        /// Edge lengths along x, y, z.
        size: [f64; 3],
    },
    /// A cylinder along z, centred on the origin.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
    },
    /// A capsule along z: a cylinder of `length` with hemispherical ends.
    Capsule {
        /// Radius.
        radius: f64,
        /// Length of the cylindrical part.
        length: f64,
    },
    /// A sphere centred on the origin.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// A mesh file.
    Mesh {
        /// The file name as written (see [`mesh_path`]).
        filename: String,
        /// Scale factors along x, y, z (1 when absent).
        scale: [f64; 3],
    },
}

impl From<&urdf_rs::Geometry> for Geometry {
    fn from(g: &urdf_rs::Geometry) -> Geometry {
        match g {
            urdf_rs::Geometry::Box { size } => Geometry::Box { size: size.0 },
            urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder {
                radius: *radius,
                length: *length,
            },
            urdf_rs::Geometry::Capsule { radius, length } => Geometry::Capsule {
                radius: *radius,
                length: *length,
            },
            urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere { radius: *radius },
            urdf_rs::Geometry::Mesh { filename, scale } => Geometry::Mesh {
                filename: filename.clone(),
                scale: scale.as_ref().map_or([1.0; 3], |s| s.0),
            },
        }
    }
}

impl Description {
    /// The collision solids of a link, in file order (none for an unknown link).
    pub fn collisions(&self, link: &str) -> Vec<Collision> {
        self.link(link).map_or_else(Vec::new, |l| {
            l.collision
                .iter()
                .map(|c| Collision {
                    origin: iso(&c.origin),
                    geometry: Geometry::from(&c.geometry),
                })
                .collect()
        })
    }
}

/// Why a mesh file name cannot be turned into a path to read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshPathError {
    /// A ROS `package://` URI: resolving it needs a ROS package path.
    Package,
}

impl fmt::Display for MeshPathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshPathError::Package => f.write_str(
                "`package://` paths need a ROS package path, which cellc does not have; \
                 write the mesh path relative to the URDF file",
            ),
        }
    }
}

impl std::error::Error for MeshPathError {}

/// The path of a mesh named in the URDF at `urdf_path`: relative to the URDF's folder
/// unless absolute, a `file://` prefix dropped, normalised.
pub fn mesh_path(urdf_path: &str, filename: &str) -> Result<String, MeshPathError> {
    if filename.starts_with("package://") {
        return Err(MeshPathError::Package);
    }
    Ok(join(
        urdf_path,
        filename.strip_prefix("file://").unwrap_or(filename),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_paths_are_relative_to_the_urdf() {
        let path = |name| mesh_path("robots/r.urdf", name);
        assert_eq!(path("meshes/a.stl").as_deref(), Ok("robots/meshes/a.stl"));
        assert_eq!(path("../meshes/a.stl").as_deref(), Ok("meshes/a.stl"));
        assert_eq!(path("file:///abs/a.stl").as_deref(), Ok("/abs/a.stl"));
        assert_eq!(path("package://p/a.stl"), Err(MeshPathError::Package));
        assert_eq!(mesh_path("r.urdf", "./a.stl").as_deref(), Ok("a.stl"));
    }

    #[test]
    fn links_fixed_to_a_link_move_with_it() {
        let d = Description::parse(
            r#"<robot name="r">
              <link name="a"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
              <link name="b"/><link name="c"/><link name="d"/>
              <joint name="ab" type="fixed"><parent link="a"/><child link="b"/><origin xyz="1 0 0"/></joint>
              <joint name="bc" type="fixed"><parent link="b"/><child link="c"/><origin xyz="0 1 0"/></joint>
              <joint name="ad" type="revolute"><parent link="a"/><child link="d"/><axis xyz="0 0 1"/></joint>
            </robot>"#,
        )
        .expect("parses");
        let attached: Vec<(&str, [f64; 3])> = d
            .attached_links("a")
            .into_iter()
            .map(|(l, p)| (l, p.translation.vector.into()))
            .collect();
        assert_eq!(
            attached,
            [
                ("a", [0.0; 3]),
                ("b", [1.0, 0.0, 0.0]),
                ("c", [1.0, 1.0, 0.0])
            ]
        );
        assert_eq!(
            d.collisions("a")[0].geometry,
            Geometry::Sphere { radius: 0.1 }
        );
        assert!(d.collisions("nothing").is_empty());
    }
}
