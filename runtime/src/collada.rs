//! The vertex positions of a COLLADA (`.dae`) file, for a convex hull: every position of
//! every `<geometry>` that the file's visual scene instantiates, placed by the nodes that
//! instantiate it, in metres (`<unit meter>`) and with z up (an `<up_axis>` of `Y_UP` or
//! `X_UP` is turned so that its up is z, as ROS's frames are; a file without one is taken
//! as z-up). Normals, texture coordinates, materials, faces and animations do not change
//! a hull and are not read.
//!
//! A mesh file is untrusted input. The text is read with a streaming XML reader (no DTD,
//! no entities beyond XML's five, no recursion: nesting costs memory linear in the file),
//! nothing is ever allocated from a count the file states (only from values it holds),
//! every index is checked against the array it indexes, and the positions are counted
//! against the vertex budget before any is computed. Errors say what is wrong in fixed
//! words and never quote the file.

use std::collections::HashMap;
use std::fmt;

use nalgebra::{Matrix4, Vector3, Vector4};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

/// Why a COLLADA file gives no positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ColladaError {
    /// Not well-formed XML, or its outermost element is not `<COLLADA>`.
    NotCollada,
    /// A `<float_array>` or a transform holds something that is not a finite number.
    BadNumber,
    /// An accessor reaches past the end of its array, or has a stride under 3.
    BadAccessor,
    /// A reference (`#id`) to nothing the file defines.
    BrokenReference,
    /// More positions than the budget allows (the count found so far).
    TooManyPositions {
        /// Positions counted when the budget was exceeded.
        count: usize,
    },
    /// More elements than `MAX_ELEMENTS` (100,000).
    TooManyElements,
    /// An `<up_axis>` other than `X_UP`, `Y_UP` or `Z_UP`: which way is up is unknown, and
    /// guessing would turn the mesh on its side.
    BadUpAxis,
}

/// The most XML elements a COLLADA file may have. Real meshes have a few per geometry
/// (a CAD export of a whole arm link, a few hundred); the vertices are in the arrays'
/// text, not in elements. The cap bounds this reader's memory by the budget times a
/// small factor whatever the file holds.
pub const MAX_ELEMENTS: usize = 100_000;

impl fmt::Display for ColladaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ColladaError::NotCollada => {
                f.write_str("not a COLLADA file: not XML with a `<COLLADA>` element")
            }
            ColladaError::BadUpAxis => {
                f.write_str("its `<up_axis>` is none of `X_UP`, `Y_UP` and `Z_UP`")
            }
            ColladaError::BadNumber => {
                f.write_str("a number array or transform holds something that is not a number")
            }
            ColladaError::BadAccessor => f.write_str(
                "a position accessor reaches past its array or has fewer than 3 values per vertex",
            ),
            ColladaError::BrokenReference => {
                f.write_str("a `#id` reference names nothing in the file")
            }
            ColladaError::TooManyPositions { count } => {
                write!(f, "at least {count} vertex positions")
            }
            ColladaError::TooManyElements => write!(
                f,
                "more than {MAX_ELEMENTS} XML elements, more than any mesh needs"
            ),
        }
    }
}

/// One element of the file, with what this reader needs of it.
#[derive(Debug, Default)]
struct Element {
    name: String,
    parent: Option<usize>,
    /// One past the index of its last descendant (elements are in document order, so
    /// the descendants of `i` are exactly `i + 1 .. end`).
    end: usize,
    id: Option<String>,
    /// `source` (inputs, accessors) or `url` (instances), without the `#`.
    target: Option<String>,
    semantic: Option<String>,
    count: Option<usize>,
    stride: Option<usize>,
    offset: Option<usize>,
    meter: Option<String>,
    /// Text, kept only for the elements whose text is data.
    text: String,
}

/// Elements whose text this reader uses.
const TEXT_ELEMENTS: &[&str] = &[
    "float_array",
    "matrix",
    "translate",
    "rotate",
    "scale",
    "up_axis",
];

fn attribute(e: &BytesStart<'_>, name: &[u8], reader: &Reader<&[u8]>) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.local_name().as_ref() == name)
        .and_then(|a| a.decode_and_unescape_value(reader.decoder()).ok())
        .map(|v| v.into_owned())
}

