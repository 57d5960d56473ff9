//! A world written as a world document and read back is the same world, bit for bit:
//! what the durable store relies on to give a restarted service the world it had.

use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, TaskOptions, World};

#[path = "support/world.rs"]
mod support;

fn round_trip(cell: &Cell, world: &World, what: &str) {
    let document = cell.world_document(world);
    let back = cell
        .world(&document, &PlanOptions::default())
        .unwrap_or_else(|e| panic!("{what}: the document does not read back: {e:?}"));
    assert_eq!(&back, world, "{what}: another world came back");
    assert_eq!(
        cell.world_document(&back),
        document,
        "{what}: another document"
    );
}

#[test]
fn vitos_worlds_read_back_as_they_were_written() {
    let cell = support::vito();
    let initial = cell
        .initial_world(&PlanOptions::default())
        .expect("vito's world");
    round_trip(&cell, &initial, "the initial world");
    let mut held = 0;
    for named in &cell.artifact().requests {
        let request = cell
            .named_request(&named.name, PlanOptions::default())
            .expect("declared");
        let start = cell.request_world(&initial, &request).expect("its start");
        let artifact = cell.artifact();
        held += usize::from((0..artifact.end_effectors.len()).any(|e| {
            artifact.end_effectors[e].movable
                && start
                    .held_by(cellc_schema::EndEffectorId(e as u32))
                    .is_some()
        }));
        round_trip(&cell, &start, &format!("the start of `{}`", named.name));
    }
    assert!(held > 0, "some request starts with an object in a hand");
    let mut moved = 0;
    for task in &cell.artifact().tasks {
        let moves = cell.task(&task.name).expect("declared");
        let mut world = initial.clone();
        let run = cell.run_task(&mut world, &moves, &TaskOptions::default());
        assert!(run.failure.is_none(), "task `{}` runs", task.name);
        moved += usize::from(world != initial);
        round_trip(&cell, &world, &format!("after task `{}`", task.name));
    }
    assert!(moved > 0, "some task leaves a different world");
}
