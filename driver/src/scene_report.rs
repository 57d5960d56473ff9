//! What the runtime's preflight found ([`cellc_runtime::verify::preflight`]) as
//! diagnostics: a link that touches a fixed body whatever its arm does (E0421, with the
//! `allow contact` line that makes the fix), a home that collides (E0420), a grasp away
//! from its hand or inside it (W0010). `cellc build` and `cellc plan` on a cell report
//! them after loading the scene and, for the errors, verify nothing: every check would
//! fail for the same reason, whatever its arc.

use cellc_lang::{Diagnostic, FileId, SourceMap, Span};
use cellc_runtime::explain::BodyName;
use cellc_runtime::verify::preflight::{
    GraspOffset, HomeCollision, Offset, PermanentContact, Preflight, GRASP_FAR,
};
use cellc_schema::Artifact;

/// Codes of the preflight (the registry's `cellc_lang::codes::scene`).
pub use cellc_lang::codes::scene as codes;

/// Home collisions listed in notes beside the first, at most (a folded arm can touch
/// itself in many places; the first few say what to change).
const MAX_HOME_PAIRS: usize = 4;

/// Every finding of `preflight` as a diagnostic, errors first.
pub fn diagnostics(
    artifact: &Artifact,
    preflight: &Preflight,
    sources: &SourceMap,
) -> Vec<Diagnostic> {
    let mut out: Vec<Diagnostic> = preflight
        .contacts
        .iter()
        .map(|c| permanent_contact(artifact, c, sources))
        .collect();
    // One diagnostic per arm (and other arm) whose home collides, its first pair in the
    // message, the others in notes.
    let mut groups: Vec<Vec<&HomeCollision>> = Vec::new();
    for home in &preflight.homes {
        let key = (home.end_effector, home.other);
        match groups
            .iter_mut()
            .find(|g| (g[0].end_effector, g[0].other) == key)
        {
            Some(group) => group.push(home),
            None => groups.push(vec![home]),
        }
    }
    for group in groups {
        let mut d = home_collides(artifact, group[0], sources);
        for also in group.iter().skip(1).take(MAX_HOME_PAIRS) {
            let (a, b) = (written(artifact, &also.a), written(artifact, &also.b));
            d = d.note(format!("also `{a}` and `{b}`"));
        }
        if group.len() > MAX_HOME_PAIRS + 1 {
            d = d.note(format!(
                "and {} more pairs",
                group.len() - MAX_HOME_PAIRS - 1
            ));
        }
        out.push(d);
    }
    out.extend(preflight.grasps.iter().map(|g| grasp_off_hand(artifact, g)));
    out
}

/// A collision body as `allow contact` writes it (`left.lwr_base_link`, `torso`).
fn written(artifact: &Artifact, body: &str) -> String {
    BodyName::of(artifact, body).map_or_else(
        || body.replace('/', "."),
        |b| crate::fixes::written_body(&b),
    )
}

fn place(artifact: &Artifact, span: u32) -> Option<(FileId, Span)> {
    let s = artifact.spans.get(span as usize)?;
    Some((FileId(s.file), Span::new(s.start as usize, s.end as usize)))
}

fn end_effector_place(artifact: &Artifact, e: u32) -> Option<(FileId, Span)> {
    place(artifact, artifact.end_effectors.get(e as usize)?.span)
}

fn name(artifact: &Artifact, e: u32) -> &str {
    artifact
        .end_effectors
        .get(e as usize)
        .map_or("?", |x| x.name.as_str())
}

fn permanent_contact(artifact: &Artifact, c: &PermanentContact, sources: &SourceMap) -> Diagnostic {
    let arm = name(artifact, c.end_effector.0);
    let (link, fixed) = (written(artifact, &c.link), written(artifact, &c.fixed));
    let line = format!("allow contact {link} {fixed}");
    let mut d = Diagnostic::error(
        codes::PERMANENT_CONTACT,
        format!("`{link}` touches `{fixed}` whatever `{arm}` does"),
    );
    if let Some((file, span)) = end_effector_place(artifact, c.end_effector.0) {
        d = d.primary(
            file,
            span,
            format!(
                "`{link}` touches `{fixed}` in all {} configurations tried, its home among them",
                c.tried
            ),
        );
    }
    if let Some(e) = artifact.end_effectors.iter().find(|e| e.name == c.fixed) {
        if let Some((file, span)) = place(artifact, e.span) {
            d = d.secondary(file, span, format!("`{fixed}` declared here"));
        }
    }
    d = d
        .help(format!(
            "declare `{line}` if they may touch (an arm's base stands on its table or torso), or move them apart"
        ))
        .note("verification would prune every arc of the arm for this contact, so no arc was checked");
    if let Some(text) = crate::fixes::allow_contact(artifact, &line, sources)
        .and_then(|edit| crate::explain_report::suggestions::fix_text(&edit, sources))
    {
        d = d.note(format!("to fix, {text}"));
    }
    d
}

