//! Lowers a compiled cell into the artifact schema.
//!
//! The artifact is the compiler/runtime boundary: everything the runtime needs, with ids
//! turned into indices and spans into a table, and nothing of the compiler's own types.

use rustc_hash::FxHashMap as HashMap;

use cellc_lang::ast::GraspKeyword;
use cellc_lang::{FileId, SourceMap, Span};
use cellc_schema as schema;
use cellc_schema::math::{aabb_to_schema, iso_to_schema};
use cellc_schema::sha256_hex;

use crate::budget::MAX_GRAPH_SIZE;
use crate::graph::{ArcSource, ObjectGraph};
use crate::ids::Id;
use crate::model::*;

/// Builds the artifact of a compiled cell.
pub fn lower(cell: &Cell, graphs: &[ObjectGraph], sources: &SourceMap) -> schema::Artifact {
    let mut spans = SpanTable::new(sources);
    let robots = cell
        .robots
        .iter()
        .map(|(_, r)| schema::Robot {
            name: r.name.clone(),
            urdf_path: r.urdf_path.clone(),
            urdf_sha256: r.urdf_sha256.clone(),
            meshes: r.meshes.clone(),
            srdf: r.srdf.as_ref().map(|(path, sha256)| schema::SourceFile {
                path: path.clone(),
                sha256: sha256.clone(),
            }),
            disabled_collisions: r.disabled_collisions.clone(),
            base_link: r.base_link.clone(),
            tip_link: r.tip_link.clone(),
            joints: r
                .chain_joints
                .iter()
                .map(|j| schema::Joint {
                    name: j.name.clone(),
                    prismatic: j.prismatic,
                    lower: j.lower.is_finite().then_some(j.lower),
                    upper: j.upper.is_finite().then_some(j.upper),
                    velocity: j
                        .velocity
                        .as_ref()
                        .map_or(Joint::DEFAULT_VELOCITY, |l| l.value),
                    acceleration: j
                        .acceleration
                        .as_ref()
                        .map_or(Joint::DEFAULT_ACCELERATION, |l| l.value),
                    jerk: j.jerk.as_ref().map(|l| l.value),
                })
                .collect(),
            span: spans.get(r.origin.file, r.origin.span),
        })
        .collect();
    let holder_kinds = cell
        .holder_kinds
        .iter()
        .map(|(_, k)| schema::HolderKind {
            name: k.name.clone(),
            class: match k.class {
                HolderClass::Hand => schema::HolderClass::Hand,
                HolderClass::Support => schema::HolderClass::Support,
            },
            solids: k
                .solids
                .iter()
                .map(|s| schema::Solid {
                    shape: shape(&s.shape),
                    pose: iso_to_schema(&s.pose),
                })
                .collect(),
        })
        .collect();
    let workspaces = cell
        .workspaces
        .iter()
        .map(|(_, w)| schema::Workspace {
            name: w.name.clone(),
            label: w.label.clone(),
            boxes: w.boxes.iter().map(aabb_to_schema).collect(),
            derived: w.derived,
            span: spans.get(w.origin.file, w.origin.span),
        })
        .collect();
    let end_effectors = cell
        .end_effectors
        .iter()
        .map(|(_, e)| schema::EndEffector {
            name: e.name.clone(),
            movable: e.is_movable(),
            kind: e.kind.map(|k| k.0),
            body: match &e.body {
                Body::Abstract => schema::Body::Abstract,
                Body::Arm { robot, base, home } => match robot {
                    Some(robot) => schema::Body::Arm {
                        robot: robot.0,
                        base: iso_to_schema(base),
                        home: home.clone(),
                    },
                    None => schema::Body::Abstract,
                },
                Body::Surface { slab, reach_height } => schema::Body::Surface {
                    slab: aabb_to_schema(slab),
                    reach_height: *reach_height,
                },
            },
            reach_boxes: e.reach_boxes.iter().map(aabb_to_schema).collect(),
            reaches: e.reaches.iter().map(|w| w.0).collect(),
            span: spans.get(e.origin.file, e.origin.span),
        })
        .collect();
    // Each grasp's index among its object's grasps (the artifact's grasp numbers).
    let mut index_in_object: Vec<u32> = vec![0; cell.grasps.len()];
    for (_, object) in cell.objects.iter() {
        for (i, &g) in object.grasps.iter().enumerate() {
            index_in_object[g.index()] = i as u32;
        }
    }
    let transitions = crate::graph::transitions_by_object(cell);
    let objects = graphs
        .iter()
        .map(|g| lower_object(cell, g, &transitions[g.object.index()], &mut spans))
        .collect();
    schema::Artifact {
        format: schema::FORMAT.to_string(),
        format_version: schema::FORMAT_VERSION,
        compiler_version: env!("CARGO_PKG_VERSION").to_string(),
        cell: cell.name.clone(),
        sources: sources
            .iter()
            .map(|(_, f)| schema::SourceFile {
                path: f.path.clone(),
                sha256: sha256_hex(f.text.as_bytes()),
            })
            .collect(),
        weights: schema::Weights {
            move_weight: cell.weights.move_weight,
            transition_weight: cell.weights.transition_weight,
        },
        robots,
        holder_kinds,
        workspaces,
        end_effectors,
        objects,
        adjacency: Some(schema::AdjacencyRecord {
            declared: !cell.adjacencies.is_empty(),
            pairs: adjacent_pairs(cell),
        }),
        obstacles: cell
            .obstacles
            .iter()
            .map(|(n, b, _)| (n.clone(), aabb_to_schema(b)))
            .collect(),
        requests: cell
            .requests
            .iter()
            .map(|r| schema::NamedRequest {
                name: r.name.clone(),
                object: schema::ObjectId(r.object.0),
                from: placement(cell, &index_in_object, r.object, &r.from),
                to: placement(cell, &index_in_object, r.object, &r.to),
                span: spans.get(r.origin.file, r.origin.span),
            })
            .collect(),
        world: cell
            .world
            .iter()
            .map(|p| schema::InitialPlacement {
                object: schema::ObjectId(p.object.0),
                placement: placement(cell, &index_in_object, p.object, &p.placement),
                span: spans.get(p.origin.file, p.origin.span),
            })
            .collect(),
        tasks: cell
            .tasks
            .iter()
            .map(|t| schema::NamedTask {
                name: t.name.clone(),
                steps: t
                    .steps
                    .iter()
                    .map(|s| schema::TaskStep {
                        object: schema::ObjectId(s.object.0),
                        to: placement(cell, &index_in_object, s.object, &s.to),
                        span: spans.get(s.origin.file, s.origin.span),
                    })
                    .collect(),
                span: spans.get(t.origin.file, t.origin.span),
            })
            .collect(),
        allowed_contacts: cell
            .allowed_contacts
            .iter()
            .map(|(a, b, _)| (a.clone(), b.clone()))
            .collect(),
        spans: spans.table,
        verification: None,
    }
}

