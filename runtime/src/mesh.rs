//! Mesh files as collision solids: the vertices of an STL, OBJ or COLLADA file, scaled,
//! and their convex hull. Robot links ([`crate::robot`]) and object shapes
//! ([`crate::scene`]) both read meshes here; COLLADA's positions come from
//! `collada.rs`.
//!
//! A mesh is untrusted input like the URDF that names it. It is read within
//! [`MAX_MESH_BYTES`], its vertices are counted against [`MAX_MESH_VERTICES`] before any
//! hull is computed (the hull is the expensive step), and a file that does not parse is
//! described by what it is not, never by quoting its lines (the STL reader's own messages
//! quote them).

use std::fmt;

use cellc_schema::files::{FileError, Files, MAX_MESH_BYTES};
use parry3d_f64::shape::SharedShape;

use crate::math::Point;

/// Why a COLLADA file's positions could not be read (a [`MeshError::Collada`]).
pub use crate::collada::ColladaError;

/// Why a mesh could not be made into a convex solid.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// The URDF names the file in a way that gives no path (a `package://` URI).
    Path(cellc_urdf::MeshPathError),
    /// A scale factor is zero or not finite.
    BadScale {
        /// The scale as written.
        scale: [f64; 3],
    },
    /// The file could not be read.
    Unreadable(FileError),
    /// The extension is none of `.stl`, `.obj` and `.dae`.
    UnknownFormat,
    /// A COLLADA file whose positions cannot be read.
    Collada(crate::collada::ColladaError),
    /// Neither a binary STL nor an ASCII STL that parses.
    NotStl,
    /// More vertices than [`MAX_MESH_VERTICES`].
    TooManyVertices {
        /// How many there are.
        count: usize,
    },
    /// An OBJ file that is not UTF-8 text.
    ObjNotText,
    /// An OBJ `v` line without three numbers.
    ObjVertex {
        /// Its line number (from 1).
        line: usize,
    },
    /// Fewer than four vertices.
    TooFewVertices {
        /// How many there are.
        count: usize,
    },
    /// A vertex coordinate (after scaling) is infinite or NaN.
    NotFinite,
    /// Every vertex lies on one plane, so the hull has no volume.
    Flat,
    /// parry found no hull (or failed on a nearly degenerate mesh).
    NoHull,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::Path(error) => write!(f, "{error}"),
            MeshError::BadScale { scale } => write!(
                f,
                "scale {} {} {} has a zero or non-finite factor",
                scale[0], scale[1], scale[2]
            ),
            MeshError::Unreadable(error) => write!(f, "{error}"),
            MeshError::UnknownFormat => f.write_str(
                "only STL, OBJ and COLLADA (`.dae`) meshes are supported (by file extension)",
            ),
            MeshError::Collada(error) => write!(f, "{error}"),
            MeshError::NotStl => f.write_str(
                "not an STL file: neither binary STL (an 84-byte header, then 50 bytes for \
                 each triangle it counts) nor ASCII STL that parses",
            ),
            MeshError::TooManyVertices { count } => write!(
                f,
                "{count} vertices, more than the {MAX_MESH_VERTICES} a mesh may have; \
                 simplify it (a convex hull needs few)"
            ),
            MeshError::ObjNotText => f.write_str("not a text OBJ file"),
            MeshError::ObjVertex { line } => {
                write!(f, "line {line}: a vertex needs three numbers")
            }
            MeshError::TooFewVertices { count } => {
                write!(f, "{count} vertices cannot bound a solid")
            }
            MeshError::NotFinite => f.write_str("a vertex is not a finite number"),
            MeshError::Flat => f.write_str(
                "its vertices lie on a plane, a line or a point, so their hull has no volume",
            ),
            MeshError::NoHull => {
                f.write_str("its vertices have no convex hull (a degenerate mesh)")
            }
        }
    }
}

impl std::error::Error for MeshError {}

/// The most vertices a mesh may have (after merging repeated ones): the hull's cost grows
/// with them, and a collision solid needs only its outline.
pub const MAX_MESH_VERTICES: usize = 200_000;

/// Reads the mesh at `path` through `files` (at most [`MAX_MESH_BYTES`]) and returns its
/// convex hull, scaled.
pub fn load(path: &str, scale: [f64; 3], files: &dyn Files) -> Result<SharedShape, MeshError> {
    if !scale.iter().all(|s| s.is_finite() && *s != 0.0) {
        return Err(MeshError::BadScale { scale });
    }
    let bytes = files
        .read_at_most(path, MAX_MESH_BYTES)
        .map_err(MeshError::Unreadable)?;
    hull(path, &bytes, scale)
}

