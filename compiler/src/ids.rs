//! Typed ids and the arena that owns what they point to.
//!
//! Inside the compiler nothing is looked up by string: a name is resolved once, to an id,
//! and every later phase indexes an [`Arena`] with it. Mixing up a grasp id and a
//! workspace id is a type error, not a wrong answer.

use std::marker::PhantomData;
use std::ops::{Index, IndexMut};

/// An index into an [`Arena`] of `T`.
pub trait Id: Copy + Eq + std::hash::Hash + Ord + std::fmt::Debug {
    /// From a position in the arena.
    fn from_index(index: usize) -> Self;
    /// The position in the arena.
    fn index(self) -> usize;
}

macro_rules! define_id {
    ($(#[$doc:meta] $name:ident),* $(,)?) => {$(
        #[$doc]
        #[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
        pub struct $name(pub u32);
        impl Id for $name {
            fn from_index(index: usize) -> Self { $name(index as u32) }
            fn index(self) -> usize { self.0 as usize }
        }
    )*};
}

define_id!(
    /// A workspace.
    WorkspaceId,
    /// An end-effector (a hand on an arm, a conveyor, or a fixed surface).
    EndEffectorId,
    /// A holder kind (a hand model or a support kind).
    HolderKindId,
    /// A robot model from a URDF.
    RobotId,
    /// An object.
    ObjectId,
    /// A grasp or resting pose declaration of one object.
    GraspId,
);

/// Owns values of `T`, addressed by ids of type `I`, in insertion order.
#[derive(Clone, Debug)]
pub struct Arena<I, T> {
    items: Vec<T>,
    _id: PhantomData<I>,
}

impl<I: Id, T> Default for Arena<I, T> {
    fn default() -> Self {
        Arena {
            items: Vec::new(),
            _id: PhantomData,
        }
    }
}

impl<I: Id, T> Arena<I, T> {
    /// Adds a value, returning its id.
    pub fn insert(&mut self, value: T) -> I {
        self.items.push(value);
        I::from_index(self.items.len() - 1)
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Ids and values in insertion order.
    pub fn iter(&self) -> impl Iterator<Item = (I, &T)> + '_ {
        self.items
            .iter()
            .enumerate()
            .map(|(i, v)| (I::from_index(i), v))
    }

    /// All ids in insertion order.
    pub fn ids(&self) -> impl Iterator<Item = I> + '_ {
        (0..self.items.len()).map(I::from_index)
    }

    /// The value behind an id, if it is in range.
    pub fn get(&self, id: I) -> Option<&T> {
        self.items.get(id.index())
    }
}

impl<I: Id, T> Index<I> for Arena<I, T> {
    type Output = T;
    fn index(&self, id: I) -> &T {
        &self.items[id.index()]
    }
}

impl<I: Id, T> IndexMut<I> for Arena<I, T> {
    fn index_mut(&mut self, id: I) -> &mut T {
        &mut self.items[id.index()]
    }
}
