//! The web page at `/`: a form that submits jobs, follows them and shows
//! their plots. Its markup (`page/index.html`) is served at `/`; its style
//! sheet and ES modules (`page/*.css`, `page/*.js`, `page/kinds/*.js`) under
//! `/static/`, from the binary. The values it shares with the service (the
//! kinds, gravity, the plausible block sizes, bounds of the specs) are not
//! written into it twice: the markup's `{{NAME}}` marks and the module
//! `/static/constants.js` are rendered here from the Rust constants.
//!
//! Its policy ([`CSP`]) allows no inline script or style: everything it runs
//! and every rule it is drawn with comes from this origin.

use std::sync::LazyLock;

use axum::extract::Path;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use utoipa::{PartialSchema, ToSchema};

use super::jobs::MAX_LIST_LIMIT;
use super::problem::Problem;
use crate::kinds::{JobKind, JobSpec};

/// The page's markup: [`KINDS_MARK`] stands where the kinds are listed,
/// [`MODULES_MARK`] where its modules are named, `{{NAME}}` where a value
/// of [`marks`] goes.
const TEMPLATE: &str = include_str!("page/index.html");

/// The line of [`TEMPLATE`] that the kinds' radio buttons replace.
const KINDS_MARK: &str = "<!-- job kinds -->\n";

/// The line of [`TEMPLATE`] that the modules' preload links replace.
const MODULES_MARK: &str = "<!-- modules -->\n";

/// Where the page's files are served.
pub const STATIC: &str = "/static/";

/// The page's files, each as served under [`STATIC`]: its path there, its
/// content type, its text. `constants.js` is rendered ([`CONSTANTS`]).
const FILES: &[(&str, &str, &str)] = &[
    ("style.css", CSS, include_str!("page/style.css")),
    ("reference.css", CSS, include_str!("page/reference.css")),
    ("main.js", JS, include_str!("page/main.js")),
    ("api.js", JS, include_str!("page/api.js")),
    ("dom.js", JS, include_str!("page/dom.js")),
    ("format.js", JS, include_str!("page/format.js")),
    ("form.js", JS, include_str!("page/form.js")),
    ("observations.js", JS, include_str!("page/observations.js")),
    ("records.js", JS, include_str!("page/records.js")),
    ("motion.js", JS, include_str!("page/motion.js")),
    ("problems.js", JS, include_str!("page/problems.js")),
    ("jobs.js", JS, include_str!("page/jobs.js")),
    ("result.js", JS, include_str!("page/result.js")),
    ("kinds/index.js", JS, include_str!("page/kinds/index.js")),
    ("kinds/common.js", JS, include_str!("page/kinds/common.js")),
    (
        "kinds/time_history.js",
        JS,
        include_str!("page/kinds/time_history.js"),
    ),
    (
        "kinds/spectrum.js",
        JS,
        include_str!("page/kinds/spectrum.js"),
    ),
    (
        "kinds/friction_spectrum.js",
        JS,
        include_str!("page/kinds/friction_spectrum.js"),
    ),
    (
        "kinds/forensic.js",
        JS,
        include_str!("page/kinds/forensic.js"),
    ),
    (
        "kinds/record_spectrum.js",
        JS,
        include_str!("page/kinds/record_spectrum.js"),
    ),
    (
        "kinds/fragility.js",
        JS,
        include_str!("page/kinds/fragility.js"),
    ),
    (
        "kinds/survival.js",
        JS,
        include_str!("page/kinds/survival.js"),
    ),
];

/// The content type of the modules.
pub const JS: &str = "text/javascript; charset=utf-8";

/// The content type of the style sheet.
pub const CSS: &str = "text/css; charset=utf-8";

/// How the page's files may be cached: kept, but checked again (by their
/// `ETag`) before each use, so that a new build is seen at once.
pub const CACHE_CONTROL: &str = "no-cache";

/// The policy the page runs under: scripts and style sheets from this
/// origin only (none inline), requests to this origin only, images from
/// here or `data:` URLs (the plot fetched with a token), no plugins, no
/// `<base>`, not framed.
pub const CSP: &str = "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; connect-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'";

/// A number as JavaScript (and the markup) writes it.
fn number(x: f64) -> String {
    assert!(x.is_finite(), "not a finite number: {x}");
    format!("{x}")
}

/// The kinds whose spec takes the field `field`, in the registry's order
/// (from the API description of their specs).
fn kinds_taking(field: &str) -> Vec<&'static str> {
    let union = serde_json::to_value(JobSpec::schema()).unwrap_or_default();
    let mut schemas = Vec::new();
    <JobSpec as ToSchema>::schemas(&mut schemas);
    let takes = |kind: &str| {
        let Some(name) = union["discriminator"]["mapping"][kind]
            .as_str()
            .and_then(|target| target.rsplit('/').next())
        else {
            return false;
        };
        schemas
            .iter()
            .filter(|(n, _)| n == name)
            .filter_map(|(_, schema)| serde_json::to_value(schema).ok())
            .any(|schema| schema["properties"].get(field).is_some())
    };
    JobKind::ALL
        .iter()
        .map(|k| k.name())
        .filter(|k| takes(k))
        .collect()
}