/// The convex hull of an STL, OBJ or COLLADA mesh (chosen by the extension of `path`),
/// scaled.
pub fn hull(path: &str, bytes: &[u8], scale: [f64; 3]) -> Result<SharedShape, MeshError> {
    let lower = path.to_ascii_lowercase();
    let vertices = if lower.ends_with(".stl") {
        read_stl_vertices(bytes)?
    } else if lower.ends_with(".obj") {
        read_obj_vertices(bytes)?
    } else if lower.ends_with(".dae") {
        // Counted against the budget while read, so a file of instances of one big
        // geometry is refused before its positions are computed.
        match crate::collada::positions(bytes, MAX_MESH_VERTICES) {
            Ok(positions) => positions,
            Err(crate::collada::ColladaError::TooManyPositions { count }) => {
                return Err(MeshError::TooManyVertices { count })
            }
            Err(error) => return Err(MeshError::Collada(error)),
        }
    } else {
        return Err(MeshError::UnknownFormat);
    };
    if vertices.len() > MAX_MESH_VERTICES {
        return Err(MeshError::TooManyVertices {
            count: vertices.len(),
        });
    }
    let points: Vec<Point> = vertices
        .iter()
        .map(|v| Point::new(v[0] * scale[0], v[1] * scale[1], v[2] * scale[2]))
        .collect();
    if points.len() < 4 {
        return Err(MeshError::TooFewVertices {
            count: points.len(),
        });
    }
    if points
        .iter()
        .any(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(MeshError::NotFinite);
    }
    if !spans_a_volume(&points) {
        return Err(MeshError::Flat);
    }
    // parry's hull code may panic on nearly degenerate input; report that as a bad mesh.
    match std::panic::catch_unwind(|| SharedShape::convex_hull(&points)) {
        Ok(Some(shape)) => Ok(shape),
        _ => Err(MeshError::NoHull),
    }
}

/// Whether the points have four corners that are not coplanar (relative to the points'
/// size): a flat mesh would give a hull with no volume, on which contact queries are
/// meaningless.
fn spans_a_volume(points: &[Point]) -> bool {
    let Some(first) = points.first() else {
        return false;
    };
    let farthest = |key: &dyn Fn(&Point) -> f64| {
        points
            .iter()
            .map(|p| (key(p), p))
            .fold((0.0, first), |best, x| if x.0 > best.0 { x } else { best })
    };
    let (size, second) = farthest(&|p| (p - first).norm());
    if size <= 0.0 {
        return false;
    }
    let along = (second - first) / size;
    let (off_line, third) = farthest(&|p| (p - first).cross(&along).norm());
    if off_line <= 1e-9 * size {
        return false;
    }
    let normal = (second - first).cross(&(third - first)).normalize();
    let (off_plane, _) = farthest(&|p| (p - first).dot(&normal).abs());
    off_plane > 1e-9 * size
}

/// The vertices of an STL file, ASCII or binary.
fn read_stl_vertices(bytes: &[u8]) -> Result<Vec<[f64; 3]>, MeshError> {
    let read = |bytes: &[u8]| -> std::io::Result<Vec<[f64; 3]>> {
        let mut cursor = std::io::Cursor::new(bytes);
        let mesh = stl_io::read_stl(&mut cursor)?;
        Ok(mesh
            .vertices
            .iter()
            .map(|v| [f64::from(v[0]), f64::from(v[1]), f64::from(v[2])])
            .collect())
    };
    match read(bytes) {
        Ok(vertices) => Ok(vertices),
        Err(_) => {
            // Many exporters write binary STL with a header that starts with "solid",
            // which makes the reader take it for ASCII. When the size matches the binary
            // layout exactly (84-byte header, 50 bytes a triangle), blank the header
            // (binary readers ignore it) and read it again.
            if bytes.len() >= 84 {
                let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
                if bytes.len() as u64 == 84 + 50 * u64::from(count) {
                    let mut copy = bytes.to_vec();
                    copy[..80].fill(0);
                    return read(&copy).map_err(|_| MeshError::NotStl);
                }
            }
            Err(MeshError::NotStl)
        }
    }
}

/// The vertices of a Wavefront OBJ file: its `v x y z [w]` lines; everything else (faces,
/// normals, materials) is irrelevant to a convex hull.
fn read_obj_vertices(bytes: &[u8]) -> Result<Vec<[f64; 3]>, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|_| MeshError::ObjNotText)?;
    let mut vertices = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        let mut xyz = [0.0; 3];
        for c in &mut xyz {
            *c = words
                .next()
                .and_then(|w| w.parse::<f64>().ok())
                .ok_or(MeshError::ObjVertex { line: number + 1 })?;
        }
        vertices.push(xyz);
    }
    Ok(vertices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collada_hulls_are_scaled_as_the_urdf_says() {
        let dae = br##"<COLLADA><library_geometries><geometry id="g"><mesh>
            <source id="p"><float_array id="a" count="24">0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1</float_array></source>
            <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
            </mesh></geometry></library_geometries></COLLADA>"##;
        let shape = hull("cube.DAE", dae, [0.5, 2.0, 3.0]).expect("a hull");
        let aabb = shape.compute_local_aabb();
        let extents = aabb.maxs - aabb.mins;
        assert!((extents - crate::math::Vec3::new(0.5, 2.0, 3.0)).norm() < 1e-9);
        assert_eq!(
            hull("cube.dae", b"solid x", [1.0; 3]).map(|_| ()),
            Err(MeshError::Collada(crate::collada::ColladaError::NotCollada))
        );
        assert_eq!(
            hull("cube.ply", dae, [1.0; 3]).map(|_| ()),
            Err(MeshError::UnknownFormat)
        );
    }

    #[test]
    fn reads_obj_vertices() {
        let text = b"# cube corner\nv 0 0 0\nv 1 0 0\nvn 0 0 1\nv 0 1 0 1.0\nf 1 2 3\n";
        let v = read_obj_vertices(text).unwrap();
        assert_eq!(v, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(
            read_obj_vertices(b"v 1 2\n"),
            Err(MeshError::ObjVertex { line: 1 })
        );
    }
}
