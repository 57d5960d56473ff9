//! Syntax errors in human words.
//!
//! pest reports what it expected as grammar rules. Every rule has a phrase here, in an
//! exhaustive match, so adding a rule without saying how to describe it does not compile
//! and no error ever shows a rule name.

use std::collections::BTreeSet;

use pest::error::{Error, ErrorVariant, InputLocation};

use crate::diagnostic::{did_you_mean, Diagnostic};
use crate::grammar::Rule;
use crate::keywords::{is_reserved, Keyword, ITEM_KEYWORDS, MEMBER_KEYWORDS};
use crate::span::{FileId, Span};

/// Codes of the syntax phase (the registry's [`crate::codes::parse`]).
pub use crate::codes::parse as codes;

/// Punctuation worth naming in "expected ..." (comment openers, quotes and `_` are
/// technically expected almost everywhere and would only be noise).
const STRUCTURAL: &[&str] = &["{", "}", "(", ")", ",", ":", "=", "->", "<->"];

/// A human description of what a rule matches.
pub fn phrase(rule: Rule) -> &'static str {
    match rule {
        Rule::WHITESPACE => "white space",
        Rule::COMMENT => "a comment",
        Rule::EOI => "the end of the file",
        Rule::file => "a cell like `cell NAME { ... }`",
        Rule::unit_kind => "`cell` or `library`",
        Rule::body => "the items of the cell",
        Rule::item_probe | Rule::item => {
            "an item (`workspace`, `fixed`, `movable`, `object`, `expect`, ...)"
        }
        Rule::member_probe | Rule::object_member => {
            "an object member (`shape`, `symmetry`, `grasp`, `rest` or `transition`)"
        }
        Rule::placement_arg => "a placement like `table in w1` or `table at (x, y, z)`",
        Rule::item_line => "an item (`workspace`, `fixed`, `movable`, `object`, `expect`, ...)",
        Rule::member_line => {
            "an object member (`shape`, `symmetry`, `grasp`, `rest` or `transition`)"
        }
        Rule::reserved => "a reserved word",
        Rule::recover => "an item",
        Rule::skip_block => "a block `{ ... }`",
        Rule::ident_char => "a letter, digit or `_`",
        Rule::plain_name => "a name",
        Rule::quoted_name => "a quoted name like `` `any text` ``",
        Rule::name => "a name",
        Rule::qualified => "a name (or `object.name`)",
        Rule::name_list => "a list of names like `w1, w2`",
        Rule::string => "a string in double quotes",
        Rule::string_inner => "the text of a string",
        Rule::label => "a label in double quotes",
        Rule::number => "a number",
        Rule::integer => "a whole number",
        Rule::unit => "a unit (`m`, `cm`, `mm`, `deg` or `rad`)",
        Rule::quantity => "a number like `0.5` or `90 deg`",
        Rule::vec3 => "three numbers like `(x, y, z)`",
        Rule::vec4 => "four numbers like `(w, x, y, z)`",
        Rule::pose => "a pose like `at (x, y, z)`",
        Rule::rotation => "a rotation like `rpy (r, p, y)` or `quat (w, x, y, z)`",
        Rule::rpy => "a rotation like `rpy (r, p, y)`",
        Rule::quat => "a rotation like `quat (w, x, y, z)`",
        Rule::aabb => "a box like `box center (x, y, z) size (dx, dy, dz)`",
        Rule::units_item => "`units m, deg`",
        Rule::weights_item => "`weights move 0.1, transition 1.0`",
        Rule::weight => "a weight like `move 0.1`",
        Rule::weight_kind => "`move` or `transition`",
        Rule::include_item => "`include \"file.cell\"`",
        Rule::package_item => "a package like `package my_robot at \"robots/my_robot\"`",
        Rule::package_name => "a ROS package name like `my_robot_description`",
        Rule::kw_package => "`package`",
        Rule::kw_srdf => "`srdf`",
        Rule::kw_group => "`group`",
        Rule::home_state => "an SRDF group state like `home ready`",
        Rule::srdf_name | Rule::plain_srdf_name => "a name from the SRDF like `arm` or `ready`",
        Rule::workspaces_from_reach => "`workspaces from reach`",
        Rule::workspace_item => "a workspace like `workspace w1 \"Left\"`",
        Rule::adjacent_item => "an adjacency like `adjacent w1 w2`",
        Rule::fixed_item => "a fixed end-effector like `fixed table reaches w1, w2`",
        Rule::movable_item => "a movable end-effector like `movable arm reaches w1`",
        Rule::reaches_clause => "`reaches` and a list of workspaces",
        Rule::hand_item => "a hand kind like `hand softhand`",
        Rule::support_item => "a support kind like `support tabletop`",
        Rule::robot_item => "a robot like `robot lwr4 urdf \"lwr4.urdf\" tip link_7`",
        Rule::arm_item => "an arm like `arm left = lwr4 at (x, y, z) with softhand`",
        Rule::surface_item => {
            "a surface like `surface table : tabletop box center (...) size (...)`"
        }
        Rule::reach_item => {
            "a reach like `reach left box center (...) size (...)` or `reach left auto`"
        }
        Rule::object_item => "an object like `object cylinder { ... }`",
        Rule::object_body => "the members of the object",
        Rule::shape_item => "a shape like `shape cylinder radius 0.04 height 0.2`",
        Rule::solid => "a shape like `box size (dx, dy, dz)`",
        Rule::solid_shape => "a shape (`box`, `cylinder`, `sphere` or `mesh`)",
        Rule::box_shape => "`box size (dx, dy, dz)`",
        Rule::cylinder_shape => "`cylinder radius R height H`",
        Rule::sphere_shape => "`sphere radius R`",
        Rule::mesh_shape => "`mesh \"file.stl\"`",
        Rule::symmetry_item => "a symmetry like `symmetry about z`",
        Rule::axis => "an axis (`x`, `y` or `z`)",
        Rule::grasp_item => "a grasp like `grasp top by softhand`",
        Rule::rest_item => "a resting pose like `rest standing on tabletop`",
        Rule::transition_item => "a transition like `transition g1 <-> g2, g3`",
        Rule::qualified_list => "a list of grasps like `g2, g3`",
        Rule::grasps_file => "a grasp-set file like `from \"grasps/pitcher.csv\"`",
        Rule::family_clause => {
            "a family clause like `every 30 deg about z` or `along z at (0, 5 cm)`"
        }
        Rule::every_clause => "a rotation step like `every 30 deg about z`",
        Rule::along_clause => "offsets along an axis like `along z at (-5 cm, 0, 5 cm)`",
        Rule::quantity_list => "a list of lengths like `(-5 cm, 0 cm, 5 cm)`",
        Rule::arrow => "`<->` or `->`",
        Rule::both_ways => "`<->`",
        Rule::one_way => "`->`",
        Rule::expect_item => "a requirement after `expect`",
        Rule::expect_reach => "a requirement like `cylinder: table in w1 -> table in w3`",
        Rule::placement => "a placement like `table in w1`",
        Rule::expect_cover => "a requirement like `w2 reached by at least 2`",
        Rule::reacher_kind => "`movable` or `fixed`",
        Rule::expect_isolated => "`no isolated states`",
        Rule::kw_cell => "`cell`",
        Rule::kw_library => "`library`",
        Rule::kw_units => "`units`",
        Rule::kw_weights => "`weights`",
        Rule::kw_include => "`include`",
        Rule::kw_workspaces => "`workspaces`",
        Rule::kw_workspace => "`workspace`",
        Rule::kw_from => "`from`",
        Rule::kw_reach => "`reach`",
        Rule::kw_reaches => "`reaches`",
        Rule::kw_reached => "`reached`",
        Rule::kw_adjacent => "`adjacent`",
        Rule::kw_fixed => "`fixed`",
        Rule::kw_movable => "`movable`",
        Rule::kw_hand => "`hand`",
        Rule::kw_support => "`support`",
        Rule::kw_robot => "`robot`",
        Rule::kw_urdf => "`urdf`",
        Rule::kw_base => "`base`",
        Rule::kw_tip => "`tip`",
        Rule::kw_arm => "`arm`",
        Rule::kw_with => "`with`",
        Rule::kw_home => "`home`",
        Rule::kw_auto => "`auto`",
        Rule::kw_allow => "`allow`",
        Rule::kw_request => "`request`",
        Rule::kw_obstacle => "`obstacle`",
        Rule::obstacle_item => {
            "an obstacle like `obstacle shelf box center (x, y, z) size (dx, dy, dz)`"
        }
        Rule::kw_to => "`to`",
        Rule::request_item => {
            "a request like `request r1: cylinder from table in w1 to table in w3`"
        }
        Rule::request_placement => "a placement like `table in w1` or `table at (x, y, z)`",
        Rule::kw_contact => "`contact`",
        Rule::allow_item => "an allowed contact like `allow contact left.lwr_link_7 table`",
        Rule::home_clause => "a home configuration like `home (joint_2 30 deg, joint_4 -60 deg)`",
        Rule::joint_value => "a joint and its value like `joint_2 30 deg`",
        Rule::kw_surface => "`surface`",
        Rule::kw_box => "`box`",
        Rule::kw_center => "`center`",
        Rule::kw_size => "`size`",
        Rule::kw_height => "`height`",
        Rule::kw_object => "`object`",
        Rule::kw_shape => "`shape`",
        Rule::kw_cylinder => "`cylinder`",
        Rule::kw_sphere => "`sphere`",
        Rule::kw_mesh => "`mesh`",
        Rule::kw_radius => "`radius`",
        Rule::kw_symmetry => "`symmetry`",
        Rule::kw_about => "`about`",
        Rule::kw_order => "`order`",
        Rule::kw_grasp => "`grasp`",
        Rule::kw_rest => "`rest`",
        Rule::kw_by => "`by`",
        Rule::kw_on => "`on`",
        Rule::kw_at => "`at`",
        Rule::kw_rpy => "`rpy`",
        Rule::kw_quat => "`quat`",
        Rule::kw_transition => "`transition`",
        Rule::kw_every => "`every`",
        Rule::kw_along => "`along`",
        Rule::kw_matching => "`matching`",
        Rule::kw_move => "`move`",
        Rule::kw_expect => "`expect`",
        Rule::kw_in => "`in`",
        Rule::kw_least => "`least`",
        Rule::kw_no => "`no`",
        Rule::kw_isolated => "`isolated`",
        Rule::kw_states => "`states`",
        Rule::kw_for => "`for`",
        Rule::kw_world => "`world`",
        Rule::kw_limits => "`limits`",
        Rule::kw_velocity => "`velocity`",
        Rule::kw_acceleration => "`acceleration`",
        Rule::kw_jerk => "`jerk`",
        Rule::limits_item => {
            "joint limits like `limits lwr4 acceleration 4 rad/s2` or `limits panda from \"joint_limits.yaml\"`"
        }
        Rule::limits_file => "a joint limits file like `from \"config/joint_limits.yaml\"`",
        Rule::limit_value => "a limit like `velocity 1.5 rad/s` or `acceleration 4 rad/s2`",
        Rule::limit_kind => "`velocity`, `acceleration` or `jerk`",
        Rule::rate_unit => "a rate unit like `rad/s`, `deg/s2` or `m/s3`",
        Rule::rate => "a rate like `1.5 rad/s` or `4 rad/s2`",
        Rule::kw_task => "`task`",
        Rule::world_item => "a world like `world { cylinder: table in w1 }`",
        Rule::world_body | Rule::world_entry_probe | Rule::world_entry_line => {
            "a line of the world like `cylinder: table in w1`"
        }
        Rule::colon => "`:`",
        Rule::world_entry => "a line of the world like `cylinder: table in w1`",
        Rule::world_placement => {
            "a placement like `table in w1`, `table at (x, y, z)` or `left.top`"
        }
        Rule::task_item => "a task like `task clear { cylinder to table in w3 }`",
        Rule::task_body | Rule::task_step_probe | Rule::task_step_line => {
            "a step of the task like `cylinder to table in w3`"
        }
        Rule::task_step => "a step of the task like `cylinder to table in w3`",
    }
}

