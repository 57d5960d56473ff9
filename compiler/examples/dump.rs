struct Fs;
impl cellc_compiler::World for Fs {
    fn read(&self, p: &str) -> Result<String, String> {
        std::fs::read_to_string(p).map_err(|e| e.to_string())
    }
}
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let c = cellc_compiler::compile(&Fs, &path);
    let cell = c.cell.unwrap();
    for (_, w) in cell.workspaces.iter() {
        println!("ws {} {:?} {:?}", w.name, w.label, w.boxes.len());
    }
    for (_, e) in cell.end_effectors.iter() {
        println!(
            "ee {} reaches {:?}",
            e.name,
            e.reaches
                .iter()
                .map(|w| cell.workspaces[*w].name.clone())
                .collect::<Vec<_>>()
        );
    }
    for g in &c.graphs {
        println!(
            "{} nodes {} arcs {} moves {} transitions {}",
            cell.objects[g.object].name,
            g.graph.node_count(),
            g.graph.edge_count(),
            g.n_moves(),
            g.n_transitions()
        );
    }
    println!("{} diagnostics", c.diagnostics.len());
}
