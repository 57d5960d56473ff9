//! Text to syntax tree, reporting every syntax error it can in one run.
//!
//! pest stops at the first error, so recovery is built into the grammar: an item that
//! does not parse is swallowed by the `recover` rule (to the end of its line, or over a
//! whole `{ ... }` block) and the parse goes on. Each recovered region is then parsed
//! again alone with a probe rule, and pest's report of what it expected there is turned
//! into words by [`crate::phrases`].

use pest::iterators::Pair;
use pest::Parser as _;

use crate::ast::*;
use crate::diagnostic::Diagnostic;
use crate::grammar::{CellParser, Rule};
use crate::phrases;
use crate::span::{FileId, Span};

/// The result of parsing one file: the tree (absent only when the file's outline
/// `cell NAME { ... }` itself is broken) and every syntax diagnostic.
#[derive(Debug)]
pub struct Parsed {
    /// The syntax tree, with the items that parsed.
    pub file: Option<File>,
    /// Syntax errors, in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// Parses one file's text.
pub fn parse(file_id: FileId, text: &str) -> Parsed {
    let mut diagnostics = Vec::new();
    let pairs = match CellParser::parse(Rule::file, text) {
        Ok(pairs) => pairs,
        Err(error) => {
            diagnostics.push(phrases::syntax_error(file_id, text, 0, &error));
            return Parsed {
                file: None,
                diagnostics,
            };
        }
    };
    let mut builder = Builder {
        file_id,
        text,
        diagnostics: &mut diagnostics,
    };
    let file = pairs.into_iter().next().and_then(|pair| builder.file(pair));
    if file.is_none() && diagnostics.is_empty() {
        diagnostics.push(phrases::internal(file_id, Span::new(0, text.len())));
    }
    diagnostics.sort_by_key(|d| d.primary_label().map(|l| l.span.start));
    Parsed { file, diagnostics }
}

/// The span of a pair without the white space and comments pest's implicit skipping
/// leaves at its end (a rule ending in an optional part swallows the trivia before the
/// part it did not find). Spans must end at the last real token: the formatter attaches
/// comments by position, and labels should not underline blank lines.
/// Parses a placement on its own (`table.g1 in w1`, `table at (0.5, 0, 0.8) rpy (0, 0,
/// 90)`), as given on the command line.
pub fn parse_placement(file_id: FileId, text: &str) -> Result<RequestPlacement, Diagnostic> {
    pest::set_error_detail(true);
    let pairs = CellParser::parse(Rule::placement_arg, text)
        .map_err(|error| phrases::syntax_error(file_id, text, 0, &error))?;
    let mut diagnostics = Vec::new();
    let mut builder = Builder {
        file_id,
        text,
        diagnostics: &mut diagnostics,
    };
    let placement = pairs
        .into_iter()
        .next()
        .and_then(|p| p.into_inner().next())
        .and_then(|p| builder.request_placement(p));
    match (placement, diagnostics.pop()) {
        (Some(p), None) => Ok(p),
        (_, Some(d)) => Err(d),
        (None, None) => Err(phrases::internal(file_id, Span::new(0, text.len()))),
    }
}

fn span_of(pair: &Pair<'_, Rule>) -> Span {
    let s = pair.as_span();
    Span::new(s.start(), s.start() + content_len(s.as_str()))
}

/// Length of `text` up to the end of its last token that is not white space or a comment.
fn content_len(text: &str) -> usize {
    let bytes = text.as_bytes();
    let mut end = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            // The UTF-8 byte-order mark (EF BB BF) is white space too.
            0xEF if bytes.get(i + 1) == Some(&0xBB) && bytes.get(i + 2) == Some(&0xBF) => i += 3,
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i = (i + 2).min(bytes.len());
            }
            quote @ (b'"' | b'`') => {
                i += 1;
                while i < bytes.len() && bytes[i] != quote {
                    if quote == b'"' && bytes[i] == b'\\' {
                        i += 1;
                    }
                    i += 1;
                }
                i = (i + 1).min(bytes.len());
                end = i;
            }
            _ => {
                i += 1;
                end = i;
            }
        }
    }
    end
}

struct Builder<'t, 'd> {
    file_id: FileId,
    text: &'t str,
    diagnostics: &'d mut Vec<Diagnostic>,
}