/// The file's elements in document order (parents before children).
fn elements(bytes: &[u8]) -> Result<Vec<Element>, ColladaError> {
    let mut reader = Reader::from_reader(bytes);
    let mut all: Vec<Element> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    loop {
        let event = reader.read_event().map_err(|_| ColladaError::NotCollada)?;
        let (start, empty) = match event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if let Some(i) = open.pop() {
                    all[i].end = all.len();
                }
                continue;
            }
            Event::Text(t) => {
                if let Some(&i) = open.last() {
                    if TEXT_ELEMENTS.contains(&all[i].name.as_str()) {
                        let text = t.decode().map_err(|_| ColladaError::NotCollada)?;
                        all[i].text.push_str(&text);
                    }
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(start.local_name().as_ref()).into_owned();
        if open.is_empty() && (!all.is_empty() || name != "COLLADA") {
            return Err(ColladaError::NotCollada);
        }
        if all.len() >= MAX_ELEMENTS {
            return Err(ColladaError::TooManyElements);
        }
        let number =
            |key: &[u8]| attribute(&start, key, &reader).and_then(|v| v.trim().parse().ok());
        let reference = attribute(&start, b"source", &reader)
            .or_else(|| attribute(&start, b"url", &reader))
            .map(|r| r.strip_prefix('#').unwrap_or(&r).to_string());
        all.push(Element {
            parent: open.last().copied(),
            end: all.len() + 1,
            id: attribute(&start, b"id", &reader),
            target: reference,
            semantic: attribute(&start, b"semantic", &reader),
            count: number(b"count"),
            stride: number(b"stride"),
            offset: number(b"offset"),
            meter: attribute(&start, b"meter", &reader),
            text: String::new(),
            name,
        });
        if !empty {
            open.push(all.len() - 1);
        }
    }
    if all.is_empty() {
        return Err(ColladaError::NotCollada);
    }
    // A file cut short leaves elements open: they end with it.
    for i in open {
        all[i].end = all.len();
    }
    Ok(all)
}

fn numbers(text: &str) -> Result<Vec<f64>, ColladaError> {
    text.split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or(ColladaError::BadNumber)
        })
        .collect()
}

/// The transform one transformation element stands for.
fn transform(e: &Element) -> Result<Option<Matrix4<f64>>, ColladaError> {
    let v = match e.name.as_str() {
        "matrix" | "translate" | "rotate" | "scale" => numbers(&e.text)?,
        _ => return Ok(None),
    };
    let m = match (e.name.as_str(), v.as_slice()) {
        ("matrix", m) if m.len() == 16 => Matrix4::from_row_slice(m),
        ("translate", [x, y, z]) => Matrix4::new_translation(&Vector3::new(*x, *y, *z)),
        ("scale", [x, y, z]) => Matrix4::new_nonuniform_scaling(&Vector3::new(*x, *y, *z)),
        ("rotate", [x, y, z, degrees]) => {
            let axis = Vector3::new(*x, *y, *z);
            if axis.norm() == 0.0 {
                return Err(ColladaError::BadNumber);
            }
            Matrix4::from_axis_angle(&nalgebra::Unit::new_normalize(axis), degrees.to_radians())
        }
        _ => return Err(ColladaError::BadNumber),
    };
    Ok(Some(m))
}

