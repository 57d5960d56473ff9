//! Every suggestion of an unreachable goal's explanation, made as the source edit
//! `cellc_driver::fixes::edit` gives, makes that request plan: for each R0004 case of
//! `tests/ui/plan/` and each cell of `runtime/tests/explain_cells/` that can be written as
//! source (no hand kinds, no arcs pruned or failed by fiat), the request is planned, its
//! explanation's suggestions are turned into text edits (every one must have an edit),
//! the edited cell is compiled (and verified, when it has arms) and the same request is
//! planned again: it must plan. The number of suggestions checked is counted, so the test
//! cannot pass by checking none.

#[path = "../runtime/tests/explain_cells/mod.rs"]
mod explain_cells;

use std::collections::BTreeMap;

use cellc_driver::fixes::{self, SourceEdit};
use cellc_driver::fs_files::FsFiles;
use cellc_lang::written_name as name;
use cellc_runtime::plan::{PlanError, PlanOptions};
use cellc_runtime::Cell;
use cellc_schema::{FileError, Files, MemoryFiles};
use explain_cells::*;

/// Edited files in memory over the file system (robot models, meshes, includes).
struct Edited<'a> {
    files: MemoryFiles,
    below: &'a dyn Files,
}

impl Files for Edited<'_> {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        self.files.read(path).or_else(|_| self.below.read(path))
    }
}

/// What planning a cell's first request gave.
struct Planned {
    sources: cellc_lang::SourceMap,
    cell: Cell,
    result: Result<cellc_runtime::plan::Plan, PlanError>,
}

/// Builds `path` as `cellc plan` does (verified when it has arms) and plans its first
/// request; `None` when the cell has errors.
fn plan(files: &dyn Files, path: &str) -> Option<Planned> {
    let built = cellc_driver::build(files, path, &Default::default());
    let cell = Cell::from_artifact(built.artifact?, files).expect("the cell loads");
    let named = cell.artifact().requests.first()?.name.clone();
    let request = cell
        .named_request(&named, PlanOptions::default())
        .expect("the request is declared");
    let result = cell.plan(&cell.home_world(), &request);
    Some(Planned {
        sources: built.compilation.sources,
        cell,
        result,
    })
}

/// Checks every suggestion of the explanation of `path`'s unreachable first request;
/// returns how many were checked.
fn check(files: &dyn Files, path: &str) -> usize {
    let planned = plan(files, path).unwrap_or_else(|| panic!("{path} has errors"));
    let Err(PlanError::Unreachable(unreachable)) = &planned.result else {
        panic!("{path}: the request must be unreachable");
    };
    let explanation = planned.cell.explain(unreachable).expect("the states exist");
    let artifact = planned.cell.artifact();
    for (i, suggestion) in explanation.suggestions.iter().enumerate() {
        let edits: Vec<SourceEdit> = suggestion
            .changes
            .iter()
            .map(|change| {
                fixes::edit(artifact, explanation.object, change, &planned.sources)
                    .unwrap_or_else(|| panic!("{path}: no edit makes {change:?}"))
            })
            .collect();
        let mut by_file: BTreeMap<u32, Vec<&SourceEdit>> = BTreeMap::new();
        for e in &edits {
            by_file.entry(e.file.0).or_default().push(e);
        }
        let mut edited = MemoryFiles::default();
        for (file, edits) in by_file {
            let source = planned.sources.get(cellc_lang::FileId(file));
            let text = fixes::apply(&source.text, &edits).expect("the edits apply");
            println!("{path}, suggestion {}: {}\n{text}", i + 1, source.path);
            edited.insert(&source.path, text);
        }
        let edited = Edited {
            files: edited,
            below: files,
        };
        let again = plan(&edited, path)
            .unwrap_or_else(|| panic!("{path}: suggestion {} gives a cell with errors", i + 1));
        assert!(
            again.result.is_ok(),
            "{path}: suggestion {} ({suggestion:?}) does not make the request plan: {:?}",
            i + 1,
            again.result.err()
        );
    }
    explanation.suggestions.len()
}