/// Turns a pest error on `text[offset..]` into a coded diagnostic for `text`.
pub(crate) fn syntax_error(
    file: FileId,
    text: &str,
    offset: usize,
    error: &Error<Rule>,
) -> Diagnostic {
    let at = offset
        + match error.location {
            InputLocation::Pos(p) => p,
            InputLocation::Span((s, _)) => s,
        };
    let at = crate::span::floor_char_boundary(text, at);
    let found = found_at(text, at);
    let expected = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            let literals: Vec<String> = error
                .parse_attempts()
                .map(|attempts| {
                    attempts
                        .expected_tokens()
                        .into_iter()
                        .filter_map(|token| {
                            // Only punctuation: keywords already come as rules.
                            let token = token.to_string();
                            STRUCTURAL
                                .contains(&token.as_str())
                                .then(|| format!("`{token}`"))
                        })
                        .collect()
                })
                .unwrap_or_default();
            describe_expected(positives, &literals)
        }
        ErrorVariant::CustomError { message } => message.clone(),
    };
    let (span, found_label) = match &found {
        Some(token) => (
            Span::new(at, at + token.len()),
            format!("found `{}`", token.escape_debug()),
        ),
        None => (Span::new(at, at), "found the end of the file".to_string()),
    };
    let keywords = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => expected_keywords(positives),
        ErrorVariant::CustomError { .. } => Vec::new(),
    };
    let suggestion = found.and_then(|word| did_you_mean(word, keywords.iter().copied()));
    let reserved = found.filter(|word| is_reserved(word) && expected.contains("a name"));
    let help = match (reserved, suggestion) {
        (Some(word), _) => {
            format!("`{word}` is a reserved word: write `` `{word}` `` to use it as a name")
        }
        (None, Some(keyword)) => format!("did you mean `{keyword}`?"),
        (None, None) => format!("write {expected} here"),
    };
    Diagnostic::error(codes::SYNTAX, format!("expected {expected}"))
        .primary(file, span, found_label)
        .help(help)
}

