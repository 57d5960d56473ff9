//! Names: database names as cell names, made unique (see the module above for the rules),
//! and the quoting of names, strings and comments in the cell text.

use std::collections::{HashMap, HashSet};

use crate::import::{Database, GraspRow};

/// A database name as a cell name: backticks and control characters (which a quoted name
/// cannot hold) are replaced; NULL or empty gives the fallback.
fn base_name(name: Option<&str>, fallback: String) -> String {
    let cleaned: String = name
        .unwrap_or_default()
        .chars()
        .map(|c| match c {
            '`' => '\'',
            c if c.is_control() => '_',
            c => c,
        })
        .collect();
    if cleaned.is_empty() {
        fallback
    } else {
        cleaned
    }
}

/// Makes names unique: a base name that only one entry has is kept; entries sharing a base
/// get `base_suffix`. Generated names avoid every base name and each other.
fn unique(entries: &[(String, String)]) -> Vec<String> {
    let mut count: HashMap<&str, usize> = HashMap::new();
    for (base, _) in entries {
        *count.entry(base.as_str()).or_default() += 1;
    }
    let mut taken: HashSet<String> = entries.iter().map(|(b, _)| b.clone()).collect();
    entries
        .iter()
        .map(|(base, suffix)| {
            if count[base.as_str()] == 1 {
                return base.clone();
            }
            let first = format!("{base}_{suffix}");
            let mut candidate = first.clone();
            let mut n = 2;
            while taken.contains(&candidate) {
                candidate = format!("{first}_{n}");
                n += 1;
            }
            taken.insert(candidate.clone());
            candidate
        })
        .collect()
}

/// A string literal, escaped as the formatter writes it.
pub(super) fn string(text: &str) -> String {
    cellc_lang::format::string_literal(text)
}

/// Text for a comment: one line, whatever the database holds.
pub(super) fn comment_text(text: &str) -> String {
    string(text)
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// The names every row gets in the cell.
pub(super) struct Names {
    pub(super) cell: String,
    pub(super) workspaces: HashMap<i64, String>,
    pub(super) end_effectors: HashMap<i64, String>,
    pub(super) objects: HashMap<i64, String>,
    pub(super) grasps: HashMap<i64, String>,
}

pub(super) fn names(db: &Database, file_name: &str) -> Names {
    let stem = file_name
        .rsplit_once('.')
        .map_or(file_name, |(stem, _)| stem);
    let cell = base_name(Some(stem), "imported".to_string());

    let mut entries: Vec<(String, String)> = Vec::new();
    for w in &db.workspaces {
        entries.push((
            base_name(w.name.as_deref(), format!("workspace_{}", w.id)),
            format!("ws{}", w.id),
        ));
    }
    for e in &db.end_effectors {
        entries.push((
            base_name(e.name.as_deref(), format!("end_effector_{}", e.id)),
            format!("ee{}", e.id),
        ));
    }
    for o in &db.objects {
        entries.push((
            base_name(o.name.as_deref(), format!("object_{}", o.id)),
            format!("obj{}", o.id),
        ));
    }
    let mut unique_names = unique(&entries).into_iter();
    let mut take = |ids: Vec<i64>| -> HashMap<i64, String> {
        ids.into_iter().zip(unique_names.by_ref()).collect()
    };
    let workspaces = take(db.workspaces.iter().map(|r| r.id).collect());
    let end_effectors = take(db.end_effectors.iter().map(|r| r.id).collect());
    let objects = take(db.objects.iter().map(|r| r.id).collect());

    let mut grasps = HashMap::new();
    for o in &db.objects {
        let of_object: Vec<&GraspRow> = db.grasps.iter().filter(|g| g.object == o.id).collect();
        let bases: Vec<String> = of_object
            .iter()
            .map(|g| base_name(g.name.as_deref(), format!("grasp_{}", g.id)))
            .collect();
        let mut per_holder: HashMap<(&str, i64), usize> = HashMap::new();
        for (g, base) in of_object.iter().zip(&bases) {
            *per_holder
                .entry((base.as_str(), g.end_effector))
                .or_default() += 1;
        }
        let entries: Vec<(String, String)> = of_object
            .iter()
            .zip(&bases)
            .map(|(g, base)| {
                let suffix = if per_holder[&(base.as_str(), g.end_effector)] == 1 {
                    end_effectors[&g.end_effector].clone()
                } else {
                    g.id.to_string()
                };
                (base.clone(), suffix)
            })
            .collect();
        for (g, unique_name) in of_object.iter().zip(unique(&entries)) {
            grasps.insert(g.id, unique_name);
        }
    }
    Names {
        cell,
        workspaces,
        end_effectors,
        objects,
        grasps,
    }
}