/// The positions of the COLLADA file `bytes`, at most `max_positions` of them.
pub fn positions(bytes: &[u8], max_positions: usize) -> Result<Vec<[f64; 3]>, ColladaError> {
    let all = elements(bytes)?;
    let parent_name = |e: &Element| e.parent.map(|p| all[p].name.as_str());
    let by_id: HashMap<&str, usize> = all
        .iter()
        .enumerate()
        .filter_map(|(i, e)| Some((e.id.as_deref()?, i)))
        .collect();
    let lookup = |id: &str| by_id.get(id).copied().ok_or(ColladaError::BrokenReference);

    // Units and the up axis, from the document's own `<asset>`.
    let mut scale = 1.0;
    let mut up = Matrix4::identity();
    for e in &all {
        let in_root_asset =
            parent_name(e) == Some("asset") && e.parent.and_then(|p| all[p].parent) == Some(0);
        if !in_root_asset {
            continue;
        }
        match e.name.as_str() {
            "unit" => {
                if let Some(meter) = &e.meter {
                    scale = meter
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|m| m.is_finite() && *m > 0.0)
                        .ok_or(ColladaError::BadNumber)?;
                }
            }
            "up_axis" => {
                up = match e.text.trim() {
                    // (x, y, z) -> (x, -z, y): y becomes z.
                    "Y_UP" => Matrix4::new(
                        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                        1.0,
                    ),
                    // (x, y, z) -> (-z, y, x): x becomes z.
                    "X_UP" => Matrix4::new(
                        0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                        1.0,
                    ),
                    "Z_UP" => Matrix4::identity(),
                    _ => return Err(ColladaError::BadUpAxis),
                }
            }
            _ => {}
        }
    }
    let root = up * Matrix4::new_scaling(scale);

    // Where each geometry is placed: the instances in the visual scene, or, in a file
    // without any visual scene, every geometry where it is.
    let mut world: Vec<Matrix4<f64>> = Vec::with_capacity(all.len());
    for (i, e) in all.iter().enumerate() {
        let above = e.parent.map_or(root, |p| world[p]);
        // A transformation element moves its node: it is folded into the node's matrix
        // (its parent's entry) in document order, before the node's children.
        world.push(above);
        if let (Some(node), Some(m)) = (e.parent, transform(e)?) {
            if all[node].name == "node" {
                // Child nodes read world[node] when they come, after its transforms
                // (COLLADA writes a node's transformations before its children).
                world[node] *= m;
            }
        }
        debug_assert_eq!(world.len(), i + 1);
    }
    let scenes: Vec<usize> = all
        .iter()
        .enumerate()
        .filter(|(_, e)| e.name == "visual_scene")
        .map(|(i, _)| i)
        .collect();
    let chosen_scene = match all.iter().find(|e| e.name == "instance_visual_scene") {
        Some(instance) => Some(lookup(instance.target.as_deref().unwrap_or_default())?),
        None => scenes.first().copied(),
    };
    let mut placed: Vec<(usize, Matrix4<f64>)> = Vec::new();
    match chosen_scene {
        Some(scene) => {
            for (i, e) in all.iter().enumerate() {
                if e.name != "instance_geometry" || !descends_from(&all, i, scene) {
                    continue;
                }
                let geometry = lookup(e.target.as_deref().unwrap_or_default())?;
                let node = e.parent.unwrap_or(0);
                placed.push((geometry, world[node]));
            }
        }
        None => placed.extend(
            all.iter()
                .enumerate()
                .filter(|(_, e)| e.name == "geometry")
                .map(|(i, _)| (i, root)),
        ),
    }

    // Each geometry's positions, counted before any is transformed.
    let mut sources: HashMap<usize, (usize, usize, usize, usize)> = HashMap::new();
    let mut total = 0usize;
    for &(geometry, _) in &placed {
        if let std::collections::hash_map::Entry::Vacant(slot) = sources.entry(geometry) {
            slot.insert(position_source(&all, geometry, &lookup)?);
        }
        let (_, count, _, _) = sources[&geometry];
        total = total.saturating_add(count);
        if total > max_positions {
            return Err(ColladaError::TooManyPositions { count: total });
        }
    }
    let mut arrays: HashMap<usize, Vec<f64>> = HashMap::new();
    let mut out = Vec::with_capacity(total);
    for (geometry, m) in placed {
        let (array, count, stride, offset) = sources[&geometry];
        if let std::collections::hash_map::Entry::Vacant(slot) = arrays.entry(array) {
            slot.insert(numbers(&all[array].text)?);
        }
        let values = &arrays[&array];
        for k in 0..count {
            let at = offset + k * stride;
            let p = m * Vector4::new(values[at], values[at + 1], values[at + 2], 1.0);
            out.push([p.x, p.y, p.z]);
        }
    }
    Ok(out)
}

/// Whether element `i` lies inside element `ancestor`.
fn descends_from(all: &[Element], i: usize, ancestor: usize) -> bool {
    ancestor < i && i < all[ancestor].end
}

