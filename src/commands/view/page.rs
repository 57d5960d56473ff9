//! The page: one HTML file with everything inlined, so it opens from `file://` with no
//! network. three.js (0.170.0, `third_party/three/`, MIT) and its OrbitControls are
//! embedded in the binary and handed to the page's module script through an import map
//! of `data:` URLs; the document computed in Rust is a JSON script element; the script
//! (`assets/view.js`) and style (`assets/view.css`) only draw it.

use base64::Engine;
use serde::Serialize;

/// three.js as published on npm (`build/three.module.min.js`).
const THREE: &str = include_str!("../../../third_party/three/three.module.min.js");
/// `examples/jsm/controls/OrbitControls.js` of the same package.
const ORBIT: &str = include_str!("../../../third_party/three/OrbitControls.js");
/// three.js's licence, kept in the page beside the code it covers.
const THREE_LICENSE: &str = include_str!("../../../third_party/three/LICENSE");
const SCRIPT: &str = include_str!("assets/view.js");
const STYLE: &str = include_str!("assets/view.css");
const BODY: &str = include_str!("assets/body.html");

fn data_url(code: &str) -> String {
    format!(
        "data:text/javascript;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(code)
    )
}

/// JSON that cannot end the script element it sits in: every `<` is written as an
/// escape (it only ever occurs inside strings).
fn script_json<T: Serialize>(value: &T) -> String {
    serde_json::to_string(value)
        .unwrap_or_else(|_| "null".to_string())
        .replace('<', "\\u003c")
}

/// The whole page.
pub fn html<T: Serialize>(title: &str, document: &T) -> String {
    let imports = serde_json::json!({
        "imports": {
            "three": data_url(THREE),
            "three/addons/controls/OrbitControls.js": data_url(ORBIT),
        }
    });
    let licence = THREE_LICENSE.replace("--", "- -");
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
<title>{}</title>\n<style>\n{STYLE}</style>\n\
<!-- three.js 0.170.0 (https://threejs.org), inlined below; its licence:\n{licence}-->\n\
<script type=\"importmap\">{}</script>\n</head>\n<body>\n{BODY}\
<script id=\"cellc-data\" type=\"application/json\">{}</script>\n\
<script type=\"module\">\n{SCRIPT}</script>\n</body>\n</html>\n",
        crate::graph_svg::xml(title),
        imports,
        script_json(document),
    )
}
