//! Every name written in a compilation's files, where it is declared and where it is
//! used, as the resolver scoped it: the one answer to "what does this name mean" that an
//! editor reads for definition, references, hover, rename and completion.
//!
//! The resolver fills the table as it resolves ([`crate::resolve`]): a declaration is
//! recorded where the resolver declares it, a use where the resolver looks it up. So the
//! scopes are the resolver's own: one namespace for workspaces, end-effectors, holder
//! kinds, robots, objects and obstacles, across every included file; grasps and resting
//! poses per object; requests and tasks a namespace of their own. Names that the resolver
//! reads but does not resolve further (an item refused as a duplicate, the other side of
//! a transition whose first side is unknown, a second `world`) are recorded as uses all
//! the same: they are written names, and renaming a declaration must rename them too.
//!
//! Keys are names, not typed ids: an editor compares the names of two compilations (a
//! library included by two open cells), whose ids differ; and a name that does not
//! resolve has no id but is still written somewhere.

use cellc_lang::{FileId, Span};

use crate::diagnostics::Sort;

/// What a declaration declares, finer than [`Sort`] (an arm and a surface are both
/// end-effectors, but an editor shows them apart).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// `workspace NAME ...`
    Workspace,
    /// `fixed NAME reaches ...`
    Fixed,
    /// `movable NAME reaches ...`
    Movable,
    /// `arm NAME = ROBOT ...`
    Arm,
    /// `surface NAME : KIND ...`
    Surface,
    /// `hand NAME { ... }`
    Hand,
    /// `support NAME`
    Support,
    /// `robot NAME urdf ...`
    Robot,
    /// `object NAME { ... }`
    Object,
    /// `grasp NAME ... by HOLDER` (a family counts as one declaration, by its name)
    Grasp,
    /// `rest NAME ... on KIND`
    Rest,
    /// `obstacle NAME box ...`
    Obstacle,
    /// `request NAME: ...`
    Request,
    /// `task NAME { ... }`
    Task,
}

impl Kind {
    /// The word people use for it.
    pub fn noun(self) -> &'static str {
        match self {
            Kind::Workspace => "workspace",
            Kind::Fixed => "fixed end-effector",
            Kind::Movable => "movable end-effector",
            Kind::Arm => "arm",
            Kind::Surface => "surface",
            Kind::Hand => "hand kind",
            Kind::Support => "support kind",
            Kind::Robot => "robot",
            Kind::Object => "object",
            Kind::Grasp => "grasp",
            Kind::Rest => "resting pose",
            Kind::Obstacle => "obstacle",
            Kind::Request => "request",
            Kind::Task => "task",
        }
    }

    /// The sort the resolver's messages name it by.
    pub fn sort(self) -> Sort {
        match self {
            Kind::Workspace => Sort::Workspace,
            Kind::Fixed | Kind::Movable | Kind::Arm | Kind::Surface => Sort::EndEffector,
            Kind::Hand | Kind::Support => Sort::HolderKind,
            Kind::Robot => Sort::Robot,
            Kind::Object => Sort::Object,
            Kind::Grasp | Kind::Rest => Sort::Grasp,
            Kind::Obstacle => Sort::Obstacle,
            Kind::Request => Sort::Request,
            Kind::Task => Sort::Task,
        }
    }

    /// True for what may hold or support an object (what a placement's holder names).
    pub fn is_end_effector(self) -> bool {
        self.sort() == Sort::EndEffector
    }

    /// True for hand and support kinds.
    pub fn is_holder_kind(self) -> bool {
        self.sort() == Sort::HolderKind
    }
}

/// What a name refers to, independent of where it is written: the name in its scope.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Key {
    /// A name of the cell's one namespace (every file of the compilation).
    Global(String),
    /// A grasp or resting pose, in the scope of its object.
    Grasp {
        /// The object's name.
        object: String,
        /// The grasp's name.
        grasp: String,
    },
    /// A request or task name.
    Request(String),
}

impl Key {
    /// The name as written (without its object, for a grasp).
    pub fn name(&self) -> &str {
        match self {
            Key::Global(n) | Key::Request(n) => n,
            Key::Grasp { grasp, .. } => grasp,
        }
    }
}

