//! Every name written in a compilation's files: where each is declared and where it is
//! used, read from the syntax trees by the same scoping as the resolver's (one namespace
//! for workspaces, end-effectors, holder kinds, robots, objects and obstacles; grasps per
//! object; requests and tasks their own). Definition, references, hover, completion and
//! symbols all read this one table, so they agree on what a name means.
//!
//! The trees are taken through the parser the compiler used (the server's cache of
//! trees, which has them from the compilation just made), for the texts of the
//! compilation's source map: the index holds exactly the texts the diagnostics were
//! computed from.

use cellc_lang::ast::{self, Item, ObjectMember, Qualified};
use cellc_lang::{FileId, SourceMap, Span};

/// What a declaration declares.
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
    /// `grasp NAME ... by HOLDER`
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

    /// True for what may hold or support an object (what a placement's holder names).
    pub fn is_end_effector(self) -> bool {
        matches!(
            self,
            Kind::Fixed | Kind::Movable | Kind::Arm | Kind::Surface
        )
    }

    /// True for hand and support kinds.
    pub fn is_holder_kind(self) -> bool {
        matches!(self, Kind::Hand | Kind::Support)
    }
}

/// What a name refers to, independent of where it is written.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Key {
    /// A name of the cell's one namespace.
    Global(String),
    /// A grasp or resting pose of an object.
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
#[derive(Clone, Debug)]
pub struct Occurrence {
    /// The file it is written in.
    pub file: FileId,
    /// The name's span.
    pub span: Span,
    /// What it names.
    pub key: Key,
    /// `Some` where the name is declared, with what it declares; `None` for a use.
    pub declares: Option<Kind>,
    /// For a declaration: the whole item's span (for outlines).
    pub item: Span,
}

/// An `include "PATH"` line.
#[derive(Clone, Debug)]
pub struct Include {
    /// The including file.
    pub file: FileId,
    /// The string literal.
    pub span: Span,
    /// The included file's path, resolved as the loader resolves it.
    pub path: String,
}

/// The names of every file of a compilation, with each file's syntax tree.
#[derive(Default)]
pub struct Index {
    /// In file order, then source order.
    pub occurrences: Vec<Occurrence>,
    /// Every include line.
    pub includes: Vec<Include>,
    /// Each file's syntax tree, when it parsed.
    pub trees: Vec<(FileId, Option<ast::File>)>,
}

impl Index {
    /// Indexes every file of `sources`, with trees made by `parser`.
    pub fn build(sources: &SourceMap, parser: &dyn cellc_compiler::load::Parser) -> Index {
        let mut index = Index::default();
        for (id, source) in sources.iter() {
            let parsed = parser.parse(id, &source.path, &source.text);
            if let Some(tree) = &parsed.file {
                let mut walk = Walk {
                    index: &mut index,
                    file: id,
                };
                for item in &tree.items {
                    walk.item(item, &source.path);
                }
            }
            index.trees.push((id, parsed.file));
        }
        index
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

    /// What `key` is declared as, if it is declared.
    pub fn kind_of(&self, key: &Key) -> Option<Kind> {
        self.declarations(key).find_map(|o| o.declares)
    }
}

/// The walk of one file's items.
struct Walk<'a> {
    index: &'a mut Index,
    file: FileId,
}

