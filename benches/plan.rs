//! Planning benchmarks (issue 5): time per request, high level only (locate, Dijkstra,
//! simplification, commands, strategy) on the paper's Fig. 3 cell and on the graphs of
//! the original Vito database (`containerA` is the paper's pitcher, `containerB` its
//! colander), five start/goal pairs each, as in the paper's protocol.

use cellc_compiler::{compile, MemoryWorld};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Goal, Placement, PlanOptions, Request};
use cellc_schema::{Artifact, Node};
use criterion::{criterion_group, criterion_main, Criterion};

fn artifact(path: &str, text: &str) -> Artifact {
    let world = MemoryWorld::new([(path, text)]);
    let compilation = compile(&world, path);
    assert!(!compilation.has_errors(), "{path} has errors");
    cellc_compiler::artifact::lower(
        compilation.cell.as_ref().unwrap(),
        &compilation.graphs,
        &compilation.sources,
    )
}

fn request(a: &Artifact, object: usize, from: Node, to: Node) -> Request {
    let obj = &a.objects[object];
    let place = |n: Node| Placement {
        holder: a.end_effectors[n.end_effector as usize].name.clone(),
        grasp: Some(obj.grasps[n.grasp as usize].name.clone()),
        workspace: Some(a.workspaces[n.workspace as usize].name.clone()),
        pose: None,
    };
    Request {
        object: obj.name.clone(),
        start: place(from),
        goal: Goal::Placement(place(to)),
        options: PlanOptions {
            motions: false,
            ..PlanOptions::default()
        },
    }
}

/// Five reachable start/goal pairs: states of fixed holders, first and last workspaces,
/// spread over the graph deterministically.
fn pairs(a: &Artifact, object: usize) -> Vec<(Node, Node)> {
    let planner = Planner::new(a, None);
    let nodes = &a.objects[object].graph.nodes;
    let fixed: Vec<Node> = nodes
        .iter()
        .copied()
        .filter(|n| !a.end_effectors[n.end_effector as usize].movable)
        .collect();
    let mut out = Vec::new();
    let n = fixed.len();
    for i in 0..n * n {
        let (s, g) = (fixed[(i * 7) % n], fixed[(i * 13 + 5) % n]);
        if s.workspace == g.workspace {
            continue;
        }
        if planner.plan(&request(a, object, s, g)).is_ok() {
            out.push((s, g));
        }
        if out.len() == 5 {
            break;
        }
    }
    out
}

fn case(c: &mut Criterion, name: &str, a: &Artifact, object: &str) {
    let index = a
        .objects
        .iter()
        .position(|o| o.name == object)
        .expect("object exists");
    let requests: Vec<Request> = pairs(a, index)
        .into_iter()
        .map(|(s, g)| request(a, index, s, g))
        .collect();
    assert_eq!(requests.len(), 5, "{name}: five start/goal pairs");
    let planner = Planner::new(a, None);
    println!(
        "{name}: {} nodes, {} arcs",
        a.objects[index].graph.nodes.len(),
        a.objects[index].graph.arcs.len()
    );
    c.bench_function(name, |b| {
        b.iter(|| {
            for r in &requests {
                std::hint::black_box(planner.plan(r).expect("plans"));
            }
        })
    });
}

fn benches(c: &mut Criterion) {
    let fig3 = artifact(
        "fig3.cell",
        &std::fs::read_to_string("cells/fig3.cell").unwrap(),
    );
    case(c, "plan_high_level/fig3_cylinder_x5", &fig3, "cylinder");
    let imported =
        cellc::import::dualmanip(std::path::Path::new("tests/data/dualmanip/vito_full.db"))
            .expect("imports");
    let vito = artifact("vito_full.cell", &imported.text);
    case(c, "plan_high_level/vito_db_pitcher_x5", &vito, "containerA");
    case(
        c,
        "plan_high_level/vito_db_colander_x5",
        &vito,
        "containerB",
    );
}

criterion_group!(plan_benches, benches);
criterion_main!(plan_benches);
