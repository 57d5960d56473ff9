//! Watching an execution step by step: what a durable store needs to journal each step
//! with the world it left before the next one starts, so that a service that stops
//! mid-task knows how far the cell got.
//!
//! [`Observed`] wraps any [`Executor`]: after each step the executor carried out, it
//! brings a copy of the world up to date from what the executor reports (the same update
//! [`Cell::execute`] makes at the end) and hands it to the [`StepObserver`]. The
//! execution itself is unchanged: the observer sees, it does not steer.

use cellc_schema::ObjectId;

use crate::cell::Cell;
use crate::execute::{Executor, ObservedObject, StepError};
use crate::plan::Step;
use crate::world::World;

/// Told of every step an execution carried out, in order, with the world as that step
/// left it.
pub trait StepObserver {
    /// `step` of a plan moving `object` is done; `world` is the cell after it (every
    /// object, the moved one where the executor says it is, the arms where they stand).
    fn stepped(&mut self, world: &World, object: ObjectId, step: &Step);
}

/// An executor whose steps a [`StepObserver`] sees.
pub(crate) struct Observed<'a, 'o> {
    inner: &'a mut dyn Executor,
    cell: &'a Cell,
    object: ObjectId,
    world: World,
    observer: &'a mut (dyn StepObserver + 'o),
}

impl<'a, 'o> Observed<'a, 'o> {
    /// Watches `inner` executing a plan for `object` that starts in `world`.
    pub(crate) fn new(
        inner: &'a mut dyn Executor,
        cell: &'a Cell,
        object: ObjectId,
        world: World,
        observer: &'a mut (dyn StepObserver + 'o),
    ) -> Observed<'a, 'o> {
        Observed {
            inner,
            cell,
            object,
            world,
            observer,
        }
    }
}

impl Executor for Observed<'_, '_> {
    fn execute(&mut self, step: &Step) -> Result<(), StepError> {
        self.inner.execute(step)?;
        self.cell
            .observe(&mut self.world, self.object, &*self.inner);
        self.observer.stepped(&self.world, self.object, step);
        Ok(())
    }

    fn object_state(&self) -> ObservedObject {
        self.inner.object_state()
    }

    fn arms(&self) -> Vec<Option<Vec<f64>>> {
        self.inner.arms()
    }
}