/// One name written in a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Occurrence {
    /// The file it is written in.
    pub file: FileId,
    /// The name's span.
    pub span: Span,
    /// What it names.
    pub key: Key,
    /// `Some` where the name is declared, with what it declares; `None` for a use.
    pub declares: Option<Kind>,
    /// For a declaration, the whole item's span (an outline shows it); for a use, the
    /// name's.
    pub item: Span,
}

/// An `include "PATH"` line, as the loader read it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Include {
    /// The including file.
    pub file: FileId,
    /// The string literal.
    pub span: Span,
    /// The included file's path, resolved as the loader resolves it (whether or not it
    /// could be read).
    pub path: String,
}

/// The names of every file of a compilation: declarations and uses, in file order then
/// source order, each written place once.
#[derive(Clone, Debug, Default)]
pub struct Names {
    occurrences: Vec<Occurrence>,
    includes: Vec<Include>,
}

impl Names {
    /// Every occurrence, in file order then source order.
    pub fn occurrences(&self) -> &[Occurrence] {
        &self.occurrences
    }

    /// Every include line.
    pub fn includes(&self) -> &[Include] {
        &self.includes
    }

    /// Every declaration, in file order then source order.
    pub fn declared(&self) -> impl Iterator<Item = (&Occurrence, Kind)> {
        self.occurrences
            .iter()
            .filter_map(|o| Some((o, o.declares?)))
    }

    /// The name at byte `offset` of `file` (its end counts, so a cursor just after a
    /// name finds it).
    pub fn at(&self, file: FileId, offset: usize) -> Option<&Occurrence> {
        self.occurrences.iter().find(|o| {
            o.file == file && o.span.start as usize <= offset && offset <= o.span.end as usize
        })
    }

    /// The include line at byte `offset` of `file`.
    pub fn include_at(&self, file: FileId, offset: usize) -> Option<&Include> {
        self.includes.iter().find(|i| {
            i.file == file && i.span.start as usize <= offset && offset < i.span.end as usize
        })
    }

    /// Where `key` is declared (more than one place only in a cell with a duplicate).
    pub fn declarations<'a>(&'a self, key: &'a Key) -> impl Iterator<Item = &'a Occurrence> {
        self.occurrences
            .iter()
            .filter(move |o| o.declares.is_some() && &o.key == key)
    }

    /// Every occurrence of `key`, declarations included.
    pub fn occurrences_of<'a>(&'a self, key: &'a Key) -> impl Iterator<Item = &'a Occurrence> {
        self.occurrences.iter().filter(move |o| &o.key == key)
    }

    /// What `key` is declared as (its first declaration), if it is declared.
    pub fn kind_of(&self, key: &Key) -> Option<Kind> {
        self.declarations(key).find_map(|o| o.declares)
    }

    /// Records that `span` of `file` declares `key` as `kind`, in the item at `item`.
    pub(crate) fn declare(&mut self, file: FileId, span: Span, key: Key, kind: Kind, item: Span) {
        self.occurrences.push(Occurrence {
            file,
            span,
            key,
            declares: Some(kind),
            item,
        });
    }

    /// Records that `span` of `file` uses `key`.
    pub(crate) fn uses(&mut self, file: FileId, span: Span, key: Key) {
        self.occurrences.push(Occurrence {
            file,
            span,
            key,
            declares: None,
            item: span,
        });
    }

    /// Records an include line.
    pub(crate) fn include(&mut self, include: Include) {
        self.includes.push(include);
    }

    /// Puts the occurrences in file and source order, each written place once: the
    /// resolver looks some names up more than once (a name checked in two passes), and a
    /// place that is a declaration is never also a use.
    pub(crate) fn finish(&mut self) {
        self.occurrences.sort_by(|a, b| {
            (a.file, a.span.start, a.span.end, a.declares.is_none()).cmp(&(
                b.file,
                b.span.start,
                b.span.end,
                b.declares.is_none(),
            ))
        });
        self.occurrences
            .dedup_by(|later, first| later.file == first.file && later.span == first.span);
        self.includes.sort_by_key(|i| (i.file, i.span.start));
        self.includes
            .dedup_by(|later, first| later.file == first.file && later.span == first.span);
    }
}
