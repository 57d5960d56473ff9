//! What a name means in the language server is the resolver's answer (the compilation's
//! table of names, `cellc_compiler::names`): rename across an include and within one
//! object's grasps, refusals that would change the cell, and definition on a file with
//! a duplicate and a line being typed.

#[path = "support/lsp_client.rs"]
mod client;

use client::{find, Client};
use serde_json::{json, Value};

/// A folder of its own under the system's temporary folder, removed when dropped.
struct Folder(std::path::PathBuf);

impl Folder {
    fn new(name: &str) -> Folder {
        let dir = std::env::temp_dir().join(format!("cellc-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        Folder(dir)
    }

    /// Writes `text` to `file` in the folder; its URI.
    fn write(&self, file: &str, text: &str) -> String {
        let path = self.0.join(file);
        std::fs::write(&path, text).expect("written");
        format!("file://{}", path.display())
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const LIB: &str = "library lib {\n  workspace w1\n  hand paw\n}\n";

const MAIN: &str = "cell main {
  include \"lib.cell\"
  workspace w2
  fixed table reaches w1, w2
  movable gripper reaches w1
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

fn rename(client: &mut Client, uri: &str, (line, character): (u32, u32), to: &str) -> Value {
    client.request(
        "textDocument/rename",
        json!({
            "textDocument": { "uri": uri },
            "position": { "line": line, "character": character },
            "newName": to,
        }),
    )
}

/// The edits of a rename answer for `uri`, as (line, start column, new text), sorted.
fn edits(answer: &Value, uri: &str) -> Vec<(u64, u64, String)> {
    let mut found: Vec<(u64, u64, String)> = answer["result"]["changes"][uri]
        .as_array()
        .map(|edits| {
            edits
                .iter()
                .map(|e| {
                    let start = &e["range"]["start"];
                    (
                        start["line"].as_u64().unwrap_or(0),
                        start["character"].as_u64().unwrap_or(0),
                        e["newText"].as_str().unwrap_or_default().to_string(),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    found
}

#[test]
fn rename_follows_the_resolver_across_files_and_scopes() {
    let folder = Folder::new("lsp-rename");
    let lib = folder.write("lib.cell", LIB);
    let main = folder.write("main.cell", MAIN);
    let mut client = Client::start();
    client.open(&main, MAIN);
    // Warnings only (the resting poses on `table` in `w2` are never entered).
    let diagnostics = client.diagnostics(&main);
    assert!(
        diagnostics
            .as_array()
            .is_some_and(|d| d.iter().all(|d| d["severity"] == 2)),
        "{diagnostics}"
    );

    // `w1`, declared in the library, is written three times in the cell; a reserved word
    // as the new name is written in backticks.
    let at = find(MAIN, "w1, w2", 0);
    let prepared = client.at("textDocument/prepareRename", &main, at.0, at.1);
    assert_eq!(
        prepared["result"],
        json!({ "start": { "line": at.0, "character": at.1 }, "end": { "line": at.0, "character": at.1 + 2 } }),
        "{prepared}"
    );
    let answer = rename(&mut client, &main, at, "fixed");
    let quoted = "`fixed`".to_string();
    assert_eq!(edits(&answer, &lib), [(1, 12, quoted.clone())], "{answer}");
    assert_eq!(
        edits(&answer, &main),
        [
            (3, 22, quoted.clone()),
            (4, 26, quoted.clone()),
            (15, 34, quoted.clone()),
            (15, 53, quoted)
        ],
        "{answer}"
    );

    // `g` of object `a` (at its declaration): its transition and the request's goal, and
    // nothing of object `b`'s `g`.
    let at = find(MAIN, "g by gripper", 0);
    let answer = rename(&mut client, &main, at, "top");
    let top = "top".to_string();
    assert_eq!(
        edits(&answer, &main),
        [(6, 10, top.clone()), (8, 24, top.clone()), (15, 48, top)],
        "{answer}"
    );
    assert!(edits(&answer, &lib).is_empty(), "{answer}");

    // A name already declared in the scope is refused, and so is a name that cannot be
    // written.
    let at = find(MAIN, "w1, w2", 0);
    let taken = rename(&mut client, &main, at, "w2");
    assert_eq!(taken["error"]["code"], -32803, "{taken}");
    assert!(
        taken["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("`w2` is already declared as a workspace")),
        "{taken}"
    );
    let unwritable = rename(&mut client, &main, at, "a`b");
    assert_eq!(unwritable["error"]["code"], -32803, "{unwritable}");
    // `paw` may be renamed to `down`: grasps are another scope.
    let at = find(LIB, "paw", 0);
    client.open(&lib, LIB);
    client.diagnostics(&lib);
    let answer = rename(&mut client, &lib, at, "down");
    assert_eq!(
        edits(&answer, &lib),
        [(2, 7, "down".to_string())],
        "{answer}"
    );
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn a_name_not_declared_is_not_renamed() {
    let folder = Folder::new("lsp-undeclared");
    let text = "cell u {\n  workspace w1\n  fixed table reaches w1, w9\n}\n";
    let cell = folder.write("u.cell", text);
    let mut client = Client::start();
    client.open(&cell, text);
    client.diagnostics(&cell);
    let at = find(text, "w9", 0);
    let prepared = client.at("textDocument/prepareRename", &cell, at.0, at.1);
    assert_eq!(prepared["error"]["code"], -32803, "{prepared}");
    let answer = rename(&mut client, &cell, at, "w3");
    assert!(
        answer["error"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("`w9` is declared nowhere")),
        "{answer}"
    );
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn definition_of_a_duplicate_and_on_a_line_being_typed() {
    let folder = Folder::new("lsp-typing");
    // `w1` declared twice, and a `movable` line being typed (a syntax error).
    let text = "cell t {\n  workspace w1\n  workspace w1\n  fixed table reaches w1\n  movable m reaches \n}\n";
    let cell = folder.write("t.cell", text);
    let mut client = Client::start();
    client.open(&cell, text);
    let diagnostics = client.diagnostics(&cell);
    assert_eq!(diagnostics[0]["code"], "E0001", "{diagnostics}");
    let at = find(text, "w1\n  movable", 0);
    let definition = client.at("textDocument/definition", &cell, at.0, at.1);
    let lines: Vec<u64> = definition["result"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|l| l["range"]["start"]["line"].as_u64())
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(lines, [1, 2], "{definition}");
    // Completion after `reaches` offers the workspace though the line does not parse.
    let at = find(text, "reaches \n}", 8);
    let offered = client.at("textDocument/completion", &cell, at.0, at.1);
    assert_eq!(client::labels(&offered), ["w1"], "{offered}");
    assert_eq!(client.stop(), Some(0));
}
