//! Robot models: reads a URDF through the [`World`], checks that the named links exist
//! and that a chain of joints leads from the base to the tip.
//!
//! The compiler only validates and records the chain; kinematics live in the runtime,
//! which reads the URDF text carried in the artifact.

use std::collections::HashMap;

use cellc_lang::ast::RobotItem;
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{Diagnostic, FileId};

use crate::diagnostics;
use crate::model::{Joint, Origin, Robot};
use crate::world::{join, World};

/// Loads the URDF of a `robot` item, reporting every problem; `None` when the model is
/// unusable.
pub fn load_robot(
    world: &dyn World,
    declaring_path: &str,
    file: FileId,
    item: &RobotItem,
    origin: Origin,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Robot> {
    let path = join(declaring_path, &item.urdf.value);
    let text = match world.read(&path) {
        Ok(text) => text,
        Err(reason) => {
            diagnostics.push(diagnostics::urdf_unreadable(
                &path,
                &reason,
                file,
                item.urdf.span,
            ));
            return None;
        }
    };
    // The URDF reader is a third-party XML stack: guard against it panicking on hostile
    // input so that bad files can never take the checker down.
    let parsed = std::panic::catch_unwind(|| urdf_rs::read_from_string(&text));
    let model = match parsed {
        Ok(Ok(model)) => model,
        Ok(Err(error)) => {
            // The reader prefixes serde's own category ("custom: "), which means nothing
            // to a cell engineer.
            let reason = error.to_string();
            let reason = reason
                .strip_prefix("custom: ")
                .unwrap_or(&reason)
                .to_string();
            diagnostics.push(diagnostics::urdf_invalid(
                &path,
                &reason,
                file,
                item.urdf.span,
            ));
            return None;
        }
        Err(_) => {
            diagnostics.push(diagnostics::urdf_invalid(
                &path,
                "the reader failed on this file",
                file,
                item.urdf.span,
            ));
            return None;
        }
    };
    let links: Vec<&str> = model.links.iter().map(|l| l.name.as_str()).collect();
    // child link -> (joint index, parent link)
    let parent_of: HashMap<&str, (usize, &str)> = model
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| (j.child.link.as_str(), (i, j.parent.link.as_str())))
        .collect();
    let root = links.iter().copied().find(|l| !parent_of.contains_key(l));
    let mut ok = true;
    let mut check_link = |name: &cellc_lang::ast::Name| {
        if links.contains(&name.text.as_str()) {
            true
        } else {
            let suggestion = did_you_mean(&name.text, links.iter().copied());
            diagnostics.push(diagnostics::urdf_unknown_link(
                "link", &name.text, &path, file, name.span, suggestion,
            ));
            false
        }
    };
    let base = match &item.base {
        Some(base) => {
            ok &= check_link(base);
            base.text.clone()
        }
        None => root.unwrap_or_default().to_string(),
    };
    ok &= check_link(&item.tip);
    if !ok {
        return None;
    }
    // Walk from the tip up to the base.
    let mut chain = Vec::new();
    let mut link = item.tip.text.as_str();
    let mut steps = 0;
    while link != base {
        match parent_of.get(link) {
            Some(&(joint, parent)) if steps <= model.joints.len() => {
                chain.push(joint);
                link = parent;
                steps += 1;
            }
            _ => {
                diagnostics.push(diagnostics::urdf_no_chain(
                    &base,
                    &item.tip.text,
                    &path,
                    file,
                    item.span,
                ));
                return None;
            }
        }
    }
    chain.reverse();
    let chain_joints: Vec<Joint> = chain
        .into_iter()
        .filter_map(|j| {
            let joint = &model.joints[j];
            let (prismatic, lower, upper) = match joint.joint_type {
                urdf_rs::JointType::Revolute => (false, joint.limit.lower, joint.limit.upper),
                urdf_rs::JointType::Prismatic => (true, joint.limit.lower, joint.limit.upper),
                urdf_rs::JointType::Continuous => (false, f64::NEG_INFINITY, f64::INFINITY),
                _ => return None,
            };
            Some(Joint {
                name: joint.name.clone(),
                prismatic,
                lower,
                upper,
            })
        })
        .collect();
    if chain_joints.is_empty() {
        diagnostics.push(
            Diagnostic::error(
                diagnostics::codes::URDF_NO_CHAIN,
                format!("in `{path}`, no movable joint lies between `{base}` and `{}`", item.tip.text),
            )
            .primary(file, item.span, "this robot cannot move its tip")
            .help("pick a base and tip with at least one revolute, continuous or prismatic joint between them"),
        );
        return None;
    }
    Some(Robot {
        name: item.name.text.clone(),
        urdf_path: path,
        urdf_text: text,
        base_link: base,
        tip_link: item.tip.text.clone(),
        chain_joints,
        links: links.iter().map(|l| l.to_string()).collect(),
        origin,
    })
}