/// The kinds that take a floor (`contact`).
fn floor_kinds() -> Vec<&'static str> {
    kinds_taking("contact")
}

/// The kinds whose form offers a vertical motion scaled with the
/// horizontal one, `{"ratio": r}`: those that take `vertical`, but a time
/// history (which has fields of its own for it: a ratio, or samples beside
/// a record).
fn vertical_ratio_kinds() -> Vec<&'static str> {
    kinds_taking("vertical")
        .into_iter()
        .filter(|k| *k != JobKind::TimeHistory.name())
        .collect()
}

/// The values the page's script takes from the service: name, value (as
/// JavaScript), what it is.
fn constants() -> Vec<(&'static str, String, &'static str)> {
    let list = |kinds: Vec<&str>| serde_json::to_string(&kinds).unwrap_or_default();
    vec![
        (
            "G",
            number(crate::dynamics::block::STANDARD_GRAVITY),
            "Gravity, m/s² (the default of every block).",
        ),
        (
            "R_MIN_M",
            number(crate::jobs::plausible::R_MIN_M),
            "The smallest plausible block size R = √(b² + h²), m: smaller, b and h were likely given in millimetres.",
        ),
        (
            "R_MAX_M",
            number(crate::jobs::plausible::R_MAX_M),
            "The largest plausible block size R, m: larger, b and h were likely given in millimetres, or p in Hz.",
        ),
        (
            "LARGE_SLIDE_M",
            number(crate::jobs::plausible::LARGE_SLIDE_M),
            "A residual slide seen past this, m, is warned about (centimetres?).",
        ),
        (
            "MAX_MU",
            number(crate::jobs::contact::MAX_MU),
            "The largest friction coefficient μ a floor takes.",
        ),
        (
            "MAX_OBSERVATIONS",
            crate::kinds::forensic::MAX_OBSERVATIONS.to_string(),
            "The most observations a forensic query takes.",
        ),
        (
            "MAX_LIST_LIMIT",
            MAX_LIST_LIMIT.to_string(),
            "The most jobs one page of GET /v1/jobs holds.",
        ),
        (
            "FLOOR_KINDS",
            list(floor_kinds()),
            "The kinds that take a floor (`contact`).",
        ),
        (
            "VERTICAL_RATIO_KINDS",
            list(vertical_ratio_kinds()),
            "The kinds whose form offers a vertical motion scaled with the horizontal one.",
        ),
    ]
}

/// The module `/static/constants.js`: [`constants`], each `export const`.
pub static CONSTANTS: LazyLock<String> = LazyLock::new(|| {
    let mut out = String::from(
        "// The values the page shares with the service, rendered by the service\n\
         // from its own constants (src/api/page.rs): not written twice.\n",
    );
    for (name, value, doc) in constants() {
        out.push_str(&format!("\n/** {doc} */\nexport const {name} = {value};\n"));
    }
    out
});

/// The values the markup's `{{NAME}}` marks stand for.
fn marks() -> Vec<(&'static str, String)> {
    vec![
        ("MAX_MU", number(crate::jobs::contact::MAX_MU)),
        (
            "MAX_VERTICAL_RATIO",
            number(crate::jobs::vertical::MAX_VERTICAL_RATIO),
        ),
        (
            "GAMMA_MAX",
            number(crate::dynamics::mavroeidis_papageorgiou::GAMMA_MAX),
        ),
        (
            "PGA_IMPLAUSIBLE_G",
            number(crate::records::PGA_IMPLAUSIBLE_G),
        ),
        (
            "DEFAULT_A_MAX",
            number(crate::kinds::spectrum::DEFAULT_A_MAX),
        ),
        (
            "DEFAULT_TOLERANCE",
            number(crate::kinds::spectrum::DEFAULT_TOLERANCE),
        ),
        ("FLOOR_KINDS", floor_kinds().join(" ")),
        ("VERTICAL_RATIO_KINDS", vertical_ratio_kinds().join(" ")),
    ]
}

/// The modules main.js imports, each preloaded: fetched at once, not one
/// import after another.
fn preloads() -> String {
    let mut paths: Vec<&str> = FILES
        .iter()
        .filter(|(path, kind, _)| *kind == JS && *path != "main.js")
        .map(|(path, _, _)| *path)
        .collect();
    paths.push("constants.js");
    paths
        .iter()
        .map(|path| format!("<link rel=\"modulepreload\" href=\"{STATIC}{path}\">\n"))
        .collect()
}