/// A placement of `object` (a request's, a world line's, a task step's) in the artifact:
/// its grasp numbered among the object's grasps (`index_in_object`, by grasp id). A grasp
/// of another object cannot be written (grasps are looked up in the placement's object),
/// and is left out rather than misnumbered.
fn placement(
    cell: &Cell,
    index_in_object: &[u32],
    object: crate::ids::ObjectId,
    p: &RequestPlacement,
) -> schema::RequestPlacement {
    let grasp = p
        .grasp
        .filter(|&g| cell.grasps[g].object == object)
        .map(|g| schema::GraspId(index_in_object[g.index()]));
    schema::RequestPlacement {
        end_effector: schema::EndEffectorId(p.end_effector.0),
        grasp,
        workspace: p.workspace.map(|w| schema::WorkspaceId(w.0)),
        pose: p.pose.as_ref().map(iso_to_schema),
    }
}

/// The scene part of a cell resolved so far, as an artifact: robots, end-effectors (with
/// the reach written so far), holder kinds, objects with their grasps and declared
/// transitions, obstacles and allowed contacts; no workspaces, empty graphs, no
/// requests. What [`crate::reach::ReachSolver`] builds a scene from, before workspaces
/// are derived.
pub fn lower_scene(cell: &Cell, sources: &SourceMap) -> schema::Artifact {
    let empty: Vec<ObjectGraph> = cell
        .objects
        .iter()
        .map(|(object, _)| ObjectGraph::empty(object))
        .collect();
    let mut artifact = lower(cell, &empty, sources);
    artifact.workspaces.clear();
    artifact.requests.clear();
    artifact.world.clear();
    artifact.tasks.clear();
    artifact.adjacency = None;
    for e in &mut artifact.end_effectors {
        e.reaches.clear();
    }
    artifact
}