/// A recovered region that parses fine on its own (should not happen: kept so that no
/// input is ever silently dropped).
pub(crate) fn unexpected_text(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(codes::SYNTAX, "unexpected text")
        .primary(file, span, "not understood here")
        .help("remove this text or move it inside the block it belongs to")
}

/// A syntax tree that does not have the shape the grammar promises. Reported rather
/// than panicking, so bad input can never crash the checker.
pub(crate) fn internal(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(codes::SYNTAX, "this text could not be read")
        .primary(file, span, "here")
        .help("simplify this item; if it looks right, report it as a cellc bug")
}

pub(crate) fn too_deep(file: FileId, span: Span, limit: usize) -> Diagnostic {
    Diagnostic::error(
        codes::TOO_DEEP,
        format!("blocks are nested more than {limit} deep"),
    )
    .primary(file, span, "this `{` is too deep")
    .help("close the blocks that are open; cells nest at most two levels (`cell` and `object`)")
}

pub(crate) fn control_character(file: FileId, span: Span, run: &str) -> Diagnostic {
    let shown: Vec<String> = run
        .chars()
        .take(8)
        .map(|c| format!("U+{:04X}", u32::from(c)))
        .collect();
    let more = if run.chars().count() > 8 { ", ..." } else { "" };
    Diagnostic::error(
        codes::CONTROL_CHARACTER,
        format!("control character in the text ({}{more})", shown.join(", ")),
    )
    .primary(file, span, "not allowed in a cell file")
    .help("remove it: a cell file holds printable text, tabs and line breaks only (inside a string, write `\\n` or `\\t`)")
}

