//! The arcs a change to the declarations adds, without rebuilding the graph: what the
//! explanation of an unreachable goal needs to check a suggestion on the graph the
//! compiler would build after it (the rules tests compare with a rebuild).

use super::{CellRules, Edit, ObjectRules, State};
use crate::ids::{EndEffectorId, GraspId, WorkspaceId};

impl CellRules {
    /// The arcs `edit` adds to an object's graph, on these rules with the edit (and any
    /// made with it) already made. Arcs the graph already has may be among them
    /// (declaring again what is declared); none it would gain is left out. A reach
    /// extension needs no look at other hands: with derived adjacency, a movable
    /// end-effector that reaches two workspaces has already made them adjacent.
    pub fn added_by(&self, object: &ObjectRules, edit: Edit) -> Vec<(State, State)> {
        match edit {
            Edit::Transition(from, to) => self.transition_arcs(object, from, to),
            Edit::Adjacency(a, b) => (0..self.n_end_effectors() as u32)
                .flat_map(|e| self.move_arcs(object, EndEffectorId(e), a, b))
                .collect(),
            Edit::Reach(e, w) => {
                let mut out = Vec::new();
                for &x in self.reach(e) {
                    out.extend(self.move_arcs(object, e, w, x));
                }
                out.extend(self.transition_arcs_at(object, e, w));
                out
            }
        }
    }

    /// The states of `e` in `w`, one per grasp it may hold (those a reach extension to `w`
    /// adds), in grasp order.
    pub fn states_at<'a>(
        &'a self,
        object: &'a ObjectRules,
        e: EndEffectorId,
        w: WorkspaceId,
    ) -> impl Iterator<Item = State> + 'a {
        object.grasps_of(e).iter().map(move |&g| State {
            end_effector: e,
            grasp: g,
            workspace: w,
        })
    }

    /// The moves of `e` between `a` and `b`, both ways, for every grasp it may hold (none
    /// unless it [carries](CellRules::carries) between them).
    fn move_arcs(
        &self,
        object: &ObjectRules,
        e: EndEffectorId,
        a: WorkspaceId,
        b: WorkspaceId,
    ) -> Vec<(State, State)> {
        if !self.carries(e, a, b) {
            return Vec::new();
        }
        let mut out = Vec::new();
        for &g in object.grasps_of(e) {
            let at = |workspace| State {
                end_effector: e,
                grasp: g,
                workspace,
            };
            out.push((at(a), at(b)));
            out.push((at(b), at(a)));
        }
        out
    }

    /// The arcs a declared transition `from -> to` makes: by giver, taker, then every
    /// workspace both reach.
    fn transition_arcs(
        &self,
        object: &ObjectRules,
        from: GraspId,
        to: GraspId,
    ) -> Vec<(State, State)> {
        let mut out = Vec::new();
        self.exchanges(object, from, to, None, &mut out);
        out
    }

    /// The arcs of the object's declared transitions that `e` takes part in inside `w`
    /// (those a reach extension to `w` adds), grouped by the grasps `e` may hold.
    fn transition_arcs_at(
        &self,
        object: &ObjectRules,
        e: EndEffectorId,
        w: WorkspaceId,
    ) -> Vec<(State, State)> {
        let mut out = Vec::new();
        let mut done = vec![false; object.declared.len()];
        for &g in object.grasps_of(e) {
            for &i in object
                .declared_by_grasp
                .get(g.index())
                .into_iter()
                .flatten()
            {
                if std::mem::replace(&mut done[i], true) {
                    continue;
                }
                let (from, to) = object.declared[i];
                self.exchanges(object, from, to, Some((e, w)), &mut out);
            }
        }
        out
    }

    /// Transition arcs `from -> to`; with `only`, just those of that end-effector in that
    /// workspace.
    fn exchanges(
        &self,
        object: &ObjectRules,
        from: GraspId,
        to: GraspId,
        only: Option<(EndEffectorId, WorkspaceId)>,
        out: &mut Vec<(State, State)>,
    ) {
        let explicit = object.explicit_pair(from, to);
        for &ei in object.holders(from) {
            for &ej in object.holders(to) {
                if !self.may_exchange(ei, ej, explicit)
                    || only.is_some_and(|(e, _)| ei != e && ej != e)
                {
                    continue;
                }
                let shared = self
                    .reach(ei)
                    .iter()
                    .filter(|&&w| self.reaches(ej, w) && only.is_none_or(|(_, ow)| ow == w));
                for &w in shared {
                    out.push((
                        State {
                            end_effector: ei,
                            grasp: from,
                            workspace: w,
                        },
                        State {
                            end_effector: ej,
                            grasp: to,
                            workspace: w,
                        },
                    ));
                }
            }
        }
    }
}
