//! An artifact read in part from its sections: the core (validated), then, object by
//! object, only the parts of its graph that a use asks for.
//!
//! A plan on a 10^6-arc artifact needs the core, the requested object's nodes and its
//! arcs; pruned arcs and declared transitions only when an unreachable goal is
//! explained, witnesses only in a cell with arms (where exchanges are placed). [`Partial`] holds what has been read, each part validated when
//! it is read ([`crate::validate::graph`]), so that what it hands out was checked as
//! [`crate::validate::validate`] checks a whole artifact. An object whose graph is not
//! read has an empty one: no state of it can be located, so nothing plans on it.

use crate::encoding::ReadError;
use crate::sections::{Sections, Source};
use crate::validate::{self, graph};
use crate::{Artifact, ObjectId};

/// Which parts of an object's graph to read (or have been read).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Parts {
    /// Nodes and arcs (what a search needs).
    pub graph: bool,
    /// Arcs removed by verification, with their reasons (explanations).
    pub pruned: bool,
    /// Witnesses of verified arcs (the placing of exchanges, arm motions).
    pub witnesses: bool,
    /// The object's declared transitions (explanations suggest from them).
    pub transitions: bool,
}

impl Parts {
    /// Nothing.
    pub const NONE: Parts = Parts {
        graph: false,
        pruned: false,
        witnesses: false,
        transitions: false,
    };
    /// Nodes and arcs.
    pub const GRAPH: Parts = Parts {
        graph: true,
        pruned: false,
        witnesses: false,
        transitions: false,
    };
    /// Every part.
    pub const ALL: Parts = Parts {
        graph: true,
        pruned: true,
        witnesses: true,
        transitions: true,
    };
    /// What an explanation of an unreachable goal needs beside the graph: the pruned arcs
    /// and the declared transitions.
    pub const EXPLAIN: Parts = Parts {
        graph: true,
        pruned: true,
        witnesses: false,
        transitions: true,
    };

    /// The parts in `self` or in `other`.
    pub fn with(self, other: Parts) -> Parts {
        Parts {
            graph: self.graph || other.graph,
            pruned: self.pruned || other.pruned,
            witnesses: self.witnesses || other.witnesses,
            transitions: self.transitions || other.transitions,
        }
    }
}

/// A validated core and the validated parts of its objects' graphs (and declared
/// transitions) read so far.
#[derive(Clone, Debug)]
pub struct Partial {
    artifact: Artifact,
    read: Vec<Parts>,
    /// The core section's checksum: later reads must come from the same file.
    core_checksum: Option<u64>,
}

fn invalid(e: validate::Invalid) -> ReadError {
    ReadError::Invalid(e)
}

impl Partial {
    /// Decodes and validates the core of `sections`; no object's graph is read yet.
    pub fn open(sections: &Sections<impl Source>) -> Result<Partial, ReadError> {
        let artifact = sections.core()?;
        validate::core(&artifact).map_err(invalid)?;
        Ok(Partial {
            read: vec![Parts::NONE; artifact.objects.len()],
            core_checksum: sections.table().first().map(|s| s.checksum),
            artifact,
        })
    }

    /// A whole artifact, validated whole: every part of every object counts as read.
    pub fn whole(artifact: Artifact) -> Result<Partial, ReadError> {
        validate::validate(&artifact).map_err(invalid)?;
        Ok(Partial {
            read: vec![Parts::ALL; artifact.objects.len()],
            core_checksum: None,
            artifact,
        })
    }

    /// The artifact as read so far.
    pub fn artifact(&self) -> &Artifact {
        &self.artifact
    }

    /// The artifact, to be changed by a caller that keeps it valid: the runtime's own
    /// verification, which adds the witnesses and pruned arcs it has checked.
    pub fn artifact_mut(&mut self) -> &mut Artifact {
        &mut self.artifact
    }

    /// The parts of object `o`'s graph read so far (none for an object that is not one).
    pub fn parts(&self, o: ObjectId) -> Parts {
        self.read.get(o.index()).copied().unwrap_or(Parts::NONE)
    }

    /// Reads the `parts` of object `o`'s graph not read yet from `sections` (the file
    /// this was opened from) and validates each. On an error nothing of that part is
    /// kept, so the artifact stays valid. The graph (nodes and arcs) is read before pruned
    /// arcs, which index its nodes.
    pub fn read(
        &mut self,
        sections: &Sections<impl Source>,
        o: ObjectId,
        parts: Parts,
    ) -> Result<(), ReadError> {
        let Some(&had) = self.read.get(o.index()) else {
            return Err(ReadError::Corrupt {
                detail: format!("no object {} in the artifact", o.0),
            });
        };
        if self.core_checksum.is_some()
            && self.core_checksum != sections.table().first().map(|s| s.checksum)
        {
            return Err(ReadError::Corrupt {
                detail: "the sections are of another artifact than its core".into(),
            });
        }
        let want = Parts {
            graph: parts.graph || parts.pruned,
            ..parts
        };
        let a = &self.artifact;
        let i = o.index();
        let witnesses_known = |w: &[crate::Witness], had: Parts| had.witnesses.then_some(w.len());
        if want.graph && !had.graph {
            let nodes = sections.nodes(i)?;
            graph::nodes(a, o, &nodes).map_err(invalid)?;
            let n_witnesses = witnesses_known(&a.objects[i].graph.witnesses, had);
            let test = graph::arc_test(a, nodes.len(), n_witnesses);
            let (arcs, passed) = sections.arcs_testing(i, test)?;
            if !passed {
                graph::arcs(a, o, &arcs, nodes.len(), n_witnesses).map_err(invalid)?;
            }
            let g = &mut self.artifact.objects[i].graph;
            (g.nodes, g.arcs) = (nodes, arcs);
            self.read[i].graph = true;
        }
        let had = self.read[i];
        let a = &self.artifact;
        if want.witnesses && !had.witnesses {
            let witnesses = sections.witnesses(i)?;
            graph::witnesses(a, o, &witnesses).map_err(invalid)?;
            let g = &a.objects[i].graph;
            // The indices read before the witnesses were, now checked against them.
            graph::arcs(a, o, &g.arcs, g.nodes.len(), Some(witnesses.len())).map_err(invalid)?;
            graph::pruned(a, o, &g.pruned, g.nodes.len(), Some(witnesses.len()))
                .map_err(invalid)?;
            self.artifact.objects[i].graph.witnesses = witnesses;
            self.read[i].witnesses = true;
        }
        let had = self.read[i];
        let a = &self.artifact;
        if want.pruned && !had.pruned {
            let pruned = sections.pruned(i)?;
            let g = &a.objects[i].graph;
            let n_witnesses = witnesses_known(&g.witnesses, had);
            graph::pruned(a, o, &pruned, g.nodes.len(), n_witnesses).map_err(invalid)?;
            self.artifact.objects[i].graph.pruned = pruned;
            self.read[i].pruned = true;
        }
        if want.transitions && !self.read[i].transitions {
            let transitions = sections.transitions(i)?;
            graph::transitions(&self.artifact, o, &transitions).map_err(invalid)?;
            self.artifact.objects[i].transitions = transitions;
            self.read[i].transitions = true;
        }
        Ok(())
    }

    /// Every part of every object, as [`Sections::artifact`] and a whole validation give.
    pub fn read_all(&mut self, sections: &Sections<impl Source>) -> Result<(), ReadError> {
        for i in 0..self.read.len() {
            self.read(sections, ObjectId(i as u32), Parts::ALL)?;
        }
        Ok(())
    }
}