pub(crate) fn integer_too_large(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(codes::INTEGER_TOO_LARGE, "this whole number is too large")
        .primary(file, span, "larger than 4294967295")
        .help("use a smaller number")
}

/// The keywords pest was ready to accept, for "did you mean".
fn expected_keywords(positives: &[Rule]) -> Vec<&'static str> {
    let mut keywords = Vec::new();
    for rule in positives {
        match rule {
            Rule::item_probe | Rule::item_line | Rule::item | Rule::recover => {
                keywords.extend(ITEM_KEYWORDS.iter().map(|k| k.word))
            }
            Rule::member_probe | Rule::member_line | Rule::object_member => {
                keywords.extend(MEMBER_KEYWORDS.iter().map(|k| k.word))
            }
            other => keywords.push(keyword_text(*other)),
        }
    }
    keywords.retain(|k| !k.is_empty());
    keywords
}

/// The word a `kw_*` rule matches (empty for other rules).
fn keyword_text(rule: Rule) -> &'static str {
    let phrase = phrase(rule);
    match format!("{rule:?}").strip_prefix("kw_") {
        Some(_) => phrase.trim_matches('`'),
        None => "",
    }
}

/// True when `rule` matches one of `keywords`.
fn starts(keywords: &[Keyword], rule: &Rule) -> bool {
    keywords.iter().any(|k| k.rule == *rule)
}

