//! MoveIt's `joint_limits.yaml`: `joint_limits: { NAME: { has_velocity_limits, max_velocity,
//! has_acceleration_limits, max_acceleration, has_jerk_limits, max_jerk } }`, in SI units
//! (rad/s, m/s and their derivatives).
//!
//! The file is untrusted input: it is read within [`MAX_LIMITS_FILE_BYTES`] from the
//! event stream of `saphyr-parser` (no tree is built, so nesting costs no stack, and no
//! alias is ever expanded, so a "billion laughs" file costs its own size), and every
//! problem is a [`Problem`] with the byte range it is at. Other keys (MoveIt's
//! `default_velocity_scaling_factor`, a joint's `has_position_limits`) are skipped.
//! A `max_*` counts only where its `has_*_limits` is `true`, as MoveIt reads it.

use cellc_lang::ast::LimitKind;
use saphyr_parser::{Event, Parser, ScalarStyle, Span as YamlSpan};

/// The largest joint limits file read (1 MiB; MoveIt's are a few kilobytes).
pub const MAX_LIMITS_FILE_BYTES: u64 = 1 << 20;

/// The most joints one file may list (a humanoid has fewer than a hundred).
pub const MAX_LIMITS_FILE_JOINTS: usize = 4096;

/// One joint's entry.
#[derive(Clone, Debug, PartialEq)]
pub struct JointEntry {
    /// The joint's name.
    pub joint: String,
    /// Its byte range (the name).
    pub span: (usize, usize),
    /// The limits it sets (in SI), by kind, with the byte range of each value.
    pub limits: Vec<(LimitKind, f64, (usize, usize))>,
}

/// What is wrong with a file, and where (byte range).
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// In words, lowercase.
    pub message: String,
    /// Where.
    pub span: (usize, usize),
}

/// A scalar or a collection read from the events, with its byte range.
enum Node {
    /// Text, plain (not quoted), the tag's suffix (`!degrees`), range.
    Scalar(String, bool, Option<String>, (usize, usize)),
    Collection((usize, usize)),
    Alias((usize, usize)),
}

struct Reader<'a> {
    text: &'a str,
    /// Byte offset of each char index (saphyr's markers count characters).
    offsets: Vec<usize>,
    parser: Parser<'a, saphyr_parser::StrInput<'a>>,
}

impl Reader<'_> {
    fn byte(&self, char_index: usize) -> usize {
        self.offsets
            .get(char_index)
            .copied()
            .unwrap_or(self.text.len())
    }

    fn range(&self, span: YamlSpan) -> (usize, usize) {
        (self.byte(span.start.index()), self.byte(span.end.index()))
    }

    fn next(&mut self) -> Result<(Event<'_>, (usize, usize)), Problem> {
        match self.parser.next_event() {
            Some(Ok((event, span))) => {
                let range = self.range(span);
                Ok((event, range))
            }
            Some(Err(error)) => {
                let at = self.byte(error.marker().index());
                Err(Problem {
                    message: format!("not YAML: {}", error.info()),
                    span: (at, at),
                })
            }
            None => Err(Problem {
                message: "the file ends early".to_string(),
                span: (self.text.len(), self.text.len()),
            }),
        }
    }

    /// The next node; a collection is skipped whole (counting its depth, not recursing).
    fn node(&mut self) -> Result<Option<Node>, Problem> {
        let (event, range) = self.next()?;
        Ok(Some(match event {
            Event::Scalar(value, style, _, tag) => Node::Scalar(
                value.to_string(),
                style == ScalarStyle::Plain,
                tag.map(|t| t.suffix.clone()),
                range,
            ),
            Event::Alias(_) => Node::Alias(range),
            Event::MappingStart(..) | Event::SequenceStart(..) => {
                self.skip_rest()?;
                Node::Collection(range)
            }
            Event::MappingEnd | Event::SequenceEnd | Event::DocumentEnd | Event::StreamEnd => {
                return Ok(None)
            }
            _ => return self.node(),
        }))
    }

    /// Skips to the end of the collection just opened.
    fn skip_rest(&mut self) -> Result<(), Problem> {
        let mut depth = 1usize;
        while depth > 0 {
            match self.next()?.0 {
                Event::MappingStart(..) | Event::SequenceStart(..) => depth += 1,
                Event::MappingEnd | Event::SequenceEnd => depth -= 1,
                Event::StreamEnd => break,
                _ => {}
            }
        }
        Ok(())
    }

    /// Waits for a mapping to open (after the stream and document starts).
    fn mapping_start(&mut self, what: &str) -> Result<Option<(usize, usize)>, Problem> {
        loop {
            let (event, range) = self.next()?;
            match event {
                Event::StreamStart | Event::DocumentStart(_) | Event::Nothing => continue,
                Event::MappingStart(..) => return Ok(Some(range)),
                Event::StreamEnd | Event::DocumentEnd => return Ok(None),
                _ => {
                    return Err(Problem {
                        message: format!("{what} is not a mapping of names to values"),
                        span: range,
                    })
                }
            }
        }
    }
}