/// The page, as served: its kind list is the registry's
/// ([`crate::kinds::registry`]), the first kind checked; its marks filled in.
pub static HTML: LazyLock<String> = LazyLock::new(|| {
    let radios: String = JobKind::ALL
        .iter()
        .enumerate()
        .map(|(i, kind)| {
            format!(
                "      <label><input type=\"radio\" name=\"kind\" value=\"{}\"{}> {}</label>\n",
                kind.name(),
                if i == 0 { " checked" } else { "" },
                kind.label()
            )
        })
        .collect();
    let mut html = TEMPLATE
        .replacen(KINDS_MARK, &radios, 1)
        .replacen(MODULES_MARK, &preloads(), 1);
    for (name, value) in marks() {
        html = html.replace(&format!("{{{{{name}}}}}"), &value);
    }
    html
});

/// A file's entity tag: a digest of its text.
fn etag(text: &str) -> String {
    format!("\"{}\"", &blake3::hash(text.as_bytes()).to_hex()[..32])
}

/// The page's file at `path` (under [`STATIC`]): its content type and text.
fn file(path: &str) -> Option<(&'static str, &'static str)> {
    if path == "constants.js" {
        return Some((JS, CONSTANTS.as_str()));
    }
    FILES
        .iter()
        .find(|(p, _, _)| *p == path)
        .map(|(_, kind, text)| (*kind, *text))
}

/// `GET /`: the page.
pub async fn index() -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CONTENT_SECURITY_POLICY, CSP),
        ],
        HTML.as_str(),
    )
}

