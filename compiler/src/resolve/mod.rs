//! Syntax trees to the resolved [`Cell`]: names to typed ids, quantities to SI.
//!
//! [`resolve`] walks the items of every loaded file (main file first, then includes in
//! the order they were read) in passes, each over all files:
//!
//! 1. **Units** ([`FileUnits::of`]): each file's `units` line, so every quantity below
//!    converts to SI.
//! 2. **Declare** (`declare.rs`): every name enters the one namespace, so an item may
//!    refer to a name declared later or in an included library. Workspaces with their
//!    boxes, end-effectors with their bodies (arm poses, surface slabs), holder kinds with
//!    their solids, robots (their URDFs read and their chains checked by `crate::urdf`),
//!    objects with their shapes, symmetries and grasps, obstacles, weights.
//! 3. **Resolve references** (`items.rs`): an arm's robot, kind and home configuration,
//!    a surface's kind, `reach` boxes, each grasp's holder, each transition's grasps.
//! 4. **Allowed contacts and computed reach**: `allow contact` bodies (`contacts.rs`),
//!    then the reach of arms declared with `reach ARM auto` ([`crate::reach`]), which
//!    builds the scene those contacts shape.
//! 5. **Derive workspaces** ([`crate::workspaces::assign`]): from the reach boxes now
//!    known; the derived names join the namespace.
//! 6. **Late references**, which may name derived workspaces: abstract `reaches` lists
//!    and `adjacent` pairs (`items.rs`), then `expect` requirements and `request`s
//!    (`requirements.rs`), the `world` and `task`s (`world.rs`).
//!
//! Name lookups with their "did you mean" live in `lookup.rs`; every declaration and
//! every name looked up is recorded there in the compilation's table of names
//! ([`crate::names::Names`]), which an editor reads instead of scoping names again. A
//! reference that fails to resolve is reported and the item is dropped or left partial;
//! resolution always goes on, so one run reports every problem.

mod contacts;
mod declare;
mod families;
mod items;
mod limits;
pub use limits::missing_limits;
mod lookup;
mod requirements;
mod world;

use std::collections::BTreeMap;

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use cellc_lang::ast;
use cellc_lang::diagnostic::SuggestionBudget;
use cellc_lang::{Diagnostic, FileId, Span};
use cellc_schema::files::Files;

use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::load::Loaded;
use crate::model::*;
use crate::names::Names;
use crate::reach::ReachSolver;
use crate::units::{Eval, FileUnits};

/// Default height of a surface's reach above its top face: tall enough for the objects
/// a cell handles to stand on it.
pub const DEFAULT_SURFACE_REACH_HEIGHT: f64 = 0.3;

/// The most members one grasp or rest family may have (E0324 beyond): a family this
/// large already gives an object thousands of states per hand.
pub const MAX_FAMILY_MEMBERS: usize = 1024;

pub use families::member_name;

#[derive(Clone, Copy, Debug)]
enum Entry {
    Workspace(WorkspaceId),
    EndEffector(EndEffectorId),
    HolderKind(HolderKindId),
    Robot(RobotId),
    Object(ObjectId),
    Obstacle,
}

impl Entry {
    fn sort(self) -> Sort {
        match self {
            Entry::Workspace(_) => Sort::Workspace,
            Entry::EndEffector(_) => Sort::EndEffector,
            Entry::HolderKind(_) => Sort::HolderKind,
            Entry::Robot(_) => Sort::Robot,
            Entry::Object(_) => Sort::Object,
            Entry::Obstacle => Sort::Obstacle,
        }
    }
}

