//! The `world` and `task` items: blocks of one line each, recovered line by line like an
//! object's members.

use pest::iterators::{Pair, Pairs};

use super::{span_of, Builder};
use crate::ast::*;
use crate::grammar::Rule;
use crate::span::Span;

impl Builder<'_, '_> {
    /// `world { ... }`, after its keyword: `inner` holds the body.
    pub(super) fn world_item(
        &mut self,
        span: Span,
        mut inner: Pairs<'_, Rule>,
    ) -> Option<WorldItem> {
        let mut entries: Vec<WorldEntry> = Vec::new();
        for p in inner.next()?.into_inner() {
            if p.as_rule() == Rule::recover {
                let previous = entries.last().map(|e| e.span);
                self.recovered(
                    &p,
                    previous,
                    Rule::world_entry_probe,
                    Rule::world_entry_line,
                );
                continue;
            }
            entries.push(self.world_entry(p)?);
        }
        Some(WorldItem { entries, span })
    }

    fn world_entry(&mut self, pair: Pair<'_, Rule>) -> Option<WorldEntry> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let object = self.name(inner.next()?)?;
        let _colon = inner.next();
        let placement = inner.next()?.into_inner().next()?;
        let placement = match placement.as_rule() {
            Rule::request_placement => WorldPlacement::Placed(self.request_placement(placement)?),
            _ => WorldPlacement::Bare(self.qualified(placement)?),
        };
        Some(WorldEntry {
            object,
            placement,
            span,
        })
    }

    /// `task NAME { ... }`, after its keyword: `inner` holds the name and the body.
    pub(super) fn task_item(&mut self, span: Span, mut inner: Pairs<'_, Rule>) -> Option<TaskItem> {
        let name = self.name(inner.next()?)?;
        let mut steps: Vec<TaskStep> = Vec::new();
        for p in inner.next()?.into_inner() {
            if p.as_rule() == Rule::recover {
                let previous = steps.last().map(|s| s.span);
                self.recovered(&p, previous, Rule::task_step_probe, Rule::task_step_line);
                continue;
            }
            let step_span = span_of(&p);
            let mut parts = p.into_inner();
            let object = self.name(parts.next()?)?;
            let _to = parts.next();
            let to = self.request_placement(parts.next()?)?;
            steps.push(TaskStep {
                object,
                to,
                span: step_span,
            });
        }
        Some(TaskItem { name, steps, span })
    }
}
