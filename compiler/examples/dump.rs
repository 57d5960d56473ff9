struct Fs;
impl cellc_compiler::Files for Fs {
    fn read(&self, p: &str) -> Result<Vec<u8>, cellc_schema::FileError> {
        Ok(std::fs::read(p)?)
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