/// Reads the joints' limits of a `joint_limits.yaml` text.
pub fn parse(text: &str) -> Result<Vec<JointEntry>, Problem> {
    let mut offsets: Vec<usize> = text.char_indices().map(|(i, _)| i).collect();
    offsets.push(text.len());
    let mut reader = Reader {
        text,
        offsets,
        parser: Parser::new_from_str(text),
    };
    let missing = Problem {
        message: "no `joint_limits:` mapping".to_string(),
        span: (0, 0),
    };
    if reader.mapping_start("the file")?.is_none() {
        return Err(missing);
    }
    // The top level: find `joint_limits`, skip every other key.
    loop {
        let key = match reader.node()? {
            None => return Err(missing),
            Some(Node::Scalar(key, ..)) => key,
            Some(Node::Collection(span) | Node::Alias(span)) => {
                return Err(Problem {
                    message: "a key that is not a name".to_string(),
                    span,
                })
            }
        };
        if key == "joint_limits" {
            break;
        }
        reader.node()?;
    }
    match reader.next()? {
        (Event::MappingStart(..), _) => {}
        (_, span) => {
            return Err(Problem {
                message: "`joint_limits` is not a mapping of joint names".to_string(),
                span,
            })
        }
    }
    let mut joints = Vec::new();
    loop {
        let (joint, span) = match reader.node()? {
            None => break,
            Some(Node::Scalar(name, _, _, span)) => (name, span),
            Some(Node::Collection(span) | Node::Alias(span)) => {
                return Err(Problem {
                    message: "a joint name that is not a name".to_string(),
                    span,
                })
            }
        };
        if joints.len() == MAX_LIMITS_FILE_JOINTS {
            return Err(Problem {
                message: format!("more than {MAX_LIMITS_FILE_JOINTS} joints"),
                span,
            });
        }
        match reader.next()? {
            (Event::MappingStart(..), _) => {}
            (_, at) => {
                return Err(Problem {
                    message: format!("the limits of `{joint}` are not a mapping"),
                    span: at,
                })
            }
        }
        joints.push(joint_entry(&mut reader, joint, span)?);
    }
    Ok(joints)
}