fn describe_expected(positives: &[Rule], literals: &[String]) -> String {
    let mut phrases: BTreeSet<&str> = BTreeSet::new();
    let n_items = positives
        .iter()
        .filter(|r| starts(ITEM_KEYWORDS, r))
        .count();
    let n_members = positives
        .iter()
        .filter(|r| starts(MEMBER_KEYWORDS, r))
        .count();
    let mut extra: Vec<String> = Vec::new();
    if n_items >= 3 {
        extra.push("an item (`workspace`, `fixed`, `movable`, `object`, `expect`, ...)".into());
    }
    if n_members >= 3 {
        extra
            .push("an object member (`shape`, `symmetry`, `grasp`, `rest` or `transition`)".into());
    }
    for rule in positives {
        if (n_items >= 3 && starts(ITEM_KEYWORDS, rule))
            || (n_members >= 3 && starts(MEMBER_KEYWORDS, rule))
        {
            continue;
        }
        if matches!(rule, Rule::recover | Rule::WHITESPACE | Rule::COMMENT) {
            continue;
        }
        phrases.insert(phrase(*rule));
    }
    let mut all: Vec<String> = extra;
    all.extend(phrases.into_iter().map(str::to_string));
    for literal in literals {
        if !all.iter().any(|p| p.contains(literal.as_str())) {
            all.push(literal.clone());
        }
    }
    match all.len() {
        0 => "something else".to_string(),
        1 => all.remove(0),
        _ => {
            let last = all.pop().unwrap_or_default();
            format!("{} or {}", all.join(", "), last)
        }
    }
}

/// The token at `at`: a word, a number, or one character; `None` at the end of the file.
fn found_at(text: &str, at: usize) -> Option<&str> {
    let rest = &text[at..];
    let first = rest.chars().next()?;
    if first.is_alphanumeric() || first == '_' {
        let end = rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.'))
            .unwrap_or(rest.len());
        Some(&rest[..end])
    } else {
        Some(&rest[..first.len_utf8()])
    }
}