/// Resolves every loaded file into one cell, computing `reach auto` with `reach` and
/// deriving workspaces on the way (see [`crate::reach`] and [`crate::workspaces`]).
/// Diagnostics are appended to `diagnostics`; the names written in the files, with what
/// each declares or refers to, are returned with the cell.
pub fn resolve(
    files: &dyn Files,
    reach: &dyn ReachSolver,
    loaded: &Loaded,
    options: &crate::CompileOptions,
    diagnostics: &mut Vec<Diagnostic>,
) -> Resolved {
    let mut r = Resolver {
        files,
        packages: cellc_urdf::PackagePath::new(),
        cell: Cell::default(),
        names: BTreeMap::new(),
        origins: HashMap::default(),
        grasp_names: ByObject::default(),
        families: ByObject::default(),
        loaded,
        weight_origins: [None, None],
        transition_origins: HashMap::default(),
        obstacle_names: HashSet::default(),
        request_names: HashMap::default(),
        suggestions: SuggestionBudget::default(),
        workspaces_incomplete: false,
        urdfs: crate::urdf::UrdfCache::default(),
        written: Names::default(),
        limits_lines: Vec::new(),
        limits_files: HashMap::default(),
        first_extra_source: loaded.sources.len() as u32,
        extra_sources: Vec::new(),
        diagnostics,
    };
    if let Some(main) = loaded.files.first().and_then(|f| f.ast.as_ref()) {
        r.cell.name = main.name.text.clone();
    }
    let files: Vec<(FileId, &str, &ast::File)> = loaded
        .files
        .iter()
        .filter_map(|f| f.ast.as_ref().map(|a| (f.id, f.path.as_str(), a)))
        .collect();
    let units: Vec<FileUnits> = files
        .iter()
        .map(|(id, _, file)| FileUnits::of(*id, &file.items, r.diagnostics))
        .collect();
    // Packages first: robots anywhere may name their files.
    r.declare_packages(&files, options);
    for (i, (id, path, file)) in files.iter().enumerate() {
        for item in &file.items {
            r.declare(*id, path, units[i], item);
        }
    }
    for (i, (id, _, file)) in files.iter().enumerate() {
        for item in &file.items {
            match item {
                ast::Item::Limits(l) => r.resolve_limits(*id, units[i], l),
                _ => r.resolve_item(*id, units[i], item),
            }
        }
    }
    r.apply_limits();
    // Allowed contacts name bodies, never workspaces: they are resolved before reach is
    // computed, which builds the scene they shape.
    for (id, _, file) in &files {
        for item in &file.items {
            if let ast::Item::Allow(a) = item {
                r.resolve_allow(*id, a);
            }
        }
    }
    r.cell.auto_reach = crate::reach::compute(&mut r.cell, &loaded.sources, reach, r.diagnostics);
    // Workspaces are derived before anything that may name them is resolved.
    crate::workspaces::assign(&mut r.cell, r.diagnostics);
    r.workspaces_incomplete = r.cell.derive_workspaces.is_some()
        && r.cell
            .end_effectors
            .iter()
            .any(|(_, e)| e.reach_auto.is_some() && e.reach_boxes.is_empty());
    let derived: Vec<(String, WorkspaceId, Origin)> = r
        .cell
        .workspaces
        .iter()
        .filter(|(_, w)| w.derived)
        .map(|(id, w)| (w.name.clone(), id, w.origin))
        .collect();
    for (name, id, origin) in derived {
        r.names.insert(name.clone(), Entry::Workspace(id));
        r.origins.insert(name, origin);
    }
    // Abstract reach lists, adjacencies and requirements may name derived workspaces.
    for (id, _, file) in &files {
        for item in &file.items {
            match item {
                ast::Item::EndEffector(e) => r.resolve_reaches(*id, e),
                ast::Item::Adjacent(adj) => r.resolve_adjacent(*id, adj),
                _ => {}
            }
        }
    }
    for (i, (id, _, file)) in files.iter().enumerate() {
        for item in &file.items {
            match item {
                ast::Item::Expect(e) => r.resolve_expect(*id, e),
                ast::Item::Request(q) => r.resolve_request(*id, units[i], q),
                ast::Item::World(w) => r.resolve_world(*id, units[i], w),
                ast::Item::Task(t) => r.resolve_task(*id, units[i], t),
                _ => {}
            }
        }
    }
    r.written.finish();
    Resolved {
        cell: r.cell,
        names: r.written,
        extra_sources: r.extra_sources,
    }
}

/// What [`resolve`] gives: the cell, the names written, and the files it read that the
/// source map must hold for its diagnostics (joint limits files, in the order their ids
/// were given, after the loaded sources).
pub struct Resolved {
    /// The cell.
    pub cell: Cell,
    /// The names written.
    pub names: Names,
    /// (path, text) of each file read, to add to the source map in this order.
    pub extra_sources: Vec<(String, String)>,
}