fn home_collides(artifact: &Artifact, h: &HomeCollision, sources: &SourceMap) -> Diagnostic {
    let arm = name(artifact, h.end_effector.0);
    let (a, b) = (written(artifact, &h.a), written(artifact, &h.b));
    let place = end_effector_place(artifact, h.end_effector.0);
    // The artifact keeps the home, not whether it was written: the arm's line says.
    let declared = place.is_some_and(|(file, span)| {
        sources
            .iter()
            .find(|(id, _)| *id == file)
            .and_then(|(_, f)| f.text.get(span.start as usize..span.end as usize))
            .is_some_and(|text| text.contains(" home "))
    });
    let which = if declared {
        "its home"
    } else {
        "its default home (every joint at 0, or the limit nearest to it)"
    };
    let mut d = Diagnostic::error(
        codes::HOME_COLLIDES,
        format!("`{arm}` collides at its home: `{a}` touches `{b}`"),
    );
    if let Some((file, span)) = place {
        d = d.primary(file, span, format!("at {which}, `{a}` and `{b}` collide"));
    }
    if let Some(other) = h.other {
        if let Some((file, span)) = end_effector_place(artifact, other.0) {
            d = d.secondary(
                file,
                span,
                format!("`{}` at its home", name(artifact, other.0)),
            );
        }
    }
    let help = match h.other {
        Some(other) => format!(
            "give `{arm}` or `{}` a home where they stand clear of each other (`home (JOINT VALUE, ...)`)",
            name(artifact, other.0)
        ),
        None if h.b.contains('/') => format!(
            "give `{arm}` a home where it stands clear of itself (`home (JOINT VALUE, ...)`)"
        ),
        None => format!(
            "give `{arm}` a home clear of `{b}` (`home (JOINT VALUE, ...)`), or declare `allow contact {a} {b}` if they may touch"
        ),
    };
    d.help(help).note(
        "every arm that is not moving stands at its home while another works, so verification would prune arcs for this collision whatever they are",
    )
}

fn grasp_off_hand(artifact: &Artifact, g: &GraspOffset) -> Diagnostic {
    let object = artifact.objects.get(g.object.index());
    let grasp = object.and_then(|o| o.grasps.get(g.grasp.index()));
    let object_name = object.map_or("?", |o| o.name.as_str());
    let grasp_name = grasp.map_or("?", |x| x.name.as_str());
    let kind = artifact
        .holder_kinds
        .get(g.kind as usize)
        .map_or("?", |k| k.name.as_str());
    let (message, label) = match g.offset {
        Offset::Far { distance } => (
            format!(
                "grasp `{grasp_name}` holds `{object_name}` {} from every solid of `{kind}`",
                centimetres(distance)
            ),
            format!(
                "the object is {} from the hand (more than {} is no grasp)",
                centimetres(distance),
                centimetres(GRASP_FAR)
            ),
        ),
        Offset::Deep { depth, solid } => (
            format!(
                "grasp `{grasp_name}` puts the centre of `{object_name}` {} deep inside solid {} of `{kind}`",
                centimetres(depth),
                solid + 1
            ),
            format!("the object's centre is inside the hand, {} from its surface", centimetres(depth)),
        ),
    };
    let mut d = Diagnostic::warning(codes::GRASP_OFF_HAND, message);
    if let Some((file, span)) = grasp.and_then(|x| place(artifact, x.span)) {
        d = d.primary(file, span, label);
    }
    d.help(format!(
        "a grasp is the object's pose in the hand frame, the robot's tip link: check it against the solids of `{kind}` (a tip moved without moving the grasps leaves them off)"
    ))
}

/// "12 cm", "4.5 cm", "3 mm".
fn centimetres(x: f64) -> String {
    if x < 0.01 {
        format!("{:.0} mm", x * 1000.0)
    } else {
        let text = format!("{:.1}", x * 100.0);
        format!("{} cm", text.trim_end_matches('0').trim_end_matches('.'))
    }
}