/// The artifact form of one object; `transitions` are its own (indices into
/// [`Cell::transitions`], in order), so lowering every object costs the transitions once.
fn lower_object(
    cell: &Cell,
    g: &ObjectGraph,
    transitions: &[usize],
    spans: &mut SpanTable,
) -> schema::Object {
    let object = &cell.objects[g.object];
    let grasp_index: HashMap<crate::ids::GraspId, u32> = object
        .grasps
        .iter()
        .enumerate()
        .map(|(i, &gid)| (gid, i as u32))
        .collect();
    let grasps = object
        .grasps
        .iter()
        .map(|&gid| {
            let grasp = &cell.grasps[gid];
            schema::Grasp {
                name: grasp.name.clone(),
                label: grasp.label.clone(),
                holder: match grasp.holder {
                    Some(Holder::Kind(k)) => schema::Holder::Kind(k.0),
                    Some(Holder::EndEffector(e)) => schema::Holder::EndEffector(e.0),
                    None => schema::Holder::EndEffector(u32::MAX),
                },
                rest: grasp.keyword == GraspKeyword::Rest,
                pose: grasp.pose.as_ref().map(iso_to_schema),
                span: spans.get(grasp.origin.file, grasp.origin.span),
            }
        })
        .collect();
    let nodes = g
        .graph
        .node_weights()
        .map(|s| schema::Node {
            end_effector: schema::EndEffectorId(s.end_effector.0),
            grasp: schema::GraspId(grasp_index[&s.grasp]),
            workspace: schema::WorkspaceId(s.workspace.0),
        })
        .collect();
    let arcs = g
        .graph
        .edge_indices()
        .filter_map(|e| {
            let (from, to) = g.graph.edge_endpoints(e)?;
            let arc = g.graph[e];
            let (kind, source, via) = match arc.source {
                ArcSource::Move { adjacency } => {
                    let state = g.graph[from];
                    let grasp = &cell.grasps[state.grasp];
                    let source = spans.get(grasp.origin.file, grasp.origin.span);
                    let via = adjacency.map(|i| {
                        let adj = &cell.adjacencies[i];
                        spans.get(adj.origin.file, adj.origin.span)
                    });
                    (schema::ArcKind::Move, source, via)
                }
                ArcSource::Transition { transition } => {
                    let t = &cell.transitions[transition];
                    (
                        schema::ArcKind::Transition,
                        spans.get(t.origin.file, t.origin.span),
                        None,
                    )
                }
            };
            Some(schema::Arc {
                from: from.index() as u32,
                to: to.index() as u32,
                kind,
                weight: arc.weight,
                source,
                via,
                witness: None,
            })
        })
        .collect();
    let transitions = transitions
        .iter()
        .map(|&t| &cell.transitions[t])
        .filter_map(|t| {
            Some(schema::DeclaredTransition {
                from: *grasp_index.get(&t.from)?,
                to: *grasp_index.get(&t.to)?,
                span: spans.get(t.origin.file, t.origin.span),
            })
        })
        .collect();
    schema::Object {
        name: object.name.clone(),
        transitions,
        shape: object.shape.as_ref().map(shape),
        symmetries: object
            .symmetries
            .iter()
            .map(|s| schema::Symmetry {
                axis: s.axis,
                order: s.order,
            })
            .collect(),
        grasps,
        graph: schema::Graph {
            nodes,
            arcs,
            pruned: Vec::new(),
            witnesses: Vec::new(),
        },
        span: spans.get(object.origin.file, object.origin.span),
    }
}

/// Every adjacent pair of workspaces, each once, in order. Artifacts are lowered from
/// cells whose graphs were built, so the pairs are within [`MAX_GRAPH_SIZE`].
fn adjacent_pairs(cell: &Cell) -> Vec<(u32, u32)> {
    crate::graph::cell_rules(cell)
        .adjacent_pairs(MAX_GRAPH_SIZE)
        .unwrap_or_default()
        .into_iter()
        .map(|(a, b)| (a.0, b.0))
        .collect()
}

/// Interns spans so that a million arcs made by a few hundred declarations share a few
/// hundred entries.
struct SpanTable<'s> {
    sources: &'s SourceMap,
    table: Vec<schema::SourceSpan>,
    index: HashMap<(FileId, Span), u32>,
}

impl<'s> SpanTable<'s> {
    fn new(sources: &'s SourceMap) -> Self {
        SpanTable {
            sources,
            table: Vec::new(),
            index: HashMap::default(),
        }
    }

    fn get(&mut self, file: FileId, span: Span) -> u32 {
        if let Some(&i) = self.index.get(&(file, span)) {
            return i;
        }
        let (line, _) = self.sources.get(file).line_col(span.start);
        let i = self.table.len() as u32;
        self.table.push(schema::SourceSpan {
            file: file.0,
            start: span.start,
            end: span.end,
            line: line as u32,
        });
        self.index.insert((file, span), i);
        i
    }
}

fn shape(s: &Shape) -> schema::Shape {
    match s {
        Shape::Box { size } => schema::Shape::Box { size: *size },
        Shape::Cylinder { radius, height } => schema::Shape::Cylinder {
            radius: *radius,
            height: *height,
        },
        Shape::Sphere { radius } => schema::Shape::Sphere { radius: *radius },
        Shape::Mesh { path } => schema::Shape::Mesh { path: path.clone() },
    }
}