/// Where a geometry's positions are: (float array element, vertex count, stride, offset),
/// checked to lie within the array.
/// The first `<vertices>` of the geometry's mesh gives its `POSITION` source; the source's
/// accessor says how its array is read (without one, three values a vertex).
fn position_source(
    all: &[Element],
    geometry: usize,
    lookup: &dyn Fn(&str) -> Result<usize, ColladaError>,
) -> Result<(usize, usize, usize, usize), ColladaError> {
    let inside = |ancestor: usize, name: &'static str| {
        (ancestor + 1..all[ancestor].end).filter(move |&i| all[i].name == name)
    };
    let Some(input) = inside(geometry, "input").find(|&i| {
        all[i].semantic.as_deref() == Some("POSITION")
            && all[i].parent.map(|p| all[p].name.as_str()) == Some("vertices")
    }) else {
        // A geometry without vertices (a spline, an empty mesh) adds nothing.
        return Ok((geometry, 0, 3, 0));
    };
    let source = lookup(all[input].target.as_deref().unwrap_or_default())?;
    let accessor = inside(source, "accessor").next();
    match accessor {
        Some(a) => {
            let array = lookup(all[a].target.as_deref().unwrap_or_default())?;
            let stride = all[a].stride.unwrap_or(1);
            if stride < 3 || all[array].name != "float_array" {
                return Err(ColladaError::BadAccessor);
            }
            let count = all[a].count.ok_or(ColladaError::BadAccessor)?;
            let offset = all[a].offset.unwrap_or(0);
            // Checked against the values the array holds, so that no count the file
            // merely states is ever trusted (or allocated for).
            let values = all[array].text.split_whitespace().count();
            let needed = count
                .checked_sub(1)
                .and_then(|last| last.checked_mul(stride))
                .and_then(|v| v.checked_add(offset))
                .and_then(|v| v.checked_add(3));
            if count > 0 && needed.is_none_or(|n| n > values) {
                return Err(ColladaError::BadAccessor);
            }
            Ok((array, count, stride, offset))
        }
        None => {
            let array = inside(source, "float_array")
                .next()
                .ok_or(ColladaError::BrokenReference)?;
            let count = all[array].text.split_whitespace().count() / 3;
            Ok((array, count, 3, 0))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's eight corners in centimetres, Y up, placed by a node.
    const CUBE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube" name="cube"><mesh>
      <source id="cube-pos">
        <float_array id="cube-pos-array" count="24">0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1</float_array>
        <technique_common><accessor source="#cube-pos-array" count="8" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#cube-vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="n"><translate>100 0 0</translate><instance_geometry url="#cube"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>"##;

    #[test]
    fn reads_positions_placed_scaled_and_turned_z_up() {
        let p = positions(CUBE.as_bytes(), 100).expect("reads");
        assert_eq!(p.len(), 8);
        // (1, 1, 0) cm in a Y-up file, moved 100 cm along x: (2, 0, 1) cm... in metres,
        // with y turned onto z: (x, -z, y).
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(p[3], [1.01, 0.0, 0.01]), "{:?}", p[3]);
        assert!(close(p[4], [1.0, -0.01, 0.0]), "{:?}", p[4]);
    }

    #[test]
    fn an_unknown_up_axis_is_refused_and_z_up_is_as_written() {
        let w_up = CUBE.replace("Y_UP", "W_UP");
        assert_eq!(
            positions(w_up.as_bytes(), 100),
            Err(ColladaError::BadUpAxis)
        );
        let z_up = positions(CUBE.replace("Y_UP", "Z_UP").as_bytes(), 100).expect("reads");
        assert!((z_up[3][1] - 0.01).abs() < 1e-12, "{:?}", z_up[3]);
    }

    #[test]
    fn hostile_files_are_errors_not_hangs_or_huge_allocations() {
        let with = |from: &str, to: &str| CUBE.replace(from, to);
        // A count far beyond the array: refused, nothing allocated from it.
        let huge = with(r#"count="8" stride"#, r#"count="4000000000" stride"#);
        assert_eq!(
            positions(huge.as_bytes(), usize::MAX),
            Err(ColladaError::BadAccessor)
        );
        assert_eq!(
            positions(CUBE.as_bytes(), 7),
            Err(ColladaError::TooManyPositions { count: 8 })
        );
        let offset = with(
            r#"stride="3">"#,
            r#"stride="3" offset="18446744073709551615">"#,
        );
        assert_eq!(
            positions(offset.as_bytes(), 100),
            Err(ColladaError::BadAccessor)
        );
        let nan = with("1 1 1</float_array>", "1 1 NaN</float_array>");
        assert_eq!(positions(nan.as_bytes(), 100), Err(ColladaError::BadNumber));
        let dangling = with(r##"url="#cube""##, r##"url="#nothing""##);
        assert_eq!(
            positions(dangling.as_bytes(), 100),
            Err(ColladaError::BrokenReference)
        );
        // Skinned files' name arrays (which hang some readers) are simply not read.
        let names = with("<library_geometries>", "<library_controllers><Name_array id=\"j\" count=\"1\">bone</Name_array></library_controllers><library_geometries>");
        assert_eq!(positions(names.as_bytes(), 100).map(|p| p.len()), Ok(8));
        assert_eq!(positions(b"solid x", 100), Err(ColladaError::NotCollada));
        assert_eq!(
            positions(b"<html></html>", 100),
            Err(ColladaError::NotCollada)
        );
        assert_eq!(positions(b"", 100), Err(ColladaError::NotCollada));
        // Cut short anywhere: an error or fewer positions, never a panic.
        for end in (0..CUBE.len()).step_by(7) {
            let _ = positions(&CUBE.as_bytes()[..end], 100);
        }
        let deep = format!(
            "<COLLADA>{}{}</COLLADA>",
            "<node>".repeat(MAX_ELEMENTS),
            "</node>".repeat(MAX_ELEMENTS)
        );
        assert_eq!(
            positions(deep.as_bytes(), 100),
            Err(ColladaError::TooManyElements)
        );
    }
}
