//! Reading an SRDF: one streaming pass of quick-xml over the text, keeping the elements
//! cellc uses and the line of each.

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

use super::{DisabledPair, Group, GroupState, Srdf, SrdfError};

/// Line numbers of byte offsets that only grow, counted incrementally (linear in all).
struct Lines<'a> {
    text: &'a str,
    offset: usize,
    line: usize,
}

impl Lines<'_> {
    fn at(&mut self, offset: u64) -> usize {
        let offset = usize::try_from(offset)
            .unwrap_or(self.text.len())
            .min(self.text.len());
        if offset > self.offset {
            let bytes = self.text.as_bytes();
            self.line += bytes[self.offset..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            self.offset = offset;
        }
        self.line
    }
}

/// The attribute `name` of an element, unescaped; `None` when absent or undecodable.
fn attribute(element: &BytesStart<'_>, name: &[u8], reader: &Reader<&[u8]>) -> Option<String> {
    element
        .attributes()
        .flatten()
        .find(|a| a.key.as_ref() == name)
        .and_then(|a| a.decode_and_unescape_value(reader.decoder()).ok())
        .map(|v| v.into_owned())
}

impl Srdf {
    /// Reads an SRDF text.
    pub fn parse(text: &str) -> Result<Srdf, SrdfError> {
        let mut reader = Reader::from_reader(text.as_bytes());
        let mut lines = Lines {
            text,
            offset: 0,
            line: 1,
        };
        let mut srdf = Srdf::default();
        // Open elements, outermost first (local names; members are known by their parent).
        let mut open: Vec<Vec<u8>> = Vec::new();
        let mut seen_root = false;
        loop {
            let start = reader.buffer_position();
            let event = reader.read_event().map_err(|_| SrdfError::NotXml {
                line: lines.at(reader.error_position()),
            })?;
            let (element, empty) = match event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    open.pop();
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let line = lines.at(start);
            let name = element.local_name().as_ref().to_vec();
            if open.is_empty() {
                if seen_root || name != b"robot" {
                    return Err(SrdfError::NotSrdf);
                }
                seen_root = true;
                srdf.name = attribute(&element, b"name", &reader).unwrap_or_default();
            } else {
                let parent = open.last().map(Vec::as_slice);
                srdf.element(&name, parent, open.len(), &element, &reader, line)?;
            }
            if !empty {
                open.push(name);
            }
        }
        if !seen_root {
            return Err(SrdfError::NotSrdf);
        }
        Ok(srdf)
    }

    /// One element at `depth` (1 = a child of `<robot>`) inside `parent`.
    fn element(
        &mut self,
        name: &[u8],
        parent: Option<&[u8]>,
        depth: usize,
        element: &BytesStart<'_>,
        reader: &Reader<&[u8]>,
        line: usize,
    ) -> Result<(), SrdfError> {
        let need = |element_name: &'static str, attribute_name: &'static str| {
            attribute(element, attribute_name.as_bytes(), reader).ok_or(
                SrdfError::MissingAttribute {
                    element: element_name,
                    attribute: attribute_name,
                    line,
                },
            )
        };
        let in_group = depth == 2 && parent == Some(b"group".as_slice());
        let in_state = depth == 2 && parent == Some(b"group_state".as_slice());
        fn last_group<'s>(
            srdf: &'s mut Srdf,
            element: &'static str,
            line: usize,
        ) -> Result<&'s mut Group, SrdfError> {
            srdf.groups
                .last_mut()
                .ok_or(SrdfError::Misplaced { element, line })
        }
        match (depth, name) {
            (1, b"group") => self.groups.push(Group {
                name: need("group", "name")?,
                line,
                ..Group::default()
            }),
            (1, b"group_state") => self.group_states.push(GroupState {
                name: need("group_state", "name")?,
                group: need("group_state", "group")?,
                line,
                values: Vec::new(),
            }),
            (1, b"disable_collisions") => self.disabled_collisions.push(DisabledPair {
                link1: need("disable_collisions", "link1")?,
                link2: need("disable_collisions", "link2")?,
                line,
            }),
            (2, b"chain") if in_group => {
                let pair = (need("chain", "base_link")?, need("chain", "tip_link")?);
                last_group(self, "chain", line)?.chains.push(pair);
            }
            (2, b"joint") if in_group => {
                let joint = need("joint", "name")?;
                last_group(self, "joint", line)?.joints.push(joint);
            }
            (2, b"link") if in_group => {
                let link = need("link", "name")?;
                last_group(self, "link", line)?.links.push(link);
            }
            (2, b"group") if in_group => {
                let group = need("group", "name")?;
                last_group(self, "group", line)?.subgroups.push(group);
            }
            (2, b"joint") if in_state => {
                let joint = need("joint", "name")?;
                let value = need("joint", "value")?;
                let value = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or(SrdfError::BadValue {
                        joint: joint.clone(),
                        line,
                    })?;
                let state = self.group_states.last_mut().ok_or(SrdfError::Misplaced {
                    element: "joint",
                    line,
                })?;
                state.values.push((joint, value));
            }
            (_, b"chain") => {
                return Err(SrdfError::Misplaced {
                    element: "chain",
                    line,
                })
            }
            // Everything else (end-effectors, virtual joints, ...) says nothing cellc uses.
            _ => {}
        }
        Ok(())
    }
}
