//! The file paths an artifact holds (sources, URDFs, SRDFs, meshes) are relative to the
//! artifact's own folder, so an artifact keeps working wherever it and its cell are moved
//! together: made relative when it is written, resolved again when it is read.

use std::path::{Path, PathBuf};

use cellc_schema::Artifact;

/// Applies `f` to every file path an artifact holds.
fn map_paths(artifact: &mut Artifact, f: &dyn Fn(&str) -> String) {
    for s in &mut artifact.sources {
        s.path = f(&s.path);
    }
    for r in &mut artifact.robots {
        r.urdf_path = f(&r.urdf_path);
        if let Some(srdf) = &mut r.srdf {
            srdf.path = f(&srdf.path);
        }
        for m in &mut r.meshes {
            m.path = f(&m.path);
        }
    }
    let mesh = |shape: &mut cellc_schema::Shape| {
        if let cellc_schema::Shape::Mesh { path } = shape {
            *path = f(path);
        }
    };
    for k in &mut artifact.holder_kinds {
        for s in &mut k.solids {
            mesh(&mut s.shape);
        }
    }
    for o in &mut artifact.objects {
        if let Some(shape) = &mut o.shape {
            mesh(shape);
        }
    }
}

/// `path` relative to the folder `base` (both as the file system sees them).
fn relative_to(path: &str, base: &Path) -> String {
    let (Ok(path_abs), Ok(base_abs)) = (std::fs::canonicalize(path), std::fs::canonicalize(base))
    else {
        return path.to_string();
    };
    let p: Vec<_> = path_abs.components().collect();
    let b: Vec<_> = base_abs.components().collect();
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out.to_string_lossy().replace('\\', "/")
}

/// The folder of the file at `path` (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Before writing the artifact to `output`: its paths become relative to its folder.
pub fn relative_to_output(artifact: &mut Artifact, output: &Path) {
    let folder = folder_of(output);
    map_paths(artifact, &|p| relative_to(p, folder));
}

/// After reading the artifact from `input`: its paths resolve against its folder.
pub fn from_input(artifact: &mut Artifact, input: &Path) {
    let folder = folder_of(input);
    map_paths(artifact, &|p| {
        if Path::new(p).is_absolute() {
            p.to_string()
        } else {
            cellc_schema::files::normalize(&folder.join(p).to_string_lossy().replace('\\', "/"))
        }
    });
}
