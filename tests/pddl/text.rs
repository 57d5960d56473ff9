//! The exported PDDL read back: a small s-expression reader and what the tests need of a
//! domain (its arc actions) and a problem (start, targets, goal).

use std::collections::BTreeMap;

/// A PDDL text as nested lists (comments dropped).
#[derive(Clone, Debug, PartialEq)]
pub enum Sexp {
    Atom(String),
    List(Vec<Sexp>),
}

impl Sexp {
    pub fn parse(text: &str) -> Sexp {
        let mut stack: Vec<Vec<Sexp>> = vec![Vec::new()];
        for line in text.lines() {
            let code = line.split(';').next().unwrap_or_default();
            let spaced = code.replace('(', " ( ").replace(')', " ) ");
            for token in spaced.split_whitespace() {
                match token {
                    "(" => stack.push(Vec::new()),
                    ")" => {
                        let list = stack.pop().expect("balanced");
                        stack.last_mut().expect("balanced").push(Sexp::List(list));
                    }
                    atom => stack
                        .last_mut()
                        .expect("balanced")
                        .push(Sexp::Atom(atom.to_string())),
                }
            }
        }
        assert_eq!(stack.len(), 1, "unbalanced parentheses");
        let mut top = stack.pop().unwrap_or_default();
        assert_eq!(top.len(), 1, "one definition per file");
        top.remove(0)
    }

    fn items(&self) -> &[Sexp] {
        match self {
            Sexp::List(items) => items,
            Sexp::Atom(_) => &[],
        }
    }

    fn atom(&self) -> &str {
        match self {
            Sexp::Atom(a) => a,
            Sexp::List(_) => "",
        }
    }

    /// The list after `key` in a definition (`(:init ...)`), or the value after a
    /// `:keyword` inside an action.
    fn section(&self, key: &str) -> Option<&Sexp> {
        self.items()
            .iter()
            .find(|s| s.items().first().is_some_and(|k| k.atom() == key))
    }

    fn after(&self, keyword: &str) -> Option<&Sexp> {
        let items = self.items();
        let at = items.iter().position(|s| s.atom() == keyword)?;
        items.get(at + 1)
    }

    /// `(at ITEM STATE)` as the state.
    fn at_state(&self) -> Option<&str> {
        match self.items() {
            [head, _, state] if head.atom() == "at" => Some(state.atom()),
            _ => None,
        }
    }
}

/// An arc action as the domain writes it.
#[derive(Clone, Debug)]
pub struct Action {
    pub from: String,
    pub to: String,
    pub cost: u64,
}

/// Every action of a domain but `arrive`, by name.
pub fn actions(domain: &Sexp) -> BTreeMap<String, Action> {
    let mut out = BTreeMap::new();
    for action in domain
        .items()
        .iter()
        .filter(|s| s.items().first().is_some_and(|k| k.atom() == ":action"))
    {
        let name = action.items()[1].atom().to_string();
        if name == "arrive" {
            continue;
        }
        let from = action
            .after(":precondition")
            .and_then(Sexp::at_state)
            .expect("an arc's precondition is where the object is")
            .to_string();
        let effect = action.after(":effect").expect("an effect").items();
        let to = effect
            .iter()
            .find_map(Sexp::at_state)
            .expect("an arc's effect puts the object somewhere")
            .to_string();
        let cost = effect
            .iter()
            .find(|e| e.items().first().is_some_and(|k| k.atom() == "increase"))
            .and_then(|e| e.items().get(2))
            .and_then(|c| c.atom().parse().ok())
            .expect("an arc costs a whole number");
        out.insert(name, Action { from, to, cost });
    }
    out
}

/// What a problem asks: start, targets, the goal's state (if one) and whether it must
/// leave.
pub struct Asked {
    pub start: String,
    pub targets: Vec<String>,
    pub goal_state: Option<String>,
    pub must_leave: bool,
}

pub fn asked(problem: &Sexp) -> Asked {
    let init = problem.section(":init").expect("an init").items();
    let start = init
        .iter()
        .find_map(Sexp::at_state)
        .expect("the object is somewhere")
        .to_string();
    let targets = init
        .iter()
        .filter(|f| f.items().first().is_some_and(|k| k.atom() == "target"))
        .map(|f| f.items()[1].atom().to_string())
        .collect();
    let goal = &problem.section(":goal").expect("a goal").items()[1];
    let conjuncts: Vec<&Sexp> = match goal.items().first().map(Sexp::atom) {
        Some("and") => goal.items()[1..].iter().collect(),
        _ => vec![goal],
    };
    Asked {
        start,
        targets,
        goal_state: conjuncts
            .iter()
            .find_map(|c| c.at_state())
            .map(str::to_string),
        must_leave: conjuncts
            .iter()
            .any(|c| c.items().first().is_some_and(|k| k.atom() == "moved")),
    }
}