/// `GET /static/{path}`: a file of the page, with its `ETag` (a request
/// that names it in `If-None-Match` is answered 304, without the file).
pub async fn asset(Path(path): Path<String>, request: HeaderMap) -> Response {
    let Some((kind, text)) = file(&path) else {
        return Problem::not_found("no such file of the page").into_response();
    };
    let tag = etag(text);
    let fresh = request
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.split(',').any(|t| t.trim() == tag || t.trim() == "*"));
    let headers = [
        (header::CONTENT_TYPE, HeaderValue::from_static(kind)),
        (
            header::CACHE_CONTROL,
            HeaderValue::from_static(CACHE_CONTROL),
        ),
        (
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        ),
        (
            header::ETAG,
            HeaderValue::from_str(&tag).unwrap_or(HeaderValue::from_static("\"\"")),
        ),
    ];
    if fresh {
        (StatusCode::NOT_MODIFIED, headers).into_response()
    } else {
        (headers, text).into_response()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn served_as_html_under_the_policy() {
        let response = index().await.into_response();
        let headers = response.headers();
        assert_eq!(headers[header::CONTENT_TYPE], "text/html; charset=utf-8");
        assert_eq!(headers[header::CONTENT_SECURITY_POLICY], CSP);
        for unsafe_source in ["'unsafe-inline'", "'unsafe-eval'", "*"] {
            assert!(!CSP.contains(unsafe_source), "{CSP}");
        }
    }

    /// Every mark of the markup is filled in, and it holds no script,
    /// style or event handler of its own: they come from its files.
    #[test]
    fn the_markup_is_markup_only() {
        assert!(TEMPLATE.contains(KINDS_MARK) && TEMPLATE.contains(MODULES_MARK));
        assert!(!HTML.contains("{{") && !HTML.contains("}}"));
        for (name, _) in marks() {
            assert!(
                TEMPLATE.contains(&format!("{{{{{name}}}}}")),
                "{name} unused"
            );
        }
        for inline in ["<style", "style=\"", "<script>"] {
            assert!(!HTML.contains(inline), "inline {inline:?}");
        }
        let handler = HTML.match_indices(" on").find(|(i, _)| {
            let rest = &HTML[i + 3..];
            let name = rest.chars().take_while(char::is_ascii_lowercase).count();
            name > 0 && rest[name..].starts_with('=')
        });
        assert!(
            handler.is_none(),
            "an event handler in the markup: {handler:?}"
        );
        assert!(HTML.contains("<script type=\"module\" src=\"/static/main.js\"></script>"));
        assert!(HTML.contains("<link rel=\"stylesheet\" href=\"/static/style.css\">"));
    }

    /// Every kind of the registry is offered, has a part of the form of its
    /// own (`data-kinds` naming it) and a module of its own, which the
    /// kinds' index imports.
    #[test]
    fn every_kind_has_its_part_of_the_page() {
        let index = file("kinds/index.js").expect("the kinds' index").1;
        for kind in crate::kinds::KINDS {
            let radio = format!(r#"<input type="radio" name="kind" value="{kind}""#);
            assert!(HTML.contains(&radio), "the form has no {kind}");
            let form = HTML.split("data-kinds=\"").skip(1).any(|rest| {
                rest.split('"')
                    .next()
                    .is_some_and(|list| list.split(' ').any(|k| k == *kind))
            });
            assert!(form, "no part of the form is for {kind}");
            assert!(
                file(&format!("kinds/{kind}.js")).is_some(),
                "no module for {kind}"
            );
            assert!(
                index.contains(&format!("import {kind} from \"./{kind}.js\";")),
                "{kind}"
            );
        }
    }

    /// Every module a module imports is served; every file served is used.
    #[test]
    fn the_modules_served_are_those_imported() {
        let mut reached = vec!["main.js".to_string()];
        let mut i = 0;
        while i < reached.len() {
            let path = reached[i].clone();
            let (kind, text) =
                file(&path).unwrap_or_else(|| panic!("{path} is imported, not served"));
            assert_eq!(kind, JS, "{path}");
            let dir = path.rsplit_once('/').map_or("", |(d, _)| d);
            for line in text.lines().filter(|l| l.starts_with("import ")) {
                let Some(target) = line
                    .split(" from \"")
                    .nth(1)
                    .and_then(|t| t.split('"').next())
                else {
                    continue;
                };
                let mut parts: Vec<&str> = dir.split('/').filter(|p| !p.is_empty()).collect();
                for step in target.split('/') {
                    match step {
                        "." => {}
                        ".." => {
                            parts.pop();
                        }
                        name => parts.push(name),
                    }
                }
                let resolved = parts.join("/");
                if !reached.contains(&resolved) {
                    reached.push(resolved);
                }
            }
            i += 1;
        }
        for (path, kind, _) in FILES {
            assert!(
                *kind == CSS || reached.iter().any(|r| r == path),
                "{path} is served, never imported"
            );
        }
        assert!(reached.iter().any(|r| r == "constants.js"));
    }

    /// The type check's declaration of `constants.js` names what is
    /// rendered, with the types rendered.
    #[test]
    fn the_constants_are_declared_as_rendered() {
        let declared = include_str!("page/constants.d.ts");
        let mut want = String::new();
        for (name, value, _) in constants() {
            let ty = if value.starts_with('[') {
                "readonly string[]"
            } else {
                "number"
            };
            want.push_str(&format!("export const {name}: {ty};\n"));
        }
        let got: String = declared
            .lines()
            .filter(|l| l.starts_with("export const "))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(got, want, "src/api/page/constants.d.ts");
    }

    /// The kinds that take a floor, as the page is told them, each take
    /// `contact`; the others refuse it.
    #[test]
    fn the_floor_kinds_are_the_service_s() {
        assert_eq!(
            floor_kinds(),
            [
                "time_history",
                "spectrum",
                "forensic",
                "record_spectrum",
                "fragility"
            ]
        );
        assert_eq!(
            vertical_ratio_kinds(),
            [
                "spectrum",
                "friction_spectrum",
                "forensic",
                "record_spectrum",
                "fragility"
            ]
        );
        let rendered = CONSTANTS.as_str();
        assert!(rendered.contains(
            "export const FLOOR_KINDS = [\"time_history\",\"spectrum\",\"forensic\",\"record_spectrum\",\"fragility\"];"
        ));
        assert!(
            rendered.contains("export const R_MIN_M = 0.01;"),
            "{rendered}"
        );
        assert!(rendered.contains("export const G = 9.81;"), "{rendered}");
    }

    #[tokio::test]
    async fn files_are_served_with_their_type_and_tag() {
        let response = asset(Path("kinds/spectrum.js".into()), HeaderMap::new()).await;
        assert_eq!(response.status(), StatusCode::OK);
        let headers = response.headers().clone();
        assert_eq!(headers[header::CONTENT_TYPE], JS);
        assert_eq!(headers[header::CACHE_CONTROL], CACHE_CONTROL);
        let mut again = HeaderMap::new();
        again.insert(header::IF_NONE_MATCH, headers[header::ETAG].clone());
        let response = asset(Path("kinds/spectrum.js".into()), again).await;
        assert_eq!(response.status(), StatusCode::NOT_MODIFIED);
        let response = asset(Path("style.css".into()), HeaderMap::new()).await;
        assert_eq!(response.headers()[header::CONTENT_TYPE], CSS);
        let response = asset(Path("../page.rs".into()), HeaderMap::new()).await;
        assert_eq!(response.status(), StatusCode::NOT_FOUND);
    }

    #[test]
    fn self_contained() {
        for external in [
            "src=\"http",
            "href=\"http",
            "src=\"//",
            "href=\"//",
            "@import",
            "url(",
        ] {
            assert!(!HTML.contains(external), "the page refers to {external}…");
            for (path, _, text) in FILES {
                assert!(!text.contains(external), "{path} refers to {external}…");
            }
        }
    }
}