impl Builder<'_, '_> {
    fn file(&mut self, pair: Pair<'_, Rule>) -> Option<File> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let kind = match inner.next()?.into_inner().next()?.as_rule() {
            Rule::kw_cell => FileKind::Cell,
            _ => FileKind::Library,
        };
        let name = self.name(inner.next()?)?;
        let body = inner.next()?;
        let mut items: Vec<Item> = Vec::new();
        for pair in body.into_inner() {
            if pair.as_rule() == Rule::recover {
                let previous = items.last().map(Item::span);
                self.recovered(&pair, previous, Rule::item_probe, Rule::item_line);
                continue;
            }
            match self.item(pair) {
                Some(item) => items.push(item),
                None => self.diagnostics.push(phrases::internal(self.file_id, span)),
            }
        }
        Some(File {
            kind,
            name,
            items,
            span,
        })
    }

    /// Re-parses a recovered region alone to learn what was expected there. When the
    /// region starts on the line where the previous item ended, the junk is most likely
    /// the unparsed tail of that item (`at (0, 0)` after `grasp g1 by table`), so the
    /// previous item is re-parsed together with it to find the real mistake.
    fn recovered(
        &mut self,
        pair: &Pair<'_, Rule>,
        previous: Option<Span>,
        probe: Rule,
        line_probe: Rule,
    ) {
        let start = pair.as_span().start();
        if let Some(previous) = previous {
            let between = &self.text[previous.end as usize..start];
            if !between.contains('\n') {
                let from = previous.start as usize;
                if let Err(error) = CellParser::parse(line_probe, &self.text[from..]) {
                    let diagnostic = phrases::syntax_error(self.file_id, self.text, from, &error);
                    if diagnostic
                        .primary_label()
                        .is_some_and(|l| l.span.start as usize >= start)
                    {
                        self.diagnostics.push(diagnostic);
                        return;
                    }
                }
            }
        }
        let rest = &self.text[start..];
        match CellParser::parse(probe, rest) {
            Err(error) => self.diagnostics.push(phrases::syntax_error(
                self.file_id,
                self.text,
                start,
                &error,
            )),
            Ok(_) => self
                .diagnostics
                .push(phrases::unexpected_text(self.file_id, span_of(pair))),
        }
    }

    fn item(&mut self, pair: Pair<'_, Rule>) -> Option<Item> {
        let span = span_of(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        // Every item starts with its keyword.
        let _keyword = inner.next();
        Some(match rule {
            Rule::units_item => {
                let units = inner
                    .map(|p| Some((Unit::parse(p.as_str())?, span_of(&p))))
                    .collect::<Option<Vec<_>>>()?;
                Item::Units(UnitsItem { units, span })
            }
            Rule::weights_item => {
                let mut weights = Vec::new();
                for weight in inner {
                    let wspan = span_of(&weight);
                    let mut parts = weight.into_inner();
                    let kind = match parts.next()?.into_inner().next()?.as_rule() {
                        Rule::kw_move => ArcKind::Move,
                        _ => ArcKind::Transition,
                    };
                    let number = parts.next()?;
                    weights.push(Weight {
                        kind,
                        number: number.as_str().to_string(),
                        value: number.as_str().parse().ok()?,
                        span: wspan,
                    });
                }
                Item::Weights(WeightsItem { weights, span })
            }
            Rule::include_item => Item::Include(IncludeItem {
                path: self.string(inner.next()?)?,
                span,
            }),
            Rule::workspaces_from_reach => Item::WorkspacesFromReach(span),
            Rule::workspace_item => {
                let name = self.name(inner.next()?)?;
                let mut label = None;
                let mut boxes = Vec::new();
                for p in inner {
                    match p.as_rule() {
                        Rule::label => label = Some(self.string(p.into_inner().next()?)?),
                        _ => boxes.push(self.aabb(p)?),
                    }
                }
                Item::Workspace(WorkspaceItem {
                    name,
                    label,
                    boxes,
                    span,
                })
            }
            Rule::adjacent_item => Item::Adjacent(AdjacentItem {
                a: self.name(inner.next()?)?,
                b: self.name(inner.next()?)?,
                span,
            }),
            Rule::fixed_item | Rule::movable_item => {
                let name = self.name(inner.next()?)?;
                let mut clause = inner.next()?.into_inner();
                let _reaches = clause.next();
                let reaches = self.name_list(clause.next()?)?;
                Item::EndEffector(EndEffectorItem {
                    mobility: if rule == Rule::fixed_item {
                        Mobility::Fixed
                    } else {
                        Mobility::Movable
                    },
                    name,
                    reaches,
                    span,
                })
            }
            Rule::hand_item => {
                let name = self.name(inner.next()?)?;
                let solids = inner.map(|p| self.solid(p)).collect::<Option<Vec<_>>>()?;
                Item::Hand(HandItem { name, solids, span })
            }
            Rule::support_item => Item::Support(SupportItem {
                name: self.name(inner.next()?)?,
                span,
            }),
            Rule::robot_item => {
                let name = self.name(inner.next()?)?;
                let _urdf = inner.next();
                let urdf = self.string(inner.next()?)?;
                let mut base = None;
                let mut tip = None;
                while let Some(keyword) = inner.next() {
                    let value = self.name(inner.next()?)?;
                    if keyword.as_rule() == Rule::kw_base {
                        base = Some(value);
                    } else {
                        tip = Some(value);
                    }
                }
                Item::Robot(RobotItem {
                    name,
                    urdf,
                    base,
                    tip: tip?,
                    span,
                })
            }
            Rule::arm_item => {
                let name = self.name(inner.next()?)?;
                let robot = self.name(inner.next()?)?;
                let pose = self.pose(inner.next()?)?;
                let _with = inner.next();
                let kind = self.name(inner.next()?)?;
                let mut home = Vec::new();
                if let Some(clause) = inner.next() {
                    for pair in clause.into_inner().skip(1) {
                        let pspan = span_of(&pair);
                        let mut parts = pair.into_inner();
                        let joint = self.name(parts.next()?)?;
                        let value = self.quantity(parts.next()?)?;
                        home.push(JointValue {
                            joint,
                            value,
                            span: pspan,
                        });
                    }
                }
                Item::Arm(ArmItem {
                    name,
                    robot,
                    pose,
                    kind,
                    home,
                    span,
                })
            }
            Rule::surface_item => {
                let name = self.name(inner.next()?)?;
                let kind = self.name(inner.next()?)?;
                let slab = self.aabb(inner.next()?)?;
                let mut reach_height = None;
                for p in inner {
                    if p.as_rule() == Rule::quantity {
                        reach_height = Some(self.quantity(p)?);
                    }
                }
                Item::Surface(SurfaceItem {
                    name,
                    kind,
                    slab,
                    reach_height,
                    span,
                })
            }
            Rule::reach_item => Item::Reach(ReachItem {
                end_effector: self.name(inner.next()?)?,
                aabb: self.aabb(inner.next()?)?,
                span,
            }),
            Rule::object_item => {
                let name = self.name(inner.next()?)?;
                let mut members: Vec<ObjectMember> = Vec::new();
                for p in inner.next()?.into_inner() {
                    if p.as_rule() == Rule::recover {
                        let previous = members.last().map(ObjectMember::span);
                        self.recovered(&p, previous, Rule::member_probe, Rule::member_line);
                        continue;
                    }
                    members.push(self.member(p)?);
                }
                Item::Object(ObjectItem {
                    name,
                    members,
                    span,
                })
            }
            Rule::request_item => {
                let name = self.name(inner.next()?)?;
                let object = self.name(inner.next()?)?;
                let _from = inner.next();
                let from = self.request_placement(inner.next()?)?;
                let _to = inner.next();
                let to = self.request_placement(inner.next()?)?;
                Item::Request(RequestItem {
                    name,
                    object,
                    from,
                    to,
                    span,
                })
            }
            Rule::obstacle_item => Item::Obstacle(ObstacleItem {
                name: self.name(inner.next()?)?,
                aabb: self.aabb(inner.next()?)?,
                span,
            }),
            Rule::allow_item => {
                let _contact = inner.next();
                Item::Allow(AllowItem {
                    a: self.qualified(inner.next()?)?,
                    b: self.qualified(inner.next()?)?,
                    span,
                })
            }
            Rule::expect_item => Item::Expect(ExpectItem {
                requirement: self.requirement(inner.next()?)?,
                span,
            }),
            _ => return None,
        })
    }

    fn member(&mut self, pair: Pair<'_, Rule>) -> Option<ObjectMember> {
        let span = span_of(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let _keyword = inner.next();
        Some(match rule {
            Rule::shape_item => ObjectMember::Shape(ShapeMember {
                shape: self.shape(inner.next()?)?,
                span,
            }),
            Rule::symmetry_item => {
                let _about = inner.next();
                let axis = match inner.next()?.as_str() {
                    "x" => Axis::X,
                    "y" => Axis::Y,
                    _ => Axis::Z,
                };
                let mut order = None;
                for p in inner {
                    if p.as_rule() == Rule::integer {
                        order = Some((self.integer(&p)?, span_of(&p)));
                    }
                }
                ObjectMember::Symmetry(SymmetryMember { axis, order, span })
            }
            Rule::grasp_item | Rule::rest_item => {
                let name = self.name(inner.next()?)?;
                let mut label = None;
                let mut holder = None;
                let mut pose = None;
                for p in inner {
                    match p.as_rule() {
                        Rule::label => label = Some(self.string(p.into_inner().next()?)?),
                        Rule::name => holder = Some(self.name(p)?),
                        Rule::pose => pose = Some(self.pose(p)?),
                        _ => {}
                    }
                }
                ObjectMember::Grasp(GraspMember {
                    keyword: if rule == Rule::grasp_item {
                        GraspKeyword::Grasp
                    } else {
                        GraspKeyword::Rest
                    },
                    name,
                    label,
                    holder: holder?,
                    pose,
                    span,
                })
            }
            Rule::transition_item => {
                let from = self.qualified(inner.next()?)?;
                let direction = match inner.next()?.into_inner().next()?.as_rule() {
                    Rule::both_ways => Direction::Both,
                    _ => Direction::OneWay,
                };
                let to = inner
                    .next()?
                    .into_inner()
                    .map(|p| self.qualified(p))
                    .collect::<Option<Vec<_>>>()?;
                ObjectMember::Transition(TransitionMember {
                    from,
                    direction,
                    to,
                    span,
                })
            }
            _ => return None,
        })
    }

    fn requirement(&mut self, pair: Pair<'_, Rule>) -> Option<Requirement> {
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        Some(match rule {
            Rule::expect_reach => {
                let object = self.name(inner.next()?)?;
                let from = self.placement(inner.next()?)?;
                let _arrow = inner.next();
                let to = self.placement(inner.next()?)?;
                Requirement::Reach { object, from, to }
            }
            Rule::expect_cover => {
                let workspace = self.name(inner.next()?)?;
                let mut at_least = None;
                let mut mobility = None;
                for p in inner {
                    match p.as_rule() {
                        Rule::integer => at_least = Some((self.integer(&p)?, span_of(&p))),
                        Rule::reacher_kind => {
                            mobility = Some(match p.into_inner().next()?.as_rule() {
                                Rule::kw_fixed => Mobility::Fixed,
                                _ => Mobility::Movable,
                            })
                        }
                        _ => {}
                    }
                }
                Requirement::Coverage {
                    workspace,
                    at_least: at_least?,
                    mobility,
                }
            }
            Rule::expect_isolated => {
                let mut object = None;
                for p in inner {
                    if p.as_rule() == Rule::name {
                        object = Some(self.name(p)?);
                    }
                }
                Requirement::NoIsolatedStates { object }
            }
            _ => return None,
        })
    }

    fn placement(&mut self, pair: Pair<'_, Rule>) -> Option<Placement> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let holder = self.qualified(inner.next()?)?;
        let _in = inner.next();
        let workspace = self.name(inner.next()?)?;
        Some(Placement {
            holder,
            workspace,
            span,
        })
    }

    fn request_placement(&mut self, pair: Pair<'_, Rule>) -> Option<RequestPlacement> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let holder = self.qualified(inner.next()?)?;
        let next = inner.next()?;
        let place = if next.as_rule() == Rule::pose {
            PlaceSpec::At(self.pose(next)?)
        } else {
            PlaceSpec::In(self.name(inner.next()?)?)
        };
        Some(RequestPlacement {
            holder,
            place,
            span,
        })
    }

    fn shape(&mut self, pair: Pair<'_, Rule>) -> Option<Shape> {
        let pair = pair.into_inner().next()?;
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        Some(match rule {
            Rule::box_shape => {
                let _box = inner.next();
                let _size = inner.next();
                Shape::Box {
                    size: self.vec3(inner.next()?)?,
                }
            }
            Rule::cylinder_shape => {
                let _cyl = inner.next();
                let _radius = inner.next();
                let radius = self.quantity(inner.next()?)?;
                let _height = inner.next();
                let height = self.quantity(inner.next()?)?;
                Shape::Cylinder { radius, height }
            }
            Rule::sphere_shape => {
                let _sphere = inner.next();
                let _radius = inner.next();
                Shape::Sphere {
                    radius: self.quantity(inner.next()?)?,
                }
            }
            Rule::mesh_shape => {
                let _mesh = inner.next();
                Shape::Mesh {
                    path: self.string(inner.next()?)?,
                }
            }
            _ => return None,
        })
    }

    fn solid(&mut self, pair: Pair<'_, Rule>) -> Option<Solid> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let shape = self.shape(inner.next()?)?;
        let pose = match inner.next() {
            Some(p) => Some(self.pose(p)?),
            None => None,
        };
        Some(Solid { shape, pose, span })
    }

    fn pose(&mut self, pair: Pair<'_, Rule>) -> Option<Pose> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let _at = inner.next();
        let at = self.vec3(inner.next()?)?;
        let rotation = match inner.next() {
            Some(rotation) => {
                let r = rotation.into_inner().next()?;
                let rspan = span_of(&r);
                let rule = r.as_rule();
                let mut parts = r.into_inner();
                let _kw = parts.next();
                let values = parts.next()?;
                Some(if rule == Rule::rpy {
                    Rotation::Rpy(self.vec3(values)?, rspan)
                } else {
                    let q = values
                        .into_inner()
                        .map(|p| self.quantity(p))
                        .collect::<Option<Vec<_>>>()?;
                    Rotation::Quat(q.try_into().ok()?, rspan)
                })
            }
            None => None,
        };
        Some(Pose { at, rotation, span })
    }

    fn aabb(&mut self, pair: Pair<'_, Rule>) -> Option<Aabb> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let _box = inner.next();
        let _center = inner.next();
        let center = self.vec3(inner.next()?)?;
        let _size = inner.next();
        let size = self.vec3(inner.next()?)?;
        Some(Aabb { center, size, span })
    }

    fn vec3(&mut self, pair: Pair<'_, Rule>) -> Option<Vec3> {
        let span = span_of(&pair);
        let parts = pair
            .into_inner()
            .map(|p| self.quantity(p))
            .collect::<Option<Vec<_>>>()?;
        Some(Vec3 {
            parts: parts.try_into().ok()?,
            span,
        })
    }

    fn quantity(&mut self, pair: Pair<'_, Rule>) -> Option<Quantity> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let number = inner.next()?;
        let unit = match inner.next() {
            Some(u) => Some(Unit::parse(u.as_str())?),
            None => None,
        };
        Some(Quantity {
            number: number.as_str().to_string(),
            value: number.as_str().parse().ok()?,
            unit,
            span,
        })
    }

    fn integer(&mut self, pair: &Pair<'_, Rule>) -> Option<u32> {
        match pair.as_str().parse() {
            Ok(value) => Some(value),
            Err(_) => {
                self.diagnostics
                    .push(phrases::integer_too_large(self.file_id, span_of(pair)));
                Some(u32::MAX)
            }
        }
    }

    fn name(&mut self, pair: Pair<'_, Rule>) -> Option<Name> {
        let span = span_of(&pair);
        let text = pair.as_str();
        let text = text
            .strip_prefix('`')
            .and_then(|t| t.strip_suffix('`'))
            .unwrap_or(text);
        Some(Name {
            text: text.to_string(),
            span,
        })
    }

    fn qualified(&mut self, pair: Pair<'_, Rule>) -> Option<Qualified> {
        let span = span_of(&pair);
        let mut names = pair
            .into_inner()
            .map(|p| self.name(p))
            .collect::<Option<Vec<_>>>()?;
        let name = names.pop()?;
        Some(Qualified {
            object: names.pop(),
            name,
            span,
        })
    }

    fn name_list(&mut self, pair: Pair<'_, Rule>) -> Option<Vec<Name>> {
        pair.into_inner().map(|p| self.name(p)).collect()
    }

    fn string(&mut self, pair: Pair<'_, Rule>) -> Option<StringLit> {
        let span = span_of(&pair);
        let raw = pair.into_inner().next()?.as_str();
        let mut value = String::with_capacity(raw.len());
        let mut chars = raw.chars();
        while let Some(c) = chars.next() {
            if c == '\\' {
                match chars.next() {
                    Some('n') => value.push('\n'),
                    Some('t') => value.push('\t'),
                    Some(other) => value.push(other),
                    None => {}
                }
            } else {
                value.push(c);
            }
        }
        Some(StringLit { value, span })
    }
}
