//! The resolver's table of names (`Compilation::names`): declarations and uses where
//! they are written, scoped as the resolver scopes them (one namespace across included
//! files, grasps per object, requests and tasks apart), including the names of items
//! the resolver refuses and of a file being typed.

use cellc_compiler::names::{Key, Kind, Names, Occurrence};
use cellc_compiler::{compile, Compilation, MemoryFiles};
use cellc_lang::FileId;

fn compiled(files: &[(&str, &str)]) -> Compilation {
    compile(&MemoryFiles::new(files.iter().copied()), files[0].0)
}

fn global(name: &str) -> Key {
    Key::Global(name.to_string())
}

fn grasp(object: &str, grasp: &str) -> Key {
    Key::Grasp {
        object: object.to_string(),
        grasp: grasp.to_string(),
    }
}

/// The text of each occurrence of `key`, with its file and whether it declares.
fn places(c: &Compilation, key: &Key) -> Vec<(u32, String, bool)> {
    c.names
        .occurrences_of(key)
        .map(|o| {
            let text = &c.sources.get(o.file).text;
            let written = text[o.span.start as usize..o.span.end as usize].to_string();
            (o.file.0, written, o.declares.is_some())
        })
        .collect()
}

/// The line (0-based) of an occurrence.
fn line(c: &Compilation, o: &Occurrence) -> usize {
    c.sources.get(o.file).text[..o.span.start as usize]
        .matches('\n')
        .count()
}

const LIB: &str = "library lib {
  workspace w1
  hand paw
}
";

const MAIN: &str = "cell main {
  include \"lib.cell\"
  workspace w2
  fixed table reaches w1, w2
  movable gripper reaches w1
  support board
  object a {
    grasp g by gripper
    rest down on table
    transition down <-> g
  }
  object b {
    grasp g by gripper
    rest down on table
    transition down <-> g
  }
  request r: a from table.down in w1 to gripper.g in w1
}
";

#[test]
fn names_of_an_included_file_are_one_namespace() {
    let c = compiled(&[("/c/main.cell", MAIN), ("/c/lib.cell", LIB)]);
    assert!(!c.has_errors(), "{:?}", c.diagnostics);
    // `w1` is declared in the library (file 1) and used by the cell (file 0).
    assert_eq!(
        places(&c, &global("w1")),
        [
            (0, "w1".to_string(), false),
            (0, "w1".to_string(), false),
            (0, "w1".to_string(), false),
            (0, "w1".to_string(), false),
            (1, "w1".to_string(), true),
        ]
    );
    assert_eq!(c.names.kind_of(&global("paw")), Some(Kind::Hand));
    assert_eq!(c.names.kind_of(&global("table")), Some(Kind::Fixed));
    assert_eq!(c.names.kind_of(&global("gripper")), Some(Kind::Movable));
    assert_eq!(c.names.kind_of(&global("board")), Some(Kind::Support));
    assert_eq!(
        c.names.kind_of(&Key::Request("r".to_string())),
        Some(Kind::Request)
    );
    // The include line, resolved against the including file.
    let include = &c.names.includes()[0];
    assert_eq!(
        (include.file, include.path.as_str()),
        (FileId(0), "/c/lib.cell")
    );
    assert_eq!(
        c.names
            .include_at(FileId(0), include.span.start as usize + 1),
        Some(include)
    );
}

#[test]
fn grasps_are_scoped_by_their_object() {
    let c = compiled(&[("/c/main.cell", MAIN), ("/c/lib.cell", LIB)]);
    let lines = |key: &Key| -> Vec<(usize, bool)> {
        c.names
            .occurrences_of(key)
            .map(|o| (line(&c, o), o.declares.is_some()))
            .collect()
    };
    // `a`'s `g`: declared on line 7, used in its transition and in the request's goal.
    assert_eq!(
        lines(&grasp("a", "g")),
        [(7, true), (9, false), (16, false)]
    );
    // `b`'s `g`, the same word, is another name.
    assert_eq!(lines(&grasp("b", "g")), [(12, true), (14, false)]);
    assert_eq!(c.names.kind_of(&grasp("b", "down")), Some(Kind::Rest));
    // The name at a position of a transition is the grasp of that object.
    let at = c
        .sources
        .get(FileId(0))
        .text
        .find("<-> g\n  }\n  object b")
        .unwrap()
        + 4;
    assert_eq!(
        c.names.at(FileId(0), at).map(|o| &o.key),
        Some(&grasp("a", "g"))
    );
}

