//! The words that start items and object members: the one table the parser's error
//! phrases, the formatter's quoting, the written-name rule and the language server's
//! completion read. The grammar (`cell.pest`) cannot import it, so a test holds the
//! grammar's `reserved` rule and its `kw_*` rules to this table word for word.

use crate::grammar::Rule;

/// A word that starts an item or an object member.
#[derive(Clone, Copy, Debug)]
pub struct Keyword {
    /// The word as written (`workspaces`).
    pub word: &'static str,
    /// The words an editor offers to complete it with: the keyword and, where the
    /// grammar allows only one continuation, that continuation (`workspaces from reach`).
    pub completion: &'static str,
    /// The grammar rule that matches the word.
    pub(crate) rule: Rule,
}

const fn keyword(word: &'static str, rule: Rule) -> Keyword {
    Keyword {
        word,
        completion: word,
        rule,
    }
}

/// Words that start an item (the grammar's `item` rule), in the order an editor offers
/// them.
pub const ITEM_KEYWORDS: &[Keyword] = &[
    keyword("units", Rule::kw_units),
    keyword("weights", Rule::kw_weights),
    keyword("include", Rule::kw_include),
    keyword("package", Rule::kw_package),
    Keyword {
        word: "workspaces",
        completion: "workspaces from reach",
        rule: Rule::kw_workspaces,
    },
    keyword("workspace", Rule::kw_workspace),
    keyword("adjacent", Rule::kw_adjacent),
    keyword("fixed", Rule::kw_fixed),
    keyword("movable", Rule::kw_movable),
    keyword("hand", Rule::kw_hand),
    keyword("support", Rule::kw_support),
    keyword("robot", Rule::kw_robot),
    keyword("arm", Rule::kw_arm),
    keyword("surface", Rule::kw_surface),
    keyword("reach", Rule::kw_reach),
    keyword("object", Rule::kw_object),
    keyword("expect", Rule::kw_expect),
    Keyword {
        word: "allow",
        completion: "allow contact",
        rule: Rule::kw_allow,
    },
    keyword("request", Rule::kw_request),
    keyword("obstacle", Rule::kw_obstacle),
    keyword("limits", Rule::kw_limits),
    keyword("world", Rule::kw_world),
    keyword("task", Rule::kw_task),
];

/// Words that start an object's member (the grammar's `object_member` rule).
pub const MEMBER_KEYWORDS: &[Keyword] = &[
    keyword("shape", Rule::kw_shape),
    keyword("symmetry", Rule::kw_symmetry),
    keyword("grasp", Rule::kw_grasp),
    keyword("rest", Rule::kw_rest),
    keyword("transition", Rule::kw_transition),
];

/// True when `word` cannot be a plain name: it starts an item or an object member (the
/// grammar's `reserved` rule), so `adjacent w1` followed by `fixed table ...` does not read
/// `fixed` as a second workspace.
pub fn is_reserved(word: &str) -> bool {
    ITEM_KEYWORDS
        .iter()
        .chain(MEMBER_KEYWORDS)
        .any(|k| k.word == word)
}

/// `text` as the language writes a name: plain when it is a plain identifier and not a
/// reserved word, otherwise in backticks. The one home of this rule: the formatter, the
/// fixes and help lines, the importers and the language server's edits all write names
/// through it, so a name they write always parses back as the same name.
pub fn written_name(text: &str) -> String {
    if crate::ast::needs_quotes(text) || is_reserved(text) {
        format!("`{text}`")
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::*;

    const GRAMMAR: &str = include_str!("cell.pest");

    /// The words the grammar's `reserved` rule lists.
    fn grammar_reserved() -> BTreeSet<&'static str> {
        let start = GRAMMAR
            .find("\nreserved = @{")
            .expect("cell.pest has a reserved rule");
        let rule = &GRAMMAR[start..];
        let body = &rule[..rule.find("~ !ident_char").expect("reserved ends its words")];
        body.split('"').skip(1).step_by(2).collect()
    }

    #[test]
    fn the_grammars_reserved_words_are_the_item_and_member_keywords() {
        let table: BTreeSet<&str> = ITEM_KEYWORDS
            .iter()
            .chain(MEMBER_KEYWORDS)
            .map(|k| k.word)
            .collect();
        assert_eq!(grammar_reserved(), table);
        assert_eq!(
            table.len(),
            ITEM_KEYWORDS.len() + MEMBER_KEYWORDS.len(),
            "a word is listed twice"
        );
    }

    /// Each `kw_NAME = @{ "WORD" ~ !ident_char }` rule of the grammar, as NAME and WORD.
    fn grammar_keyword_rules() -> Vec<(&'static str, &'static str)> {
        GRAMMAR
            .lines()
            .filter(|line| line.starts_with("kw_"))
            .map(|line| {
                let (name, rest) = line.split_once('=').expect("a rule has `=`");
                let word = rest
                    .split('"')
                    .nth(1)
                    .expect("a keyword rule matches a word");
                (name.trim(), word)
            })
            .collect()
    }

    #[test]
    fn each_keyword_is_its_grammar_rules_word() {
        let rules = grammar_keyword_rules();
        assert!(rules.len() > ITEM_KEYWORDS.len() + MEMBER_KEYWORDS.len());
        for k in ITEM_KEYWORDS.iter().chain(MEMBER_KEYWORDS) {
            let name = format!("{:?}", k.rule);
            assert_eq!(name, format!("kw_{}", k.word));
            assert!(
                rules.contains(&(name.as_str(), k.word)),
                "cell.pest has no `{name}` rule matching `{}`",
                k.word
            );
            assert_eq!(crate::phrases::phrase(k.rule), format!("`{}`", k.word));
            assert!(k.completion.starts_with(k.word));
        }
    }

    #[test]
    fn reserved_and_odd_names_are_written_in_backticks() {
        assert_eq!(written_name("left_arm"), "left_arm");
        assert_eq!(written_name("_x9"), "_x9");
        assert_eq!(written_name("fixed"), "`fixed`");
        assert_eq!(written_name("transition"), "`transition`");
        assert_eq!(written_name("fixedly"), "fixedly");
        assert_eq!(written_name("top x- (copy)"), "`top x- (copy)`");
        assert_eq!(written_name("9lives"), "`9lives`");
        // `from` starts no item: the grammar takes it as a plain name.
        assert_eq!(written_name("from"), "from");
    }
}