/// The fields of one joint's mapping, just opened.
fn joint_entry(
    reader: &mut Reader<'_>,
    joint: String,
    span: (usize, usize),
) -> Result<JointEntry, Problem> {
    let mut has: [Option<(bool, (usize, usize))>; 3] = [None; 3];
    let mut max: [Option<(f64, (usize, usize))>; 3] = [None; 3];
    loop {
        let key = match reader.node()? {
            None => break,
            Some(Node::Scalar(key, ..)) => key,
            Some(Node::Collection(at) | Node::Alias(at)) => {
                return Err(Problem {
                    message: format!("a key of `{joint}` that is not a name"),
                    span: at,
                })
            }
        };
        let field = LimitKind::ALL.iter().position(|k| {
            key == format!("has_{}_limits", k.as_str()) || key == format!("max_{}", k.as_str())
        });
        let value = reader.node()?;
        let Some(i) = field else {
            continue;
        };
        let (text, plain, tag, at) = match value {
            Some(Node::Scalar(text, plain, tag, at)) => (text, plain, tag, at),
            Some(Node::Collection(at) | Node::Alias(at)) => {
                return Err(Problem {
                    message: format!("`{key}` of `{joint}` is not a single value"),
                    span: at,
                })
            }
            None => {
                return Err(Problem {
                    message: format!("`{key}` of `{joint}` has no value"),
                    span,
                })
            }
        };
        if key.starts_with("has_") {
            let flag = match (plain, text.as_str()) {
                (true, "true" | "True" | "TRUE") => true,
                (true, "false" | "False" | "FALSE") => false,
                _ => {
                    return Err(Problem {
                        message: format!("`{key}` of `{joint}` is `{text}`, not `true` or `false`"),
                        span: at,
                    })
                }
            };
            has[i] = Some((flag, at));
        } else {
            // ur_description writes `max_velocity: !degrees 180.0`, a tag its launch files
            // turn into radians; any other tag is a meaning cellc does not know.
            let scale = match tag.as_deref() {
                None => Some(1.0),
                Some("degrees") => Some(std::f64::consts::PI / 180.0),
                Some(_) => None,
            };
            let number = plain
                .then(|| text.parse::<f64>().ok())
                .flatten()
                .zip(scale)
                .map(|(v, k)| v * k);
            match number {
                Some(v) if v.is_finite() && v > 0.0 => max[i] = Some((v, at)),
                // MoveIt's generated files write `max_acceleration: 0` beside
                // `has_acceleration_limits: false`: a zero counts only where it is used.
                Some(v) if v == 0.0 => max[i] = Some((v, at)),
                _ => {
                    return Err(Problem {
                        message: format!(
                            "`{key}` of `{joint}` is `{text}`, not a positive finite number"
                        ),
                        span: at,
                    })
                }
            }
        }
    }
    let mut limits = Vec::new();
    for (i, kind) in LimitKind::ALL.iter().enumerate() {
        let Some((true, has_at)) = has[i] else {
            continue;
        };
        match max[i] {
            Some((v, at)) if v > 0.0 => limits.push((*kind, v, at)),
            Some((_, at)) => {
                return Err(Problem {
                    message: format!(
                        "`max_{}` of `{joint}` is zero, and `has_{}_limits` is true",
                        kind.as_str(),
                        kind.as_str()
                    ),
                    span: at,
                })
            }
            None => {
                return Err(Problem {
                    message: format!(
                        "`has_{}_limits` of `{joint}` is true, but it has no `max_{}`",
                        kind.as_str(),
                        kind.as_str()
                    ),
                    span: has_at,
                })
            }
        }
    }
    Ok(JointEntry {
        joint,
        span,
        limits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moveit_files_give_the_limits_they_enable() {
        let text = "# generated\ndefault_velocity_scaling_factor: 0.1\njoint_limits:\n  a1:\n    has_velocity_limits: true\n    max_velocity: 1.5\n    has_acceleration_limits: true\n    max_acceleration: 3\n    has_jerk_limits: false\n    max_jerk: 0\n  a2: {has_acceleration_limits: false, max_acceleration: 0, has_position_limits: true, max_position: 2.9}\n";
        let joints = parse(text).unwrap();
        assert_eq!(joints.len(), 2);
        assert_eq!(joints[0].joint, "a1");
        let kinds: Vec<(LimitKind, f64)> = joints[0].limits.iter().map(|l| (l.0, l.1)).collect();
        assert_eq!(
            kinds,
            [(LimitKind::Velocity, 1.5), (LimitKind::Acceleration, 3.0)]
        );
        let (start, end) = joints[0].limits[1].2;
        assert_eq!(&text[start..end], "3");
        assert!(joints[1].limits.is_empty());
    }

    #[test]
    fn the_degrees_tag_of_ur_description_is_radians() {
        let joints = parse(
            "joint_limits:\n  j:\n    max_position: !degrees 360.0\n    has_velocity_limits: true\n    max_velocity: !degrees  180.0\n",
        )
        .unwrap();
        assert!((joints[0].limits[0].1 - std::f64::consts::PI).abs() < 1e-12);
        let problem = parse(
            "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: !grads 200\n",
        )
        .unwrap_err();
        assert!(problem.message.contains("not a positive finite number"));
    }

    #[test]
    fn a_max_without_its_flag_is_not_a_limit() {
        let joints = parse("joint_limits:\n  j:\n    max_acceleration: 3\n").unwrap();
        assert!(joints[0].limits.is_empty());
    }

    #[test]
    fn malformed_files_are_problems_at_their_place() {
        for (text, at) in [
            ("joint_limits:\n  j:\n    has_jerk_limits: true\n", "true"),
            (
                "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: fast\n",
                "fast",
            ),
            (
                "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: .inf\n",
                ".inf",
            ),
            (
                "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: -1\n",
                "-1",
            ),
            ("joint_limits:\n  j:\n    has_velocity_limits: yes\n", "yes"),
            (
                "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: \"2\"\n",
                "\"2\"",
            ),
            ("joint_limits: [1, 2]\n", "["),
        ] {
            let problem = parse(text).expect_err(text);
            let (start, end) = problem.span;
            assert!(
                text[start..end.max(start)].starts_with(at) || text[start..].starts_with(at),
                "{text:?}: {problem:?}"
            );
        }
        for text in ["", "other: 1\n", "- a\n", "joint_limits:\n  j: {\n"] {
            assert!(parse(text).is_err(), "{text:?}");
        }
    }

    #[test]
    fn aliases_are_never_expanded() {
        // Each level doubles; expanded, the last would be 2^30 scalars.
        let mut text = String::from("a0: &a0 [x, x]\n");
        for i in 1..30 {
            text.push_str(&format!("a{i}: &a{i} [*a{}, *a{}]\n", i - 1, i - 1));
        }
        text.push_str(
            "joint_limits:\n  j:\n    has_velocity_limits: true\n    max_velocity: *a29\n",
        );
        let problem = parse(&text).unwrap_err();
        assert!(problem.message.contains("single value"), "{problem:?}");
    }

    #[test]
    fn deep_nesting_is_a_problem_not_a_crash() {
        let text = format!(
            "x: {}{}\njoint_limits: {{}}\n",
            "[".repeat(50_000),
            "]".repeat(50_000)
        );
        let problem = parse(&text).unwrap_err();
        assert!(problem.message.starts_with("not YAML"), "{problem:?}");
        let shallow = format!(
            "x: {}{}\njoint_limits: {{}}\n",
            "[".repeat(20),
            "]".repeat(20)
        );
        assert_eq!(parse(&shallow), Ok(Vec::new()));
    }
}
