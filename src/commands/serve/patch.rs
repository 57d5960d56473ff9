//! `PATCH /v1/world`: an incremental update of the world document (docs/world.md) without
//! sending the whole world, as a JSON Merge Patch (RFC 7396, `application/merge-patch+json`
//! or any other type) or a JSON Patch (RFC 6902, `application/json-patch+json`: a list of
//! operations). The patched document is then read and checked exactly like a
//! `PUT` body, and it confirms only the objects and arms it names.
//!
//! Both forms come from the `json-patch` crate. JSON Patch's `copy` is refused: it is the
//! one operation that can make a document larger than the request that asked for it
//! (copy a subtree onto itself a few thousand times), and a world document has no use
//! for it.

use axum::body::Body;
use axum::extract::State;
use axum::http::HeaderMap;
use axum::response::{IntoResponse, Response};
use cellc_schema::WorldDocument;
use cellc_store::{Confirms, Subjects};
use serde_json::Value;

use super::durable::Precondition;
use super::errors::{ApiError, Failure};
use super::routes::{document_error, store_world, Shared};
use super::{read_body, MAX_WORLD};
use cellc_lang::codes::serve as codes;

/// How often a patch without a precondition is applied again to a world that changed
/// while it was being checked, before the request gives up (S0004).
const MOST_ATTEMPTS: usize = 20;

/// Which form of patch the body is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    /// RFC 7396.
    Merge,
    /// RFC 6902.
    Operations,
}

/// `PATCH /v1/world`.
pub async fn patch_world(State(service): Shared, headers: HeaderMap, body: Body) -> Response {
    let precondition = match Precondition::from_headers(&headers) {
        Ok(p) => p,
        Err(e) => return e.into_response(),
    };
    let form = form(&headers);
    let bytes = match read_body(body, MAX_WORLD).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    super::routes::blocking(service, move |service, _| {
        let patch: Value = match serde_json::from_slice(&bytes) {
            Ok(v) => v,
            Err(e) => return bad_patch(&e.to_string()).into_response(),
        };
        // The document is patched as the world is now; the store's compare-and-set
        // (under `store_world`'s lock) refuses it if the world moves on meanwhile and a
        // precondition was given; without one, a world changed in between is patched
        // again from its new state.
        for _ in 0..MOST_ATTEMPTS {
            let now = service.snapshot();
            let cell = &service.loaded.cell;
            let before = cell.world_document(&now.world);
            let (patched, named) = match apply(&before, &patch, form) {
                Ok(p) => p,
                Err(e) => return e.into_response(),
            };
            let document = match WorldDocument::from_json(patched.as_bytes()) {
                Ok(d) => d,
                Err(e) => {
                    return ApiError::from_diagnostic(
                        Failure::BadBody,
                        &document_error(e),
                        service.loaded.sources(),
                    )
                    .into_response()
                }
            };
            // Pin the revision the patch was applied to, whatever the client gave.
            let pinned = if precondition.given() {
                precondition.clone()
            } else {
                Precondition::default().with_revision(Some(now.revision.0))
            };
            let answer = store_world(service, &pinned, &document, &Confirms::Only(named));
            let moved_on = answer.status() == axum::http::StatusCode::PRECONDITION_FAILED;
            if !moved_on || precondition.given() {
                return answer;
            }
        }
        ApiError::new(
            Failure::TimedOut,
            cellc_lang::codes::serve::TIMED_OUT,
            format!("the world changed {MOST_ATTEMPTS} times while the patch was applied"),
            "send the patch again, or a whole world with PUT /v1/world",
        )
        .into_response()
    })
    .await
}

/// The form the `Content-Type` names: JSON Patch for `application/json-patch+json`, a
/// merge patch for anything else (as the other endpoints read their bodies as JSON
/// whatever the type says, so that `curl -d` works).
fn form(headers: &HeaderMap) -> Form {
    let kind = headers
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .map(|v| {
            v.split(';')
                .next()
                .unwrap_or_default()
                .trim()
                .to_ascii_lowercase()
        });
    if kind.as_deref() == Some("application/json-patch+json") {
        Form::Operations
    } else {
        Form::Merge
    }
}

