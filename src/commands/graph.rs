//! `cellc graph INPUT --object O [--emit dot|json|svg]`

use std::fmt::Write;
use std::process::ExitCode;

use crate::args::GraphFormat;

use cellc_schema::{ArcKind, Artifact, Object};
use serde::Serialize;

/// Prints the object-state graph of one object.
pub fn run(
    path: &str,
    object: &str,
    format: GraphFormat,
    color: crate::render::Color,
    options: &cellc_compiler::CompileOptions,
) -> ExitCode {
    // A JSON graph has JSON diagnostics, so standard output stays JSON on every path.
    let report = crate::render::Style {
        format: match format {
            GraphFormat::Dot | GraphFormat::Svg => crate::render::Format::Human,
            GraphFormat::Json => crate::render::Format::Json,
        },
        color,
    };
    let Some(artifact) = crate::artifact_io::cell_or_artifact(path, report, options) else {
        return ExitCode::from(1);
    };
    let Some(obj) = artifact.objects.iter().find(|o| o.name == object) else {
        let known: Vec<&str> = artifact.objects.iter().map(|o| o.name.as_str()).collect();
        let help = match cellc_lang::diagnostic::did_you_mean(object, known.iter().copied()) {
            Some(s) => format!("did you mean `{s}`?"),
            None => format!("the objects are: {}", known.join(", ")),
        };
        let d = cellc_lang::Diagnostic::error(
            cellc_compiler::diagnostics::codes::UNKNOWN_NAME,
            format!("unknown object `{object}`"),
        )
        .help(help);
        crate::render::emit(report, &[d], &cellc_lang::SourceMap::new());
        return ExitCode::from(1);
    };
    match format {
        GraphFormat::Dot => print!("{}", dot(&artifact, obj)),
        GraphFormat::Json => print!("{}", json(&artifact, obj)),
        GraphFormat::Svg => print!("{}", svg(&artifact, obj)),
    }
    ExitCode::SUCCESS
}

/// SVG laid out without Graphviz ([`crate::graph_svg`]), pruned arcs with their reasons.
pub fn svg(a: &Artifact, o: &Object) -> String {
    let reason = |i: usize| {
        o.graph
            .pruned
            .get(i)
            .map(|p| cellc_driver::explain_report::words::infeasibility(a, &p.reason))
            .unwrap_or_default()
    };
    crate::graph_svg::svg(a, o, &reason)
}

fn quote(text: &str) -> String {
    let escaped = text
        .replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n");
    format!("\"{escaped}\"")
}

/// DOT in the style of the paper's Fig. 6.
pub fn dot(a: &Artifact, o: &Object) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "digraph {} {{", quote(&o.name));
    let _ = writeln!(
        out,
        "  compound=true;\n  node [shape=box, style=rounded, fontsize=10];"
    );
    for (w, ws) in a.workspaces.iter().enumerate() {
        let nodes: Vec<usize> = (0..o.graph.nodes.len())
            .filter(|&n| o.graph.nodes[n].workspace.index() == w)
            .collect();
        if nodes.is_empty() {
            continue;
        }
        let label = match &ws.label {
            Some(l) if !ws.derived => format!("{} ({l})", ws.name),
            _ => ws.name.clone(),
        };
        let _ = writeln!(
            out,
            "  subgraph {} {{",
            quote(&format!("cluster_{}", ws.name))
        );
        let _ = writeln!(out, "    label={};", quote(&label));
        for n in nodes {
            let node = o.graph.nodes[n];
            let ee = a
                .end_effectors
                .get(node.end_effector.index())
                .map_or("?", |e| e.name.as_str());
            let grasp = o
                .grasps
                .get(node.grasp.index())
                .map_or("?", |g| g.name.as_str());
            let _ = writeln!(
                out,
                "    n{n} [label={}];",
                quote(&format!("{ee}\n{grasp}"))
            );
        }
        let _ = writeln!(out, "  }}");
    }
    for arc in &o.graph.arcs {
        let style = match arc.kind {
            ArcKind::Move => "dashed",
            ArcKind::Transition => "solid",
        };
        let _ = writeln!(out, "  n{} -> n{} [style={style}];", arc.from, arc.to);
    }
    out.push_str("}\n");
    out
}

#[derive(Serialize)]
struct JsonGraph<'a> {
    object: &'a str,
    nodes: Vec<JsonNode<'a>>,
    arcs: Vec<JsonArc>,
}

#[derive(Serialize)]
struct JsonNode<'a> {
    id: usize,
    end_effector: &'a str,
    grasp: &'a str,
    workspace: &'a str,
}

#[derive(Serialize)]
struct JsonArc {
    from: u32,
    to: u32,
    kind: ArcKind,
    weight: f64,
    line: Option<u32>,
}

/// The graph with names, for programs.
pub fn json(a: &Artifact, o: &Object) -> String {
    let doc = JsonGraph {
        object: &o.name,
        nodes: o
            .graph
            .nodes
            .iter()
            .enumerate()
            .map(|(id, n)| JsonNode {
                id,
                end_effector: a
                    .end_effectors
                    .get(n.end_effector.index())
                    .map_or("?", |e| &e.name),
                grasp: o.grasps.get(n.grasp.index()).map_or("?", |g| &g.name),
                workspace: a
                    .workspaces
                    .get(n.workspace.index())
                    .map_or("?", |w| &w.name),
            })
            .collect(),
        arcs: o
            .graph
            .arcs
            .iter()
            .map(|arc| JsonArc {
                from: arc.from,
                to: arc.to,
                kind: arc.kind,
                weight: arc.weight,
                line: a.spans.get(arc.source as usize).map(|s| s.line),
            })
            .collect(),
    };
    serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
}
