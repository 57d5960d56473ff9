//! Items, object members and requirements: the tree of what a cell declares.

use pest::iterators::Pair;

use super::{span_of, Builder};
use crate::ast::*;
use crate::grammar::Rule;

impl Builder<'_, '_> {
    pub(super) fn item(&mut self, pair: Pair<'_, Rule>) -> Option<Item> {
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
            Rule::package_item => {
                let name = self.name(inner.next()?)?;
                let _at = inner.next();
                Item::Package(PackageItem {
                    name,
                    dir: self.string(inner.next()?)?,
                    span,
                })
            }
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
                let (mut srdf, mut group, mut base, mut tip) = (None, None, None, None);
                while let Some(keyword) = inner.next() {
                    let value = inner.next()?;
                    match keyword.as_rule() {
                        Rule::kw_srdf => srdf = Some(self.string(value)?),
                        Rule::kw_group => group = Some(self.name(value)?),
                        Rule::kw_base => base = Some(self.name(value)?),
                        _ => tip = Some(self.name(value)?),
                    }
                }
                Item::Robot(RobotItem {
                    name,
                    urdf,
                    srdf,
                    group,
                    base,
                    tip,
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
                let mut home_state = None;
                if let Some(clause) = inner.next() {
                    let is_state = clause.as_rule() == Rule::home_state;
                    for pair in clause.into_inner().skip(1) {
                        if is_state {
                            home_state = Some(self.name(pair)?);
                            continue;
                        }
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
                    home_state,
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
            Rule::reach_item => {
                let end_effector = self.name(inner.next()?)?;
                let extent = inner.next()?;
                let extent = match extent.as_rule() {
                    Rule::kw_auto => ReachExtent::Auto(span_of(&extent)),
                    _ => ReachExtent::Box(self.aabb(extent)?),
                };
                Item::Reach(ReachItem {
                    end_effector,
                    extent,
                    span,
                })
            }
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
            Rule::limits_item => {
                let target = inner.next()?;
                let target = if target.as_rule() == Rule::name {
                    let name = self.name(target)?;
                    Qualified {
                        object: None,
                        span: name.span,
                        name,
                    }
                } else {
                    self.qualified(target)?
                };
                let mut file = None;
                let mut values = Vec::new();
                for p in inner {
                    if p.as_rule() == Rule::limits_file {
                        let string = p.into_inner().find(|q| q.as_rule() == Rule::string)?;
                        file = Some(self.string(string)?);
                        continue;
                    }
                    let vspan = span_of(&p);
                    let mut parts = p.into_inner();
                    let kind = match parts.next()?.into_inner().next()?.as_rule() {
                        Rule::kw_velocity => LimitKind::Velocity,
                        Rule::kw_acceleration => LimitKind::Acceleration,
                        _ => LimitKind::Jerk,
                    };
                    values.push(LimitValue {
                        kind,
                        rate: self.rate(parts.next()?)?,
                        span: vspan,
                    });
                }
                Item::Limits(LimitsItem {
                    target,
                    file,
                    values,
                    span,
                })
            }
            Rule::world_item => Item::World(self.world_item(span, inner)?),
            Rule::task_item => Item::Task(self.task_item(span, inner)?),
            _ => return None,
        })
    }

    pub(super) fn member(&mut self, pair: Pair<'_, Rule>) -> Option<ObjectMember> {
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
                let mut file = None;
                let mut family = Vec::new();
                for p in inner {
                    match p.as_rule() {
                        Rule::label => label = Some(self.string(p.into_inner().next()?)?),
                        Rule::name => holder = Some(self.name(p)?),
                        Rule::pose => pose = Some(self.pose(p)?),
                        Rule::grasps_file => {
                            let string = p.into_inner().find(|q| q.as_rule() == Rule::string)?;
                            file = Some(self.string(string)?);
                        }
                        Rule::family_clause => family.push(self.family_clause(p)?),
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
                    file,
                    family,
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
                let matching = inner.next().map(|p| span_of(&p));
                ObjectMember::Transition(TransitionMember {
                    from,
                    direction,
                    to,
                    matching,
                    span,
                })
            }
            _ => return None,
        })
    }

    pub(super) fn requirement(&mut self, pair: Pair<'_, Rule>) -> Option<Requirement> {
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

    pub(super) fn placement(&mut self, pair: Pair<'_, Rule>) -> Option<Placement> {
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

    pub(super) fn request_placement(&mut self, pair: Pair<'_, Rule>) -> Option<RequestPlacement> {
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
}