/// The patched document as JSON text, and the objects and arms the patch names.
fn apply(
    before: &WorldDocument,
    patch: &Value,
    form: Form,
) -> Result<(String, Subjects), ApiError> {
    let mut document = serde_json::to_value(before).map_err(|e| bad_patch(&e.to_string()))?;
    let all = |document: &Value, section: &str| -> Vec<String> {
        document[section]
            .as_object()
            .map(|m| m.keys().cloned().collect())
            .unwrap_or_default()
    };
    let mut named = Subjects::default();
    match form {
        Form::Merge => {
            if !patch.is_object() {
                return Err(bad_patch(
                    "a merge patch of the world is an object (`{\"objects\": {…}, \"arms\": {…}}`)",
                ));
            }
            for (section, set) in [("objects", &mut named.objects), ("arms", &mut named.arms)] {
                match patch.get(section) {
                    None => {}
                    Some(Value::Object(entries)) => set.extend(entries.keys().cloned()),
                    // Replacing or removing a whole section names all of it, before and after.
                    Some(replaced) => {
                        set.extend(all(&document, section));
                        if let Some(m) = replaced.as_object() {
                            set.extend(m.keys().cloned());
                        }
                    }
                }
            }
            json_patch::merge(&mut document, patch);
        }
        Form::Operations => {
            let operations: json_patch::Patch = serde_json::from_value(patch.clone())
                .map_err(|e| bad_patch(&format!("not a list of JSON Patch operations: {e}")))?;
            for op in &operations.0 {
                let mut paths = vec![op.path().to_string()];
                match op {
                    json_patch::PatchOperation::Copy(_) => {
                        return Err(bad_patch(
                            "`copy` is not taken: a world document has no use for it, and it can grow a document past any bound",
                        ))
                    }
                    json_patch::PatchOperation::Move(m) => paths.push(m.from.to_string()),
                    _ => {}
                }
                for path in paths {
                    let mut tokens = path.split('/').skip(1);
                    let section = tokens.next();
                    let name = tokens
                        .next()
                        .map(|t| t.replace("~1", "/").replace("~0", "~"));
                    let set = match section {
                        Some("objects") => &mut named.objects,
                        Some("arms") => &mut named.arms,
                        Some(_) => continue,
                        None => {
                            // The whole document: everything, before and after.
                            named.objects.extend(all(&document, "objects"));
                            named.arms.extend(all(&document, "arms"));
                            continue;
                        }
                    };
                    match name {
                        Some(n) => {
                            set.insert(n);
                        }
                        None => set.extend(all(&document, section.unwrap_or_default())),
                    }
                }
            }
            json_patch::patch(&mut document, &operations.0).map_err(|e| {
                bad_patch(&format!("the operations do not apply to the world: {e}"))
            })?;
            if let Some(section) = ["objects", "arms"]
                .into_iter()
                .find(|s| document.get(*s).is_some_and(|v| !v.is_object()))
            {
                return Err(bad_patch(&format!("`{section}` must stay an object")));
            }
        }
    }
    let text = serde_json::to_string(&document).map_err(|e| bad_patch(&e.to_string()))?;
    Ok((text, named))
}

/// S0001 for a patch that is not one.
fn bad_patch(detail: &str) -> ApiError {
    let d = cellc_lang::Diagnostic::error(codes::BAD_BODY, "the body is not a patch of the world")
        .note(crate::render::escape(detail).into_owned())
        .help("send a JSON Merge Patch (`{\"objects\": {\"ball\": {\"holder\": \"table\", \"at\": [0.5, 0.3, 1.0]}}}`) or JSON Patch operations; see docs/service.md");
    ApiError::from_diagnostic(Failure::BadBody, &d, &cellc_lang::SourceMap::new())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn document() -> WorldDocument {
        WorldDocument::from_json(
            br#"{"arms": {"left": {"j1": 0.1}, "right": {"j1": 0.2}},
                 "objects": {"ball": {"holder": "table", "at": [0.5, 0.3, 1.0]}, "box": "absent"}}"#,
        )
        .expect("a world document")
    }

    #[test]
    fn a_merge_patch_names_what_it_touches() {
        let (text, named) = apply(
            &document(),
            &json!({"objects": {"ball": null}, "arms": {"left": {"j1": 0.4}}}),
            Form::Merge,
        )
        .expect("applies");
        let patched: Value = serde_json::from_str(&text).unwrap();
        assert!(patched["objects"].get("ball").is_none());
        assert_eq!(patched["arms"]["left"]["j1"], json!(0.4));
        assert_eq!(patched["arms"]["right"]["j1"], json!(0.2));
        assert_eq!(named.objects.iter().collect::<Vec<_>>(), ["ball"]);
        assert_eq!(named.arms.iter().collect::<Vec<_>>(), ["left"]);
    }

    #[test]
    fn operations_apply_in_order_and_copy_is_refused() {
        let ops = json!([
            {"op": "replace", "path": "/objects/box", "value": {"holder": "table", "at": [0.1, 0.1, 1.0]}},
            {"op": "remove", "path": "/arms/right"}
        ]);
        let (text, named) = apply(&document(), &ops, Form::Operations).expect("applies");
        let patched: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(patched["objects"]["box"]["holder"], json!("table"));
        assert!(patched["arms"].get("right").is_none());
        assert_eq!(named.objects.iter().collect::<Vec<_>>(), ["box"]);
        assert_eq!(named.arms.iter().collect::<Vec<_>>(), ["right"]);
        let copy = json!([{"op": "copy", "from": "/objects", "path": "/arms/x"}]);
        assert!(apply(&document(), &copy, Form::Operations).is_err());
        let wrong = json!([{"op": "remove", "path": "/objects/nothing"}]);
        assert!(apply(&document(), &wrong, Form::Operations).is_err());
    }
}