struct Resolver<'w, 'd> {
    files: &'w dyn Files,
    /// Where `package://` files are found: the cell's `package` items, then the options'.
    packages: cellc_urdf::PackagePath,
    cell: Cell,
    /// Sorted, so "did you mean" compares candidates in an order that does not depend on
    /// hashing (it compares a bounded number of them).
    names: BTreeMap<String, Entry>,
    origins: HashMap<String, Origin>,
    /// Grasps and family members (aliases too) by object and name.
    grasp_names: ByObject<GraspId>,
    /// Grasp and rest families by object and name.
    families: ByObject<families::Family>,
    /// The files read, for the grasp-set files families name.
    loaded: &'w Loaded,
    /// Where the move and transition weights were set, to refuse setting them twice.
    weight_origins: [Option<Origin>; 2],
    /// First declaration of each directed transition.
    transition_origins: HashMap<(GraspId, GraspId), Origin>,
    /// Obstacles with a box, by name.
    obstacle_names: HashSet<String>,
    /// Requests and tasks by name (one namespace: `cellc plan` and `cellc run` may take
    /// either), with where each was declared.
    request_names: HashMap<String, Origin>,
    /// What is left of this compilation's "did you mean" searches.
    suggestions: SuggestionBudget,
    /// URDFs read so far, and the budget for reading more.
    urdfs: crate::urdf::UrdfCache,
    /// Whether `workspaces from reach` ran without the reach of some `reach ARM auto`
    /// (its robot did not load, or the cell had errors before reach was computed): the
    /// names it would have derived are then not known, and a reference to one is not
    /// reported as unknown on top of the error that caused it.
    workspaces_incomplete: bool,
    /// Every name declared and looked up so far, where it is written.
    written: Names,
    /// `limits` lines resolved, applied once all are known.
    limits_lines: Vec<limits::LimitsLine<'w>>,
    /// Joint limits files read, by resolved path.
    limits_files: HashMap<String, limits::ReadLimitsFile>,
    /// The id the first file read here gets (the loaded sources come first).
    first_extra_source: u32,
    /// Files read here, for the source map.
    extra_sources: Vec<(String, String)>,
    diagnostics: &'d mut Vec<Diagnostic>,
}

fn origin(file: FileId, span: Span, name: &ast::Name) -> Origin {
    Origin {
        file,
        span,
        name_span: name.span,
    }
}

impl Resolver<'_, '_> {
    /// The cell's `package NAME at "DIR"` items (each folder relative to its file), then
    /// the search folders of the options. A name declared twice with two folders is an
    /// error; the same folder twice (a library included by two files) is not.
    fn declare_packages(
        &mut self,
        files: &[(FileId, &str, &ast::File)],
        options: &crate::CompileOptions,
    ) {
        let mut first: HashMap<String, Origin> = HashMap::default();
        for (id, path, file) in files {
            for item in &file.items {
                let ast::Item::Package(p) = item else {
                    continue;
                };
                let dir = cellc_schema::files::join(path, &p.dir.value);
                let here = origin(*id, p.span, &p.name);
                match self.packages.declared(&p.name.text) {
                    Some(known) if known != cellc_schema::files::normalize(&dir) => {
                        self.diagnostics.push(diagnostics::package_declared_twice(
                            &p.name.text,
                            first[&p.name.text],
                            here,
                        ));
                    }
                    Some(_) => {}
                    None => {
                        self.packages.declare(&p.name.text, &dir);
                        first.insert(p.name.text.clone(), here);
                    }
                }
            }
        }
        for dir in &options.package_path {
            self.packages.search(dir);
        }
    }

    fn eval(&mut self, file: FileId, units: FileUnits) -> Eval<'_> {
        Eval {
            file,
            units,
            diagnostics: self.diagnostics,
        }
    }

    /// Adds a name to the one namespace of workspaces, end-effectors, kinds, robots and
    /// objects. One namespace (rather than one per sort) means a name always means one
    /// thing, so `left` in a message is never ambiguous.
    fn add_name(&mut self, name: &ast::Name, entry: Entry, origin: Origin) -> bool {
        if let Some(first) = self.origins.get(&name.text) {
            let sort = self.names[&name.text].sort();
            self.diagnostics.push(diagnostics::duplicate_name(
                sort, &name.text, *first, origin,
            ));
            return false;
        }
        self.names.insert(name.text.clone(), entry);
        self.origins.insert(name.text.clone(), origin);
        true
    }
}

/// Values by object and name (grasps, family members, families), looked up with a
/// borrowed name: a transition line names every grasp it pairs, and building an owned
/// `(object, name)` key for each lookup cost an allocation per name.
struct ByObject<V>(HashMap<ObjectId, HashMap<String, V>>);

impl<V> Default for ByObject<V> {
    fn default() -> Self {
        ByObject(HashMap::default())
    }
}

impl<V> ByObject<V> {
    /// The value of `name` in `object`.
    fn get(&self, object: ObjectId, name: &str) -> Option<&V> {
        self.0.get(&object)?.get(name)
    }

    /// Sets the value of `name` in `object`.
    fn insert(&mut self, object: ObjectId, name: String, value: V) {
        self.0.entry(object).or_default().insert(name, value);
    }
}