impl Walk<'_> {
    fn declare(&mut self, name: &ast::Name, key: Key, kind: Kind, item: Span) {
        self.index.occurrences.push(Occurrence {
            file: self.file,
            span: name.span,
            key,
            declares: Some(kind),
            item,
        });
    }

    fn global(&mut self, name: &ast::Name, kind: Kind, item: Span) {
        self.declare(name, Key::Global(name.text.clone()), kind, item);
    }

    fn use_key(&mut self, span: Span, key: Key) {
        self.index.occurrences.push(Occurrence {
            file: self.file,
            span,
            key,
            declares: None,
            item: span,
        });
    }

    fn uses(&mut self, name: &ast::Name) {
        self.use_key(name.span, Key::Global(name.text.clone()));
    }

    fn grasp(&mut self, object: &str, name: &ast::Name) {
        let key = Key::Grasp {
            object: object.to_string(),
            grasp: name.text.clone(),
        };
        self.use_key(name.span, key);
    }

    /// `HOLDER` or `HOLDER.GRASP` of a placement of `object`.
    fn holder(&mut self, object: &str, q: &Qualified) {
        match &q.object {
            Some(holder) => {
                self.uses(holder);
                self.grasp(object, &q.name);
            }
            None => self.uses(&q.name),
        }
    }

    fn request_placement(&mut self, object: &str, p: &ast::RequestPlacement) {
        self.holder(object, &p.holder);
        if let ast::PlaceSpec::In(workspace) = &p.place {
            self.uses(workspace);
        }
    }

    fn item(&mut self, item: &Item, path: &str) {
        let span = item.span();
        match item {
            Item::Include(i) => self.index.includes.push(Include {
                file: self.file,
                span: i.path.span,
                path: cellc_schema::files::join(path, &i.path.value),
            }),
            Item::Units(_) | Item::Weights(_) | Item::Package(_) | Item::WorkspacesFromReach(_) => {
            }
            Item::Workspace(i) => self.global(&i.name, Kind::Workspace, span),
            Item::Adjacent(i) => {
                self.uses(&i.a);
                self.uses(&i.b);
            }
            Item::EndEffector(i) => {
                let kind = match i.mobility {
                    ast::Mobility::Fixed => Kind::Fixed,
                    ast::Mobility::Movable => Kind::Movable,
                };
                self.global(&i.name, kind, span);
                i.reaches.iter().for_each(|w| self.uses(w));
            }
            Item::Hand(i) => self.global(&i.name, Kind::Hand, span),
            Item::Support(i) => self.global(&i.name, Kind::Support, span),
            Item::Robot(i) => self.global(&i.name, Kind::Robot, span),
            Item::Arm(i) => {
                self.global(&i.name, Kind::Arm, span);
                self.uses(&i.robot);
                self.uses(&i.kind);
            }
            Item::Surface(i) => {
                self.global(&i.name, Kind::Surface, span);
                self.uses(&i.kind);
            }
            Item::Reach(i) => self.uses(&i.end_effector),
            Item::Object(i) => self.object(i),
            Item::Expect(i) => self.requirement(&i.requirement),
            Item::Allow(i) => {
                for q in [&i.a, &i.b] {
                    // `ARM.LINK` names a link of the arm's robot, not a cell name.
                    self.uses(q.object.as_ref().unwrap_or(&q.name));
                }
            }
            Item::Request(i) => {
                self.declare(
                    &i.name,
                    Key::Request(i.name.text.clone()),
                    Kind::Request,
                    span,
                );
                self.uses(&i.object);
                self.request_placement(&i.object.text, &i.from);
                self.request_placement(&i.object.text, &i.to);
            }
            Item::Obstacle(i) => self.global(&i.name, Kind::Obstacle, span),
            Item::World(i) => {
                for entry in &i.entries {
                    self.uses(&entry.object);
                    match &entry.placement {
                        ast::WorldPlacement::Placed(p) => {
                            self.request_placement(&entry.object.text, p)
                        }
                        ast::WorldPlacement::Bare(q) => self.holder(&entry.object.text, q),
                    }
                }
            }
            Item::Task(i) => {
                self.declare(&i.name, Key::Request(i.name.text.clone()), Kind::Task, span);
                for step in &i.steps {
                    self.uses(&step.object);
                    self.request_placement(&step.object.text, &step.to);
                }
            }
        }
    }

    fn object(&mut self, item: &ast::ObjectItem) {
        self.global(&item.name, Kind::Object, item.span);
        let object = item.name.text.as_str();
        for member in &item.members {
            match member {
                ObjectMember::Shape(_) | ObjectMember::Symmetry(_) => {}
                ObjectMember::Grasp(g) => {
                    let kind = match g.keyword {
                        ast::GraspKeyword::Grasp => Kind::Grasp,
                        ast::GraspKeyword::Rest => Kind::Rest,
                    };
                    let key = Key::Grasp {
                        object: object.to_string(),
                        grasp: g.name.text.clone(),
                    };
                    self.declare(&g.name, key, kind, g.span);
                    self.uses(&g.holder);
                }
                ObjectMember::Transition(t) => {
                    for q in std::iter::once(&t.from).chain(&t.to) {
                        match &q.object {
                            Some(other) => {
                                self.uses(other);
                                self.grasp(&other.text, &q.name);
                            }
                            None => self.grasp(object, &q.name),
                        }
                    }
                }
            }
        }
    }

    fn requirement(&mut self, requirement: &ast::Requirement) {
        match requirement {
            ast::Requirement::Reach { object, from, to } => {
                self.uses(object);
                for p in [from, to] {
                    self.holder(&object.text, &p.holder);
                    self.uses(&p.workspace);
                }
            }
            ast::Requirement::Coverage { workspace, .. } => self.uses(workspace),
            ast::Requirement::NoIsolatedStates { object } => {
                if let Some(object) = object {
                    self.uses(object);
                }
            }
        }
    }
}
