//! Collision geometry of links, and the paths of the mesh files it names.

use std::fmt;

use cellc_schema::files::join;
use cellc_schema::math::Iso;
use cellc_schema::MeshFile;

use crate::description::{iso, Description};
use crate::package::{file_ref, FileRef};

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
    /// A ROS `package://` URI, where only paths relative to the URDF are known.
    Package,
    /// A mesh the table of resolved paths does not list (the artifact and the URDF it was
    /// built from disagree).
    NotRecorded,
}

impl fmt::Display for MeshPathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshPathError::Package => f.write_str(
                "`package://` paths are resolved by the compiler (`package NAME at \"DIR\"`, \
                 `--package-path`, `ROS_PACKAGE_PATH`); here only paths relative to the URDF \
                 are known",
            ),
            MeshPathError::NotRecorded => f.write_str(
                "the artifact records no path for this mesh; rebuild it with `cellc build`",
            ),
        }
    }
}

impl std::error::Error for MeshPathError {}

/// Where the mesh files a URDF names are to be read.
#[derive(Clone, Copy, Debug)]
pub enum MeshPaths<'a> {
    /// Relative to the URDF at this path (see [`mesh_path`]); `package://` is refused.
    RelativeTo(&'a str),
    /// As the compiler resolved them (written name -> path), as an artifact records them.
    Resolved(&'a [MeshFile]),
}

impl MeshPaths<'_> {
    /// The path of the mesh written `filename` in the URDF.
    pub fn path(&self, filename: &str) -> Result<String, MeshPathError> {
        match self {
            MeshPaths::RelativeTo(urdf_path) => mesh_path(urdf_path, filename),
            MeshPaths::Resolved(table) => table
                .iter()
                .find(|m| m.written == filename)
                .map(|m| m.path.clone())
                .ok_or(MeshPathError::NotRecorded),
        }
    }
}

/// The path of a mesh named in the URDF at `urdf_path`: relative to the URDF's folder
/// unless absolute, a `file://` prefix dropped, normalised.
pub fn mesh_path(urdf_path: &str, filename: &str) -> Result<String, MeshPathError> {
    match file_ref(filename) {
        Ok(FileRef::Path(path)) => Ok(join(urdf_path, path)),
        Ok(FileRef::Package { .. }) | Err(_) => Err(MeshPathError::Package),
    }
}

impl Description {
    /// Every mesh file name the collision solids of the description name, each once, in
    /// file order (visual meshes are for viewers and never read).
    pub fn collision_meshes(&self) -> Vec<&str> {
        let mut seen = std::collections::HashSet::new();
        self.model
            .links
            .iter()
            .flat_map(|l| &l.collision)
            .filter_map(|c| match &c.geometry {
                urdf_rs::Geometry::Mesh { filename, .. } => Some(filename.as_str()),
                _ => None,
            })
            .filter(|f| seen.insert(*f))
            .collect()
    }
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
        let table = [MeshFile {
            written: "package://p/a.stl".into(),
            path: "robots/p/a.stl".into(),
        }];
        let resolved = MeshPaths::Resolved(&table);
        assert_eq!(
            resolved.path("package://p/a.stl").as_deref(),
            Ok("robots/p/a.stl")
        );
        assert_eq!(resolved.path("b.stl"), Err(MeshPathError::NotRecorded));
    }

    #[test]
    fn collision_meshes_are_listed_once_and_visual_ones_not_at_all() {
        let d = Description::parse(
            r#"<robot name="r">
              <link name="a">
                <visual><geometry><mesh filename="v.dae"/></geometry></visual>
                <collision><geometry><mesh filename="c.stl" scale="2 2 2"/></geometry></collision>
                <collision><geometry><mesh filename="c.stl"/></geometry></collision>
              </link>
              <link name="b"><collision><geometry><mesh filename="d.dae"/></geometry></collision></link>
              <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
            </robot>"#,
        )
        .expect("parses");
        assert_eq!(d.collision_meshes(), ["c.stl", "d.dae"]);
        assert_eq!(
            d.collisions("a")[0].geometry,
            Geometry::Mesh {
                filename: "c.stl".into(),
                scale: [2.0; 3]
            }
        );
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