/// A cell description and its request as source, when the language can say it: no hand
/// kinds (abstract end-effectors have none), no arcs pruned or failed by fiat, and a start
/// other than the goal (an abstract request has no poses to move between).
fn source((d, req): &(Desc, Req)) -> Option<String> {
    if !d.kinds.is_empty() || !d.pruned.is_empty() || !req.failed.is_empty() {
        return None;
    }
    let goal = req.goals.first()?;
    if *goal == req.start {
        return None;
    }
    let mut out = String::from("cell test {\n");
    for w in &d.workspaces {
        out.push_str(&format!("  workspace {}\n", name(w)));
    }
    for (a, b) in &d.adjacent {
        out.push_str(&format!("  adjacent {} {}\n", name(a), name(b)));
    }
    for (e, movable, reaches) in &d.end_effectors {
        let list: Vec<String> = reaches.iter().map(|w| name(w)).collect();
        let mobility = if *movable { "movable" } else { "fixed" };
        out.push_str(&format!(
            "  {mobility} {} reaches {}\n",
            name(e),
            list.join(", ")
        ));
    }
    out.push_str("\n  object cylinder {\n");
    for (g, holder) in &d.grasps {
        out.push_str(&format!("    grasp {} by {}\n", name(g), name(holder)));
    }
    for (a, b) in &d.transitions {
        out.push_str(&format!("    transition {} -> {}\n", name(a), name(b)));
    }
    out.push_str("  }\n\n");
    let place = |(e, g, w): &St| format!("{}.{} in {}", name(e), name(g), name(w));
    out.push_str(&format!(
        "  request r: cylinder from {} to {}\n}}\n",
        place(&req.start),
        place(goal)
    ));
    Some(out)
}

/// Checks a described cell written as source; `None` when it cannot be written, has
/// errors (a declared workspace no one reaches, a transition between two surfaces) or its
/// request plans as written.
fn check_described(cell: &(Desc, Req)) -> Option<usize> {
    let text = source(cell)?;
    let files = MemoryFiles::new([("test.cell", text.as_str())]);
    let planned = plan(&files, "test.cell")?;
    if !matches!(planned.result, Err(PlanError::Unreachable(_))) {
        return None;
    }
    Some(check(&files, "test.cell"))
}

#[test]
fn every_suggestion_of_the_ui_cases_is_an_edit_that_makes_the_request_plan() {
    let mut cases = 0;
    let mut checked = 0;
    let mut dir: Vec<_> = std::fs::read_dir("tests/ui/plan")
        .expect("the UI cases are there")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("R0004_"))
        })
        .collect();
    dir.sort();
    for path in dir {
        let path = path.to_string_lossy().to_string();
        let n = check(&FsFiles, &path);
        assert!(n > 0, "{path} makes no suggestion");
        checked += n;
        cases += 1;
    }
    println!("{cases} R0004 cases, {checked} suggestions");
    assert!(cases >= 4, "{cases} R0004 cases");
    assert!(checked >= 6, "only {checked} suggestions checked");
}

#[test]
fn every_suggestion_of_the_explain_cells_is_an_edit_that_makes_the_request_plan() {
    let named = [
        fig3_right_arm_cannot_take(),
        fig3_right_arm_isolated(),
        arms_apart_with_boxes(),
        arms_apart_declaring_adjacency(),
        line_with_a_gap(),
        two_surfaces_and_an_arm(),
        surfaces_alone(),
        workspaces_not_adjacent(),
    ];
    // A cell the compiler refuses (`arms_apart_declaring_adjacency` declares two
    // workspaces adjacent that no hand spans, E0305) is not a cell anyone wrote.
    let (mut written, mut checked) = (0, 0);
    for cell in &named {
        if let Some(n) = check_described(cell) {
            written += 1;
            checked += n;
        }
    }
    assert!(written >= 7, "only {written} of the named cells written");
    println!("{written} named cells, {checked} suggestions");
    assert!(checked >= 8, "only {checked} suggestions checked");
    let mut random = 0;
    for seed in 0..1000 {
        random += check_described(&random_cell(seed)).unwrap_or(0);
    }
    println!("{random} suggestions on random cells");
    assert!(
        random >= 50,
        "only {random} suggestions checked on random cells"
    );
}