#[test]
fn a_duplicate_is_declared_twice_and_its_names_are_uses() {
    let text = "cell d {
  workspace w1
  workspace w1
  robot r urdf \"r.urdf\" tip t
  hand paw
  arm left = r at (0, 0, 0) with paw
  arm left = r at (0, 0, 0) with paw
  fixed t1 reaches w1
  fixed t1 reaches w1
}
";
    let c = compiled(&[("/c/d.cell", text)]);
    let declared: Vec<usize> = c
        .names
        .declarations(&global("w1"))
        .map(|o| line(&c, o))
        .collect();
    assert_eq!(declared, [1, 2]);
    // The second `arm left` is refused (E0102), yet its robot and hand are written there.
    let paw: Vec<usize> = c
        .names
        .occurrences_of(&global("paw"))
        .filter(|o| o.declares.is_none())
        .map(|o| line(&c, o))
        .collect();
    assert_eq!(paw, [5, 6]);
    let uses_of_w1 = c
        .names
        .occurrences_of(&global("w1"))
        .filter(|o| o.declares.is_none())
        .count();
    assert_eq!(uses_of_w1, 2, "both `reaches w1`");
}

#[test]
fn names_the_resolver_does_not_reach_are_still_written() {
    let text = "cell u {
  workspace w1
  fixed table reaches w1
  object a {
    grasp g by table
    grasp h by table
    transition missing <-> g, h
  }
  world {
    a: table in w1
  }
  world {
    a: table.h in w1
  }
}
";
    let c = compiled(&[("/c/u.cell", text)]);
    assert!(c.has_errors());
    // The first side is unknown, so the others are not looked up: they are uses anyway.
    assert_eq!(
        c.names.occurrences_of(&grasp("a", "g")).count(),
        2,
        "declared and used"
    );
    // The second `world` is refused whole; its names are uses.
    let h: Vec<usize> = c
        .names
        .occurrences_of(&grasp("a", "h"))
        .map(|o| line(&c, o))
        .collect();
    assert_eq!(h, [5, 6, 12]);
    assert_eq!(
        c.names
            .occurrences_of(&global("w1"))
            .filter(|o| line(&c, o) == 12)
            .count(),
        1
    );
}

#[test]
fn a_file_being_typed_still_has_its_names() {
    // `fixed gripper reaches` with nothing after it: a syntax error.
    let text = "cell t {\n  workspace w1\n  hand paw\n  object a {\n    grasp g by paw\n  }\n  fixed gripper reaches\n  movable m reaches w1\n}\n";
    let c = compiled(&[("/c/t.cell", text)]);
    assert!(c.has_errors());
    assert!(c.cell.is_none(), "no cell from a file that does not parse");
    assert!(
        c.diagnostics
            .iter()
            .all(|d| d.code == cellc_lang::phrases::codes::SYNTAX),
        "only the syntax error is reported: {:?}",
        c.diagnostics
    );
    assert_eq!(c.names.kind_of(&global("w1")), Some(Kind::Workspace));
    assert_eq!(c.names.kind_of(&grasp("a", "g")), Some(Kind::Grasp));
    assert_eq!(c.names.occurrences_of(&global("w1")).count(), 2);
}

#[test]
fn an_include_that_cannot_be_read_is_still_an_include() {
    let c = compiled(&[("/c/main.cell", "cell m {\n  include \"gone.cell\"\n}\n")]);
    let paths: Vec<&str> = c.names.includes().iter().map(|i| i.path.as_str()).collect();
    assert_eq!(paths, ["/c/gone.cell"]);
    assert!(Names::default().occurrences().is_empty());
}
