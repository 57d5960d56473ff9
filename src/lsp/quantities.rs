//! The quantities of a file with what they measure, so that hover can show the value a
//! written number resolves to (in SI, with the file's `units` applied), as the resolver
//! reads it.

use cellc_compiler::units::{Eval, FileUnits};
use cellc_lang::ast::{self, Item, ObjectMember, Quantity};
use cellc_lang::{FileId, Span};

/// What a quantity measures.
#[derive(Clone, Debug, PartialEq)]
pub enum Measure {
    /// A length (metres).
    Length,
    /// An angle (radians).
    Angle,
    /// A home value of an arm's joint: an angle, or a length for a prismatic joint.
    Home {
        /// The arm.
        arm: String,
        /// The joint.
        joint: String,
    },
}

/// One quantity written in a file.
#[derive(Clone, Debug)]
pub struct Written {
    /// As written.
    pub quantity: Quantity,
    /// What it measures.
    pub measure: Measure,
}

/// Every quantity of `file` that measures something, and the file's default units.
pub fn of_file(file: FileId, tree: &ast::File) -> (Vec<Written>, FileUnits) {
    let units = FileUnits::of(file, &tree.items, &mut Vec::new());
    let mut out = Collect(Vec::new());
    for item in &tree.items {
        out.item(item);
    }
    (out.0, units)
}

/// The quantity at byte `offset`, in SI (metres or radians) with its measure and whether
/// it is a length; `None` for no quantity there or one that does not resolve (its
/// diagnostic says why).
/// `prismatic(arm, joint)` tells whether a home value is a length.
pub fn at(
    written: &[Written],
    units: FileUnits,
    file: FileId,
    offset: usize,
    prismatic: impl Fn(&str, &str) -> bool,
) -> Option<(&Written, f64, bool)> {
    let w = written.iter().find(|w| contains(w.quantity.span, offset))?;
    let mut eval = Eval {
        file,
        units,
        diagnostics: &mut Vec::new(),
    };
    let is_length = match &w.measure {
        Measure::Length => true,
        Measure::Angle => false,
        Measure::Home { arm, joint } => prismatic(arm, joint),
    };
    let value = if is_length {
        eval.length(&w.quantity)
    } else {
        eval.angle(&w.quantity)
    }?;
    Some((w, value, is_length))
}

fn contains(span: Span, offset: usize) -> bool {
    span.start as usize <= offset && offset <= span.end as usize
}

struct Collect(Vec<Written>);

impl Collect {
    fn push(&mut self, q: &Quantity, measure: Measure) {
        self.0.push(Written {
            quantity: q.clone(),
            measure,
        });
    }

    fn lengths(&mut self, v: &ast::Vec3) {
        v.parts.iter().for_each(|q| self.push(q, Measure::Length));
    }

    fn aabb(&mut self, b: &ast::Aabb) {
        self.lengths(&b.center);
        self.lengths(&b.size);
    }

    fn pose(&mut self, p: &ast::Pose) {
        self.lengths(&p.at);
        if let Some(ast::Rotation::Rpy(v, _)) = &p.rotation {
            v.parts.iter().for_each(|q| self.push(q, Measure::Angle));
        }
    }

    fn shape(&mut self, s: &ast::Shape) {
        match s {
            ast::Shape::Box { size } => self.lengths(size),
            ast::Shape::Cylinder { radius, height } => {
                self.push(radius, Measure::Length);
                self.push(height, Measure::Length);
            }
            ast::Shape::Sphere { radius } => self.push(radius, Measure::Length),
            ast::Shape::Mesh { .. } => {}
        }
    }

    fn placement(&mut self, p: &ast::RequestPlacement) {
        if let ast::PlaceSpec::At(pose) = &p.place {
            self.pose(pose);
        }
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Workspace(i) => i.boxes.iter().for_each(|b| self.aabb(b)),
            Item::Hand(i) => {
                for solid in &i.solids {
                    self.shape(&solid.shape);
                    if let Some(pose) = &solid.pose {
                        self.pose(pose);
                    }
                }
            }
            Item::Arm(i) => {
                self.pose(&i.pose);
                for value in &i.home {
                    let measure = Measure::Home {
                        arm: i.name.text.clone(),
                        joint: value.joint.text.clone(),
                    };
                    self.push(&value.value, measure);
                }
            }
            Item::Surface(i) => {
                self.aabb(&i.slab);
                if let Some(h) = &i.reach_height {
                    self.push(h, Measure::Length);
                }
            }
            Item::Reach(i) => {
                if let ast::ReachExtent::Box(b) = &i.extent {
                    self.aabb(b);
                }
            }
            Item::Obstacle(i) => self.aabb(&i.aabb),
            Item::Object(i) => {
                for member in &i.members {
                    match member {
                        ObjectMember::Shape(s) => self.shape(&s.shape),
                        ObjectMember::Grasp(g) => {
                            if let Some(pose) = &g.pose {
                                self.pose(pose);
                            }
                        }
                        ObjectMember::Symmetry(_) | ObjectMember::Transition(_) => {}
                    }
                }
            }
            Item::Request(i) => {
                self.placement(&i.from);
                self.placement(&i.to);
            }
            Item::World(i) => {
                for entry in &i.entries {
                    if let ast::WorldPlacement::Placed(p) = &entry.placement {
                        self.placement(p);
                    }
                }
            }
            Item::Task(i) => i.steps.iter().for_each(|s| self.placement(&s.to)),
            _ => {}
        }
    }
}
