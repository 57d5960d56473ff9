//! The bodies of the fuzz targets (`fuzz/fuzz_targets/*.rs`), here so that `cargo test`
//! replays every committed seed and finding through exactly the code the fuzzer ran
//! (`tests/fuzz_corpus.rs`). Each function takes arbitrary bytes and must return without
//! panicking; a violated property (a formatter that is not idempotent, a validated
//! artifact the planner cannot index) panics on purpose, which the fuzzer reports.

use cellc_lang::FileId;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, MemoryFiles};
use cellc_schema::Artifact;

/// Cells larger than this are not interesting to the fuzzer (the size limits are tested
/// elsewhere) and would only slow it down.
const MAX_INPUT: usize = 64 * 1024;

/// Parse, resolve and check a cell, then render its diagnostics in every format.
pub fn parse_check(data: &[u8]) {
    let Some(text) = text(data) else {
        return;
    };
    let files = MemoryFiles::new([("fuzz.cell", text)]);
    let built = cellc_driver::build(
        &files,
        "fuzz.cell",
        &cellc_driver::BuildOptions::unverified(),
    );
    let compilation = &built.compilation;
    let _ = crate::render::human(
        &compilation.diagnostics,
        &compilation.sources,
        crate::render::Color::Never,
    );
    let _ = crate::render::short(&compilation.diagnostics, &compilation.sources);
    let json = crate::render::json(&compilation.diagnostics, &compilation.sources);
    assert!(
        serde_json::from_str::<serde_json::Value>(&json).is_ok(),
        "the JSON report is not JSON"
    );
    if let Some(artifact) = &built.artifact {
        assert!(
            cellc_schema::validate::validate(artifact).is_ok(),
            "the compiler lowered an artifact that does not validate"
        );
    }
}

/// The formatter on any cell that parses: its output parses again, without errors, and
/// formatting it again changes nothing.
pub fn format(data: &[u8]) {
    let Some(text) = text(data) else {
        return;
    };
    let parsed = cellc_lang::parse(FileId(0), text);
    let (Some(file), true) = (parsed.file, parsed.diagnostics.is_empty()) else {
        return;
    };
    let once = cellc_lang::format(&file, text);
    let again = cellc_lang::parse(FileId(0), &once);
    assert!(
        again.diagnostics.is_empty(),
        "formatted text does not parse: {:?}\n{once}",
        again.diagnostics.first().map(|d| &d.message)
    );
    let file = again.file.expect("parsed without errors");
    assert_eq!(cellc_lang::format(&file, &once), once, "not idempotent");
}

/// A sectioned binary read in part, as `cellc plan` reads it: per named request only its
/// object's graph, then (when it fails) what its explanation needs.
fn artifact_plan_in_part(data: &[u8], files: &MemoryFiles) {
    use cellc_schema::partial::Parts;
    let Ok(sections) = cellc_schema::sections::Sections::open(data) else {
        return;
    };
    let Ok(core) = cellc_schema::partial::Partial::open(&sections) else {
        return;
    };
    let options = PlanOptions {
        motions: false,
        max_backtracks: 16,
        ..PlanOptions::default()
    };
    for named in &core.artifact().requests {
        let Ok(mut cell) = Cell::load_objects(&sections, &[named.object], Parts::GRAPH, files)
        else {
            continue;
        };
        let Some(request) = cell.named_request(&named.name, options.clone()) else {
            continue;
        };
        if let Err(cellc_runtime::PlanError::Unreachable(u)) =
            cell.plan(&cell.home_world(), &request)
        {
            if cell
                .read_parts(&sections, named.object, Parts::EXPLAIN)
                .is_ok()
            {
                let _ = cell.explain(&u);
            }
        }
    }
}

/// An artifact's bytes through the runtime's front door, then every named request planned
/// (high level: motions would make each execution seconds long). Inputs that start with
/// `P` are taken as the postcard content of an artifact without header and checksum, so
/// the fuzzer reaches validation and planning instead of stopping at the checksum.
pub fn artifact_plan(data: &[u8]) {
    if data.len() > MAX_INPUT {
        return;
    }
    let files = MemoryFiles::default();
    if data.starts_with(cellc_schema::MAGIC.as_slice()) {
        artifact_plan_in_part(data, &files);
    }
    let cell = match data.split_first() {
        Some((b'P', content)) => {
            let Ok(artifact) = postcard::from_bytes::<Artifact>(content) else {
                return;
            };
            Cell::from_artifact(artifact, &files)
        }
        _ => Cell::load(data, &files),
    };
    let Ok(cell) = cell else {
        return;
    };
    let options = PlanOptions {
        motions: false,
        max_backtracks: 16,
        ..PlanOptions::default()
    };
    for named in &cell.artifact().requests {
        if let Some(request) = cell.named_request(&named.name, options.clone()) {
            if let Err(cellc_runtime::PlanError::Unreachable(u)) =
                cell.plan(&cell.home_world(), &request)
            {
                let _ = cell.explain(&u);
            }
        }
    }
    // The declared world and every task, each move planned where the plans before it
    // leave the world.
    if let Ok(world) = cell.initial_world(&options) {
        for task in &cell.artifact().tasks {
            let mut world = world.clone();
            for (object, goal) in cell.task(&task.name).unwrap_or_default() {
                match cell.plan_move(&world, object, &goal, &options) {
                    Ok(plan) => world = cell.world_after(&world, &plan),
                    Err(_) => break,
                }
            }
        }
    }
}

