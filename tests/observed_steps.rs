//! An execution watched step by step: every step the simulator carried out is seen once,
//! in order, with the world it left — the world a durable store journals after each step.

use cellc_runtime::plan::{Command, PlanOptions, Step};
use cellc_runtime::{StepObserver, TaskOptions, World};

#[path = "support/world.rs"]
mod support;

/// Each step's command and the world after it.
#[derive(Default)]
struct Seen(Vec<(Command, World)>);

impl StepObserver for Seen {
    fn stepped(&mut self, world: &World, _object: cellc_runtime::ObjectId, step: &Step) {
        self.0.push((step.command.clone(), world.clone()));
    }
}

#[test]
fn every_step_of_vitos_tasks_is_seen_with_the_world_it_left() {
    let cell = support::vito();
    let initial = cell
        .initial_world(&PlanOptions::default())
        .expect("vito's world");
    let (mut grasps, mut releases) = (0, 0);
    for task in &cell.artifact().tasks {
        let moves = cell.task(&task.name).expect("declared");
        let options = TaskOptions {
            clear: true,
            ..TaskOptions::default()
        };
        let mut unwatched = initial.clone();
        let plain = cell.run_task(&mut unwatched, &moves, &options);
        let mut watched = initial.clone();
        let mut seen = Seen::default();
        let run = cell.run_task_observed(&mut watched, &moves, &options, Some(&mut seen));
        assert!(run.failure.is_none(), "task `{}` runs", task.name);
        // Watching changes nothing.
        assert_eq!(watched, unwatched, "{}", task.name);
        assert_eq!(run.record.len(), plain.record.len());
        let done: usize = run
            .record
            .iter()
            .map(|e| e.result.as_ref().expect("executed").steps_done)
            .sum();
        assert_eq!(seen.0.len(), done, "one sighting per step carried out");
        assert_eq!(
            seen.0.last().map(|(_, w)| w),
            Some(&watched),
            "the last is the end"
        );
        for (command, world) in &seen.0 {
            match command {
                Command::Grasp { holder, .. } => {
                    grasps += 1;
                    assert!(
                        world.held_by(*holder).is_some(),
                        "a grasp leaves the hand holding"
                    );
                }
                // A surface holds many objects; a hand one.
                Command::Ungrasp { holder, .. }
                    if cell.artifact().end_effectors[holder.index()].movable =>
                {
                    releases += 1;
                    assert!(
                        world.held_by(*holder).is_none(),
                        "a release leaves it empty: {holder:?} holds {:?}",
                        world
                            .held_by(*holder)
                            .map(|o| (o, world.whereabouts(o).clone()))
                    );
                }
                Command::Ungrasp { .. } | Command::Move { .. } => {}
            }
            // What a store keeps of each step reads back to that world.
            let document = cell.world_document(world);
            let back = cell
                .world(&document, &PlanOptions::default())
                .expect("reads back");
            assert_eq!(&back, world);
        }
    }
    assert!(
        grasps > 0 && releases > 0,
        "the tasks grasp and release ({grasps}, {releases})"
    );
}
