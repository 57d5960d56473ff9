//! `cellc lsp` driven as an editor drives it (`support/lsp_client.rs`): diagnostics,
//! hover, navigation, completion, formatting and quick fixes, and a server that no
//! input stops. Answers are snapshotted with the checkout's path replaced by `$ROOT`.

#[path = "support/lsp_client.rs"]
mod client;

use std::io::Write;

use client::{find, labels, portable, text_of, uri, Client};
use serde_json::{json, Value};

/// A cell with one error: `w4` is not a workspace (E0101, did you mean `w1`?).
const BROKEN: &str = "cell small {\n  workspace w1\n  workspace w2\n  fixed table reaches w1, w4\n  movable gripper reaches w1, w2\n  object box {\n    grasp down by table\n    grasp held by gripper\n    transition down <-> held\n  }\n}\n";

#[test]
fn shipped_cell_is_clean_and_an_error_shows_and_clears() {
    let mut client = Client::start();
    let vito = uri("cells/vito.cell");
    client.open(&vito, &text_of("cells/vito.cell"));
    assert_eq!(client.diagnostics(&vito), json!([]));

    let broken = uri("target/lsp-test/broken.cell");
    client.open(&broken, BROKEN);
    let diagnostics = client.diagnostics(&broken);
    assert_eq!(diagnostics[0]["code"], "E0101", "{diagnostics}");
    let (line, column) = find(BROKEN, "w4", 0);
    assert_eq!(
        diagnostics[0]["range"]["start"],
        json!({ "line": line, "character": column })
    );
    assert_eq!(
        diagnostics[0]["range"]["end"],
        json!({ "line": line, "character": column + 2 })
    );
    insta::assert_snapshot!("broken_diagnostics", portable(&diagnostics));

    // The quick fix of its "did you mean".
    let actions = client.request(
        "textDocument/codeAction",
        json!({
            "textDocument": { "uri": broken },
            "range": diagnostics[0]["range"],
            "context": { "diagnostics": diagnostics },
        }),
    );
    let edit = &actions["result"][0]["edit"]["changes"][&broken][0];
    assert_eq!(edit["newText"], "w1", "{actions}");
    let declare = &actions["result"][1];
    assert_eq!(declare["title"], "declare `workspace w4`", "{actions}");
    let insert = &declare["edit"]["changes"][&broken][0];
    assert_eq!(insert["newText"], "  workspace w4\n");
    assert_eq!(
        insert["range"]["start"],
        json!({ "line": 10, "character": 0 })
    );

    // Two changes queued at once: the last one counts.
    let fixed = BROKEN.replace("w1, w4", "w1, w2");
    for (version, text) in [(2, BROKEN.replace("w4", "w5")), (3, fixed)] {
        client.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": broken, "version": version },
                "contentChanges": [{ "text": text }],
            }),
        );
    }
    let mut cleared = client.diagnostics(&broken);
    // The first change may have been compiled on its own if it arrived alone.
    if cleared != json!([]) {
        cleared = client.diagnostics(&broken);
    }
    assert_eq!(cleared, json!([]));
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn hover_describes_workspaces_arms_and_grasps() {
    let mut client = Client::start();
    let vito = uri("cells/vito.cell");
    let source = text_of("cells/vito.cell");
    client.open(&vito, &source);
    let mut answers = Vec::new();
    for (needle, skip) in [
        ("in ws_left_table", 4),
        ("left.top in", 6),
        ("arm left", 5),
        ("softhand home", 2),
        ("grasp top", 7),
        ("surface table", 9),
        ("lwr4 at (0, 0.1086", 13),
        ("(0, 0.1086, 1.375) rpy (-60", 25),
        ("lwr_a1_joint 100", 14),
    ] {
        let (line, column) = find(&source, needle, skip);
        let answer = client.at("textDocument/hover", &vito, line, column);
        answers.push(json!({ "at": needle, "hover": answer["result"] }));
    }
    let grasp = answers[4]["hover"]["contents"]["value"]
        .as_str()
        .unwrap_or_default()
        .to_string();
    assert!(
        grasp.contains("at (0, 0.12, 0.09) m rpy (90, -90, 0) deg"),
        "{grasp}"
    );
    let value = |i: usize| answers[i]["hover"]["contents"]["value"].clone();
    assert_eq!(value(6), "**length** 0.1086 m");
    assert_eq!(value(7), "**angle** -60° (-1.0472 rad)");
    assert_eq!(value(8), "**home of `lwr_a1_joint`** 100° (1.7453 rad)");
    insta::assert_snapshot!("hover", portable(&json!(answers)));
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn definition_and_references_cross_includes() {
    let mut client = Client::start();
    let vito = uri("cells/vito.cell");
    let source = text_of("cells/vito.cell");
    client.open(&vito, &source);
    // `softhand` in `arm left = lwr4 ... with softhand` is declared in robots/softhand.cell.
    let (line, column) = find(&source, "softhand home", 2);
    let definition = client.at("textDocument/definition", &vito, line, column);
    let library = text_of("cells/robots/softhand.cell");
    let (decl_line, decl_column) = find(&library, "hand softhand", 5);
    assert_eq!(
        definition["result"]["uri"],
        uri("cells/robots/softhand.cell")
    );
    assert_eq!(
        definition["result"]["range"]["start"],
        json!({ "line": decl_line, "character": decl_column })
    );
    // An include's path goes to the file.
    let (line, column) = find(&source, "robots/softhand.cell", 3);
    let file = client.at("textDocument/definition", &vito, line, column);
    assert_eq!(file["result"]["uri"], uri("cells/robots/softhand.cell"));

    let references = client.at("textDocument/references", &vito, line, column);
    assert_eq!(references["result"], Value::Null, "no name at an include");
    let (line, column) = find(&source, "softhand home", 2);
    let references = client.at("textDocument/references", &vito, line, column);
    let places = references["result"].as_array().cloned().unwrap_or_default();
    // Declared once in the library, used by both arms and every grasp of the cell.
    let in_library = places
        .iter()
        .filter(|l| l["uri"] == uri("cells/robots/softhand.cell"))
        .count();
    assert_eq!(in_library, 1, "{references}");
    assert!(places.len() > 3, "{references}");
    insta::assert_snapshot!("references", portable(&references["result"]));
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn completion_symbols_and_formatting() {
    let mut client = Client::start();
    let vito = uri("cells/vito.cell");
    let source = text_of("cells/vito.cell");
    client.open(&vito, &source);
    // At the start of an item (the blank line before `workspaces from reach`).
    let (line, _) = find(&source, "  workspaces from reach", 0);
    let items = client.at("textDocument/completion", &vito, line - 1, 0);
    let labels: Vec<&str> = items["result"]
        .as_array()
        .map(|a| a.iter().filter_map(|i| i["label"].as_str()).collect())
        .unwrap_or_default();
    assert!(
        labels.contains(&"workspace") && labels.contains(&"object"),
        "{items}"
    );
    // After `with`, holder kinds.
    let (line, column) = find(&source, "with softhand", 5);
    let kinds = client.at("textDocument/completion", &vito, line, column);
    let kinds: Vec<&str> = kinds["result"]
        .as_array()
        .map(|a| a.iter().filter_map(|i| i["label"].as_str()).collect())
        .unwrap_or_default();
    assert!(
        kinds.contains(&"softhand") && !kinds.contains(&"left"),
        "{kinds:?}"
    );
    // In a `reaches` list, workspaces.
    let broken = uri("target/lsp-test/list.cell");
    client.open(&broken, BROKEN);
    let (line, column) = find(BROKEN, "w1, w2", 4);
    let in_list = client.at("textDocument/completion", &broken, line, column);
    let in_list: Vec<&str> = in_list["result"]
        .as_array()
        .map(|a| a.iter().filter_map(|i| i["label"].as_str()).collect())
        .unwrap_or_default();
    assert_eq!(in_list, ["w1", "w2"]);
    // Inside `home (`, the arm's joints.
    let (line, column) = find(&source, "home (lwr_a1_joint", 6);
    let joints = client.at("textDocument/completion", &vito, line, column);
    assert!(joints.to_string().contains("lwr_a7_joint"), "{joints}");
    // After `allow contact ARM.`, the links of the arm's robot.
    let (line, column) = find(&source, "allow contact left.", 19);
    let links = client.at("textDocument/completion", &vito, line, column);
    assert!(links.to_string().contains("lwr_link_7"), "{links}");

    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": vito } }),
    );
    insta::assert_snapshot!("document_symbols", portable(&symbols["result"]));
    let found = client.request("workspace/symbol", json!({ "query": "soft" }));
    assert!(found.to_string().contains("softhand.cell"), "{found}");

    // Formatting an unformatted cell: one edit to the formatter's output.
    let messy = uri("target/lsp-test/messy.cell");
    let text = "cell messy {\nworkspace   w1\n    fixed t reaches w1\n}\n";
    client.open(&messy, text);
    let edits = client.request(
        "textDocument/formatting",
        json!({ "textDocument": { "uri": messy }, "options": { "tabSize": 2, "insertSpaces": true } }),
    );
    let parsed = cellc_lang::parse(cellc_lang::FileId(0), text);
    let expected = cellc_lang::format(&parsed.file.expect("it parses"), text);
    assert_eq!(edits["result"][0]["newText"], expected, "{edits}");
    assert_eq!(
        edits["result"][0]["range"]["end"],
        json!({ "line": 4, "character": 0 })
    );
    // A range in the `fixed` line formats that item alone: one edit of its line.
    let one = client.request(
        "textDocument/rangeFormatting",
        json!({
            "textDocument": { "uri": messy },
            "range": { "start": { "line": 2, "character": 6 }, "end": { "line": 2, "character": 7 } },
            "options": { "tabSize": 2, "insertSpaces": true },
        }),
    );
    assert_eq!(
        one["result"],
        json!([{
            "range": { "start": { "line": 2, "character": 0 }, "end": { "line": 3, "character": 0 } },
            "newText": "  fixed t reaches w1\n",
        }]),
        "{one}"
    );
    // One that does not parse is left alone.
    let broken = uri("target/lsp-test/unparsable.cell");
    client.open(&broken, "cell x {\n  workspace\n}\n");
    let none = client.request(
        "textDocument/formatting",
        json!({ "textDocument": { "uri": broken }, "options": { "tabSize": 2, "insertSpaces": true } }),
    );
    assert_eq!(none["result"], json!([]), "{none}");
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn a_corrupted_stream_never_stops_the_server() {
    let mut client = Client::start();
    // Lengths that would allocate a terabyte or overflow, each followed by two bytes.
    for length in ["1000000000000", "18446744073709551615"] {
        let frame = format!("Content-Length: {length}\r\n\r\nab");
        client.stdin.write_all(frame.as_bytes()).expect("write");
        let error = client.response(Value::Null);
        assert_eq!(error["error"]["code"], -32700, "{error}");
        let hover = client.request("cell/teleport", json!({}));
        assert_eq!(hover["error"]["code"], -32601, "{length}: {hover}");
    }
    // A header line of a megabyte with no end, then a valid message.
    let long = vec![b'x'; 1 << 20];
    client.stdin.write_all(&long).expect("write");
    let error = client.response(Value::Null);
    assert_eq!(error["error"]["code"], -32700, "{error}");
    let alive = client.request("cell/teleport", json!({}));
    assert_eq!(alive["error"]["code"], -32601, "{alive}");
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn garbage_never_stops_the_server() {
    let mut client = Client::start();
    client.write_raw("this is not json");
    let error = client.response(Value::Null);
    assert_eq!(error["error"]["code"], -32700, "{error}");
    client.write_raw(
        r#"{"jsonrpc":"2.0","id":99,"method":"textDocument/hover","params":{"nonsense":1}}"#,
    );
    let invalid = client.response(json!(99));
    assert_eq!(invalid["error"]["code"], -32602, "{invalid}");
    let unknown = client.request("cell/teleport", json!({}));
    assert_eq!(unknown["error"]["code"], -32601, "{unknown}");
    // A cell that does not parse, then requests on it.
    let bad = uri("target/lsp-test/garbage.cell");
    client.open(&bad, "cell { ] ] \u{0} `");
    let diagnostics = client.diagnostics(&bad);
    assert!(
        diagnostics.as_array().is_some_and(|d| !d.is_empty()),
        "{diagnostics}"
    );
    let hover = client.at("textDocument/hover", &bad, 0, 3);
    assert_eq!(hover["result"], Value::Null, "{hover}");
    let vito = uri("cells/vito.cell");
    client.open(&vito, &text_of("cells/vito.cell"));
    assert_eq!(client.diagnostics(&vito), json!([]));
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn secondary_labels_and_unsaved_includes() {
    let mut client = Client::start();
    // A duplicate: the first declaration is related information.
    let twice = uri("target/lsp-test/twice.cell");
    let text = "cell twice {\n  workspace w1\n  workspace w1\n  fixed t reaches w1\n}\n";
    client.open(&twice, text);
    let diagnostics = client.diagnostics(&twice);
    assert_eq!(diagnostics[0]["code"], "E0102", "{diagnostics}");
    let related = &diagnostics[0]["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], twice.as_str(), "{diagnostics}");
    assert_eq!(
        related["location"]["range"]["start"],
        json!({ "line": 1, "character": 12 })
    );

    // The cell includes the library; the library's unsaved text breaks it, and the error
    // is published for the library's URI.
    let vito = uri("cells/vito.cell");
    client.open(&vito, &text_of("cells/vito.cell"));
    assert_eq!(client.diagnostics(&vito), json!([]));
    let library = uri("cells/robots/softhand.cell");
    let broken = text_of("cells/robots/softhand.cell").replace("hand softhand", "hand soft_hand");
    client.open(&library, &broken);
    let in_library = client.diagnostics(&library);
    assert_eq!(in_library, json!([]), "the library alone is clean");
    let in_cell = client.diagnostics(&vito);
    assert!(in_cell.to_string().contains("softhand"), "{in_cell}");
    assert_eq!(client.stop(), Some(0));
}

#[test]
fn an_error_in_an_included_file_is_published_for_that_file() {
    let dir = std::env::temp_dir().join(format!("cellc-lsp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let lib = dir.join("lib.cell");
    std::fs::write(
        &lib,
        "library lib {\n  workspace w1\n  fixed t reaches w9\n}\n",
    )
    .expect("written");
    let main = dir.join("main.cell");
    let main_text = "cell main {\n  include \"lib.cell\"\n}\n";
    std::fs::write(&main, main_text).expect("written");
    let mut client = Client::start();
    let main_uri = format!("file://{}", main.display());
    client.open(&main_uri, main_text);
    let lib_uri = format!("file://{}", lib.display());
    let diagnostics = client.diagnostics(&lib_uri);
    let unknown = diagnostics
        .as_array()
        .and_then(|d| d.iter().find(|d| d["code"] == "E0101"))
        .unwrap_or_else(|| panic!("{diagnostics}"));
    assert_eq!(
        unknown["range"]["start"],
        json!({ "line": 2, "character": 18 })
    );
    assert_eq!(client.diagnostics(&main_uri), json!([]));
    assert_eq!(client.stop(), Some(0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn completion_of_grasps_after_a_holder_and_in_transitions() {
    let mut client = Client::start();
    let vito = uri("cells/vito.cell");
    let source = text_of("cells/vito.cell");
    client.open(&vito, &source);
    // `request single_arm_regrasp: cylinder from left.top ...`: the cylinder's grasps
    // that the left arm (a softhand) holds, not its resting poses.
    let (line, column) = find(&source, "left.top in ws_left_table", 5);
    let by_arm = labels(&client.at("textDocument/completion", &vito, line, column));
    assert_eq!(by_arm, ["top", "bottom", "side"], "{by_arm:?}");
    // `... to table.lying in ...`: the resting poses on the tabletop, not the bin's.
    let (line, column) = find(&source, "table.lying in ws_left_table", 6);
    let on_table = labels(&client.at("textDocument/completion", &vito, line, column));
    assert_eq!(
        on_table,
        ["standing", "upside_down", "lying"],
        "{on_table:?}"
    );
    // `expect cylinder: table.standing ...`: the same, from an expectation.
    let (line, column) = find(&source, "table.standing in ws_left_table ->", 6);
    let expected = labels(&client.at("textDocument/completion", &vito, line, column));
    assert_eq!(expected, on_table);
    // In a transition of the cylinder: every grasp and resting pose of the cylinder.
    let (line, column) = find(&source, "transition standing <-> top", 24);
    let in_transition = client.at("textDocument/completion", &vito, line, column);
    let names = labels(&in_transition);
    assert!(
        names.contains(&"dropped".to_string()) && names.contains(&"top".to_string()),
        "{names:?}"
    );
    assert!(!names.contains(&"handle".to_string()), "{names:?}");
    insta::assert_snapshot!("grasp_completion", portable(&in_transition["result"]));

    // A world entry and a task step of a cell being written, and a transition naming
    // another object's grasp (`OTHER.`).
    let text = "cell g {\n  workspace w1\n  fixed table reaches w1\n  movable gripper reaches w1\n  object a {\n    grasp down by table\n    grasp held by gripper\n    transition down <-> held\n  }\n  object b {\n    grasp low by table\n    transition low <-> a.\n  }\n  world {\n    a: gripper.\n  }\n  task t {\n    a to table.\n  }\n}\n";
    let cell = uri("target/lsp-test/grasps.cell");
    client.open(&cell, text);
    client.diagnostics(&cell);
    let (line, column) = find(text, "a.\n", 2);
    let other = labels(&client.at("textDocument/completion", &cell, line, column));
    assert_eq!(other, ["down", "held"], "{other:?}");
    let (line, column) = find(text, "gripper.\n", 8);
    let world = labels(&client.at("textDocument/completion", &cell, line, column));
    assert_eq!(world, ["held"], "{world:?}");
    let (line, column) = find(text, "table.\n", 6);
    let step = labels(&client.at("textDocument/completion", &cell, line, column));
    assert_eq!(step, ["down"], "{step:?}");
    assert_eq!(client.stop(), Some(0));
}

/// `text` with one insertion at `position` (ASCII text).
fn insert_at(text: &str, position: &Value, insert: &str) -> String {
    let line = position["line"].as_u64().unwrap_or(0) as usize;
    let column = position["character"].as_u64().unwrap_or(0) as usize;
    let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
    let at = start + column;
    format!("{}{insert}{}", &text[..at], &text[at..])
}

#[test]
fn a_missing_declaration_is_added_and_the_error_goes() {
    let text = "cell decl {\n  workspace w1\n  fixed table reaches w1\n  surface shelf : board box center (0, 0, 0) size (1, 1, 0.1)\n  object box {\n    grasp down by table\n    grasp held by gripper\n    transition down <-> held\n  }\n  request r: crate from table in w1 to table in w1\n}\n";
    let mut client = Client::start();
    let cell = uri("target/lsp-test/declare.cell");
    client.open(&cell, text);
    let diagnostics = client.diagnostics(&cell);
    let unknown: Vec<Value> = diagnostics
        .as_array()
        .map(|d| d.iter().filter(|d| d["code"] == "E0101").cloned().collect())
        .unwrap_or_default();
    assert_eq!(unknown.len(), 3, "{diagnostics}");
    let actions = client.request(
        "textDocument/codeAction",
        json!({
            "textDocument": { "uri": cell },
            "range": { "start": { "line": 0, "character": 0 }, "end": { "line": 10, "character": 0 } },
            "context": { "diagnostics": unknown },
        }),
    );
    insta::assert_snapshot!("declare_actions", portable(&actions["result"]));
    let titles: Vec<&str> = actions["result"]
        .as_array()
        .map(|a| a.iter().filter_map(|a| a["title"].as_str()).collect())
        .unwrap_or_default();
    assert_eq!(
        titles,
        [
            "declare `support board`",
            "declare `movable gripper reaches w1`",
            "declare `object crate {}`",
        ],
        "{actions}"
    );
    // Each edit alone: the declaration parses, the formatter keeps it, and its error
    // goes (the others stay).
    for (version, (action, d)) in actions["result"]
        .as_array()
        .cloned()
        .unwrap_or_default()
        .iter()
        .zip(&unknown)
        .enumerate()
    {
        let edit = &action["edit"]["changes"][&cell][0];
        let inserted = edit["newText"].as_str().unwrap_or_default();
        let edited = insert_at(text, &edit["range"]["start"], inserted);
        let parsed = cellc_lang::parse(cellc_lang::FileId(0), &edited);
        let tree = parsed.file.expect("it parses");
        assert!(parsed.diagnostics.is_empty(), "{edited}");
        assert!(
            cellc_lang::format(&tree, &edited).contains(inserted),
            "{edited}"
        );
        client.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": cell, "version": version + 2 },
                "contentChanges": [{ "text": edited }],
            }),
        );
        let after = client.diagnostics(&cell);
        let messages: Vec<&str> = after
            .as_array()
            .map(|a| a.iter().filter_map(|d| d["message"].as_str()).collect())
            .unwrap_or_default();
        let gone = d["message"].as_str().unwrap_or_default().lines().next();
        assert!(
            !messages.iter().any(|m| m.lines().next() == gone),
            "{gone:?} is still there: {after}"
        );
        let still = after
            .as_array()
            .map_or(0, |a| a.iter().filter(|d| d["code"] == "E0101").count());
        assert_eq!(still, 2, "{after}");
    }
    assert_eq!(client.stop(), Some(0));
}