/// A cell with a world and a task, abstract (no geometry), that world documents are
/// checked against by [`world_document`].
const WORLD_CELL: &str = "cell tidy {
  workspace w1
  workspace w2
  fixed table reaches w1, w2
  movable gripper reaches w1, w2
  object cube {
    grasp on_table by table
    grasp held by gripper
    transition on_table <-> held
  }
  object ball {
    grasp on_table by table
    grasp held by gripper
    transition on_table <-> held
  }
  world {
    cube: table in w1
    ball: table in w1
  }
  task clear_w1 {
    cube to table in w2
    ball to gripper.held in w2
  }
}
";

/// A world document (JSON) read and checked against a small cell, then its moves planned:
/// every malformed document is an error value, never a panic, and a world that is
/// accepted plans.
pub fn world_document(data: &[u8]) {
    use std::sync::OnceLock;
    static CELL: OnceLock<Option<Cell>> = OnceLock::new();
    let cell = CELL.get_or_init(|| {
        let files = MemoryFiles::new([("tidy.cell", WORLD_CELL)]);
        let built = cellc_driver::build(
            &files,
            "tidy.cell",
            &cellc_driver::BuildOptions::unverified(),
        );
        Cell::from_artifact(built.artifact?, &files).ok()
    });
    let Some(cell) = cell else {
        return;
    };
    let Ok(document) = cellc_schema::WorldDocument::from_json(data) else {
        return;
    };
    let options = PlanOptions::default();
    let Ok(mut world) = cell.world(&document, &options) else {
        return;
    };
    for (object, goal) in cell.task("clear_w1").unwrap_or_default() {
        match cell.plan_move(&world, object, &goal, &options) {
            Ok(plan) => world = cell.world_after(&world, &plan),
            Err(_) => break,
        }
    }
}

/// A robot description or a mesh. The first byte picks what: `U` a URDF whose first line
/// names the base and tip links (`base tip`), `S` an STL mesh, `O` an OBJ mesh, `D` a
/// COLLADA mesh, `R` an SRDF (checked against an empty robot).
pub fn urdf_mesh(data: &[u8]) {
    if data.len() > MAX_INPUT {
        return;
    }
    let files = MemoryFiles::default();
    match data.split_first() {
        Some((b'U', rest)) => {
            let Ok(text) = std::str::from_utf8(rest) else {
                return;
            };
            let (links, urdf) = text.split_once('\n').unwrap_or((text, ""));
            let (base, tip) = links.split_once(' ').unwrap_or((links, links));
            let _ = cellc_runtime::robot::Robot::from_urdf(urdf, "fuzz.urdf", base, tip, &files);
        }
        Some((b'S', rest)) => {
            let _ = cellc_runtime::mesh::hull("fuzz.stl", rest, [1.0, 1.0, 1.0]);
        }
        Some((b'O', rest)) => {
            let _ = cellc_runtime::mesh::hull("fuzz.obj", rest, [1.0, 1.0, 1.0]);
        }
        Some((b'D', rest)) => {
            let _ = cellc_runtime::mesh::hull("fuzz.dae", rest, [1.0, 1.0, 1.0]);
        }
        Some((b'R', rest)) => {
            if let (Ok(text), Ok(urdf)) = (
                std::str::from_utf8(rest),
                cellc_urdf::Description::parse("<robot name='r'><link name='a'/></robot>"),
            ) {
                if let Ok(srdf) = cellc_urdf::Srdf::parse(text) {
                    let _ = srdf.problems(&urdf);
                    for group in &srdf.groups {
                        let _ = srdf.group_chain(&group.name, &urdf);
                    }
                }
            }
        }
        _ => {}
    }
}

fn text(data: &[u8]) -> Option<&str> {
    (data.len() <= MAX_INPUT)
        .then(|| std::str::from_utf8(data).ok())
        .flatten()
}

/// The language server's input stream: frames read within bounds (no body over the
/// limit, memory only for what arrives), every body either a message or a refusal, and
/// the reader always making progress, so a stream of `n` bytes gives at most `n` frames.
pub fn lsp_frames(data: &[u8]) {
    use crate::lsp::framing::{Frame, FrameReader, MAX_BODY};
    let mut frames = FrameReader::new(data);
    let mut count = 0;
    loop {
        match frames.next_frame() {
            Frame::End => break,
            Frame::Body(body) => {
                assert!(body.len() as u64 <= MAX_BODY);
                let _ = crate::lsp::transport::message(&body);
            }
            Frame::Malformed(why) => assert!(!why.is_empty()),
        }
        count += 1;
        assert!(count <= data.len(), "no progress");
    }
}
