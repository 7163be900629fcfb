//! `GET /docs`: the API reference, an HTML page rendered once from the same
//! OpenAPI document `/openapi.yaml` serves — every operation (its
//! parameters, body and answers) and every schema (its fields, their types,
//! ranges and descriptions), linked to each other.
//!
//! It is made here, from the document, so that it cannot drift from it and
//! needs nothing at run time: no script at all, one style sheet from
//! `/static/`, served under the page's own policy ([`super::page::CSP`]).

use std::fmt::Write as _;
use std::sync::LazyLock;

use axum::http::header;
use axum::response::IntoResponse;
use serde_json::{Map, Value};

use super::page::{CSP, STATIC};

/// Where the reference is served.
pub const PATH: &str = "/docs";

/// The reference, rendered on first use.
static HTML: LazyLock<String> = LazyLock::new(|| render(&super::openapi_value()));

/// `GET /docs`: the API reference as HTML, under the page's policy.
pub async fn index() -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CONTENT_SECURITY_POLICY, CSP),
        ],
        HTML.as_str(),
    )
}

/// The methods of an OpenAPI path item, in the order they are listed.
const METHODS: [&str; 5] = ["get", "post", "put", "patch", "delete"];

/// Text for HTML: `&`, `<`, `>`, `"` and `'` escaped.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// A description's text as HTML: escaped, `` `code` `` as `<code>`, a blank
/// line between paragraphs.
fn prose(text: &str) -> String {
    let mut out = String::new();
    for paragraph in text.split("\n\n").filter(|p| !p.trim().is_empty()) {
        out.push_str("<p>");
        out.push_str(&inline(paragraph.trim()));
        out.push_str("</p>\n");
    }
    out
}

/// One line or paragraph of a description as inline HTML.
fn inline(text: &str) -> String {
    let mut out = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{}</code>", escape(part));
        } else {
            out.push_str(&escape(part));
        }
    }
    out
}

/// The anchor of a schema.
fn schema_anchor(name: &str) -> String {
    format!("schema-{}", anchor_text(name))
}

/// The anchor of an operation.
fn operation_anchor(method: &str, path: &str, op: &Value) -> String {
    match op["operationId"].as_str() {
        Some(id) => format!("op-{}", anchor_text(id)),
        None => format!("op-{method}-{}", anchor_text(path)),
    }
}

/// Text usable in an `id`: letters, digits, `-` and `_`; anything else `-`.
fn anchor_text(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// The schema a `$ref` names (`#/components/schemas/Name` → `Name`).
fn ref_name(reference: &str) -> &str {
    reference.rsplit('/').next().unwrap_or(reference)
}

/// A schema's type in one line of HTML: a link for a named schema, the
/// alternatives of `oneOf`/`anyOf`, `array of …`, an enum's values, and its
/// bounds and default.
fn type_of(schema: &Value) -> String {
    if let Some(reference) = schema["$ref"].as_str() {
        let name = ref_name(reference);
        return format!("<a href=\"#{}\">{}</a>", schema_anchor(name), escape(name));
    }
    let mut out = String::new();
    for key in ["oneOf", "anyOf", "allOf"] {
        if let Some(list) = schema[key].as_array() {
            let sep = if key == "allOf" { " and " } else { " | " };
            let parts: Vec<String> = list
                .iter()
                .map(|part| {
                    if is_rule(part) {
                        rule(part)
                    } else {
                        type_of(part)
                    }
                })
                .collect();
            out = parts.join(sep);
        }
    }
    if out.is_empty() {
        out = match &schema["type"] {
            Value::String(t) => base_type(t, schema),
            Value::Array(types) => types
                .iter()
                .filter_map(Value::as_str)
                .map(|t| base_type(t, schema))
                .collect::<Vec<_>>()
                .join(" | "),
            _ => String::from("any"),
        };
    }
    if let Some(values) = schema["enum"].as_array() {
        let values: Vec<String> = values
            .iter()
            .map(|v| format!("<code>{}</code>", escape(&v.to_string())))
            .collect();
        out = format!("one of {}", values.join(", "));
    }
    let bounds = bounds(schema);
    if !bounds.is_empty() {
        let _ = write!(out, " <span class=\"bounds\">{}</span>", escape(&bounds));
    }
    out
}

/// Whether a schema only states which fields are given (a cross-field
/// rule: `required`, a field that must or must not be null, and their
/// combinations), with no type of its own.
fn is_rule(schema: &Value) -> bool {
    let null = serde_json::json!({"type": "null"});
    let not_null = serde_json::json!({"not": {"type": "null"}});
    let Some(object) = schema.as_object() else {
        return false;
    };
    !object.is_empty()
        && object.iter().all(|(key, value)| match key.as_str() {
            "required" => value.is_array(),
            "properties" => value.as_object().is_some_and(|p| {
                p.values().all(|v| {
                    *v == null
                        || *v == not_null
                        || v["enum"].is_array()
                        || v["not"]["enum"].is_array()
                })
            }),
            "not" | "if" | "then" | "else" => is_rule(value),
            "allOf" | "anyOf" | "oneOf" => value
                .as_array()
                .is_some_and(|list| list.iter().all(is_rule)),
            _ => false,
        })
}

/// A cross-field rule ([`is_rule`]) in words: `alpha` given, no `pulse`,
/// neither … nor …, exactly one of (…).
fn rule(schema: &Value) -> String {
    let mut parts = Vec::new();
    for field in schema["required"].as_array().into_iter().flatten() {
        let name = field.as_str().unwrap_or("");
        parts.push(format!("<code>{}</code> given", escape(name)));
    }
    if let Some(properties) = schema["properties"].as_object() {
        for (name, v) in properties {
            let (values, word) = match (v["enum"].as_array(), v["not"]["enum"].as_array()) {
                (Some(values), _) => (values, "one of"),
                (None, Some(values)) => (values, "not one of"),
                (None, None) => continue,
            };
            let values: Vec<String> = values
                .iter()
                .map(|x| format!("<code>{}</code>", escape(&x.to_string())))
                .collect();
            parts.push(format!(
                "<code>{}</code> {word} {}",
                escape(name),
                values.join(", ")
            ));
        }
        let absent: Vec<String> = properties
            .iter()
            .filter(|(_, v)| v["type"] == "null")
            .map(|(name, _)| format!("<code>{}</code>", escape(name)))
            .collect();
        if !absent.is_empty() {
            parts.push(format!("no {}", absent.join(", ")));
        }
    }
    if let (Some(condition), Some(then)) = (schema.get("if"), schema.get("then")) {
        let otherwise = schema
            .get("else")
            .map(|e| format!("; otherwise {}", rule(e)))
            .unwrap_or_default();
        parts.push(format!(
            "when {}: {}{otherwise}",
            rule(condition),
            rule(then)
        ));
    }
    if let Some(inner) = schema.get("not") {
        parts.push(match inner["anyOf"].as_array() {
            Some(list) => format!(
                "neither {}",
                list.iter().map(rule).collect::<Vec<_>>().join(" nor ")
            ),
            None => format!("not ({})", rule(inner)),
        });
    }
    for (key, open, sep, close) in [
        ("allOf", "", " and ", ""),
        ("anyOf", "(", " or ", ")"),
        ("oneOf", "exactly one of (", "; ", ")"),
    ] {
        if let Some(list) = schema[key].as_array() {
            let inner: Vec<String> = list.iter().map(rule).collect();
            parts.push(format!("{open}{}{close}", inner.join(sep)));
        }
    }
    parts.join(" and ")
}

/// One JSON type, `array of …` with its items.
fn base_type(t: &str, schema: &Value) -> String {
    if t == "array" {
        let items = &schema["items"];
        if items.is_null() {
            return "array".into();
        }
        return format!("array of {}", type_of(items));
    }
    match schema["format"].as_str() {
        Some(format) if t != "null" => format!("{} ({})", escape(t), escape(format)),
        _ => escape(t),
    }
}

/// A schema's bounds and default, as `≥ 0, < 10, default 1`.
fn bounds(schema: &Value) -> String {
    let mut parts = Vec::new();
    for (key, sign) in [
        ("minimum", "≥"),
        ("exclusiveMinimum", ">"),
        ("maximum", "≤"),
        ("exclusiveMaximum", "<"),
        ("minItems", "items ≥"),
        ("maxItems", "items ≤"),
        ("minLength", "length ≥"),
        ("maxLength", "length ≤"),
    ] {
        if let Some(v) = schema.get(key).filter(|v| v.is_number()) {
            parts.push(format!("{sign} {v}"));
        }
    }
    if let Some(v) = schema.get("default") {
        parts.push(format!("default {v}"));
    }
    parts.join(", ")
}

/// The page: the contents, the operations by tag, the schemas.
fn render(doc: &Value) -> String {
    let mut html = String::new();
    let title = doc["info"]["title"].as_str().unwrap_or("API");
    let version = doc["info"]["version"].as_str().unwrap_or("");
    let _ = write!(
        html,
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{t} API reference</title>\n\
         <link rel=\"stylesheet\" href=\"{STATIC}reference.css\">\n</head>\n<body>\n\
         <nav class=\"top\"><a href=\"/\">the page</a> · <a href=\"/openapi.yaml\">openapi.yaml</a></nav>\n\
         <header><h1>{t} API reference</h1><p class=\"version\">version {v} · OpenAPI {o}</p>\n",
        t = escape(title),
        v = escape(version),
        o = escape(doc["openapi"].as_str().unwrap_or("")),
    );
    html.push_str(&prose(doc["info"]["description"].as_str().unwrap_or("")));
    html.push_str("</header>\n");
    let operations = operations(doc);
    let schemas = doc["components"]["schemas"]
        .as_object()
        .cloned()
        .unwrap_or_default();
    html.push_str(&contents(doc, &operations, &schemas));
    html.push_str("<main>\n");
    for (tag, description) in tags(doc) {
        let _ = write!(
            html,
            "<section class=\"tag\" id=\"tag-{}\">\n<h2>{}</h2>\n{}",
            anchor_text(&tag),
            escape(&tag),
            prose(&description)
        );
        for (method, path, op) in operations.iter().filter(|o| tag_of(&o.2) == tag) {
            html.push_str(&operation(method, path, op));
        }
        html.push_str("</section>\n");
    }
    html.push_str("<section class=\"schemas\" id=\"schemas\">\n<h2>Schemas</h2>\n");
    for (name, schema) in &schemas {
        html.push_str(&schema_section(name, schema));
    }
    html.push_str("</section>\n</main>\n</body>\n</html>\n");
    html
}

/// Every operation, as (method, path, operation), in the document's order.
fn operations(doc: &Value) -> Vec<(String, String, Value)> {
    let mut out = Vec::new();
    if let Some(paths) = doc["paths"].as_object() {
        for (path, item) in paths {
            for method in METHODS {
                if let Some(op) = item.get(method) {
                    out.push((method.to_string(), path.clone(), op.clone()));
                }
            }
        }
    }
    out
}

/// An operation's first tag (`other` without one).
fn tag_of(op: &Value) -> String {
    op["tags"][0].as_str().unwrap_or("other").to_string()
}

/// The document's tags with their descriptions, and `other` last when an
/// operation has no tag the document lists.
fn tags(doc: &Value) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = doc["tags"]
        .as_array()
        .map(|tags| {
            tags.iter()
                .filter_map(|t| {
                    let name = t["name"].as_str()?;
                    Some((
                        name.to_string(),
                        t["description"].as_str().unwrap_or("").into(),
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    let untagged = operations(doc)
        .iter()
        .any(|(_, _, op)| !out.iter().any(|(name, _)| *name == tag_of(op)));
    if untagged {
        out.push(("other".into(), String::new()));
    }
    out
}

/// The table of contents: the operations by tag, then the schemas.
fn contents(
    doc: &Value,
    operations: &[(String, String, Value)],
    schemas: &Map<String, Value>,
) -> String {
    let mut html = String::from("<nav class=\"contents\"><h2>Contents</h2>\n<ul>\n");
    for (tag, _) in tags(doc) {
        let _ = write!(
            html,
            "<li><a href=\"#tag-{}\">{}</a>\n<ul>\n",
            anchor_text(&tag),
            escape(&tag)
        );
        for (method, path, op) in operations.iter().filter(|o| tag_of(&o.2) == tag) {
            let _ = writeln!(
                html,
                "<li><a href=\"#{}\"><span class=\"method {m}\">{M}</span> <code>{}</code></a></li>",
                operation_anchor(method, path, op),
                escape(path),
                m = method,
                M = method.to_uppercase(),
            );
        }
        html.push_str("</ul></li>\n");
    }
    let _ = write!(
        html,
        "<li><a href=\"#schemas\">Schemas</a> ({})</li>\n</ul>\n</nav>\n",
        schemas.len()
    );
    html
}

/// One operation: its title, description, parameters, body and answers.
fn operation(method: &str, path: &str, op: &Value) -> String {
    let mut html = String::new();
    let _ = write!(
        html,
        "<section class=\"operation\" id=\"{}\">\n<h3><span class=\"method {method}\">{}</span> <code>{}</code></h3>\n",
        operation_anchor(method, path, op),
        method.to_uppercase(),
        escape(path),
    );
    if let Some(summary) = op["summary"].as_str() {
        let _ = writeln!(html, "<p class=\"summary\">{}</p>", inline(summary));
    }
    html.push_str(&prose(op["description"].as_str().unwrap_or("")));
    if let Some(params) = op["parameters"].as_array().filter(|p| !p.is_empty()) {
        html.push_str(
            "<h4>Parameters</h4>\n<table>\n<tr><th>name</th><th>in</th><th>type</th><th>description</th></tr>\n",
        );
        for p in params {
            let required = if p["required"].as_bool() == Some(true) {
                " <span class=\"required\">required</span>"
            } else {
                ""
            };
            let _ = writeln!(
                html,
                "<tr><td><code>{}</code>{required}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(p["name"].as_str().unwrap_or("")),
                escape(p["in"].as_str().unwrap_or("")),
                type_of(&p["schema"]),
                inline(p["description"].as_str().unwrap_or("")),
            );
        }
        html.push_str("</table>\n");
    }
    if let Some(body) = op["requestBody"].as_object() {
        html.push_str("<h4>Request body</h4>\n");
        html.push_str(&prose(
            body.get("description")
                .and_then(Value::as_str)
                .unwrap_or(""),
        ));
        html.push_str(&content(body.get("content").unwrap_or(&Value::Null)));
    }
    html.push_str(&responses(&op["responses"]));
    html.push_str("</section>\n");
    html
}

/// A body's media types, each with its schema.
fn content(content: &Value) -> String {
    let mut html = String::new();
    if let Some(types) = content.as_object() {
        html.push_str("<ul class=\"content\">\n");
        for (media, body) in types {
            let schema = &body["schema"];
            let shown = if schema.is_null() {
                String::new()
            } else {
                format!(": {}", type_of(schema))
            };
            let _ = writeln!(html, "<li><code>{}</code>{shown}</li>", escape(media));
        }
        html.push_str("</ul>\n");
    }
    html
}

/// An operation's answers: status, description, headers and body.
fn responses(responses: &Value) -> String {
    let mut html = String::new();
    let Some(responses) = responses.as_object() else {
        return html;
    };
    html.push_str(
        "<h4>Responses</h4>\n<table>\n<tr><th>status</th><th>description</th><th>body</th></tr>\n",
    );
    for (status, response) in responses {
        let mut description = inline(response["description"].as_str().unwrap_or(""));
        if let Some(headers) = response["headers"].as_object() {
            for (name, h) in headers {
                let _ = write!(
                    description,
                    "<br><span class=\"header\">header <code>{}</code>: {}</span>",
                    escape(name),
                    inline(h["description"].as_str().unwrap_or(""))
                );
            }
        }
        let _ = writeln!(
            html,
            "<tr><td class=\"status\">{}</td><td>{description}</td><td>{}</td></tr>",
            escape(status),
            content(&response["content"]),
        );
    }
    html.push_str("</table>\n");
    html
}

/// One schema: its description, what it is (one of, all of, an enum), and
/// its fields.
fn schema_section(name: &str, schema: &Value) -> String {
    let mut html = String::new();
    let _ = write!(
        html,
        "<section class=\"schema\" id=\"{}\">\n<h3>{}</h3>\n",
        schema_anchor(name),
        escape(name)
    );
    html.push_str(&prose(schema["description"].as_str().unwrap_or("")));
    let is_object = schema["type"] == "object" || schema.get("properties").is_some();
    let parts: Vec<&Value> = schema["allOf"].as_array().into_iter().flatten().collect();
    let (rules, types): (Vec<&Value>, Vec<&Value>) = parts.into_iter().partition(|p| is_rule(p));
    if !is_object {
        let _ = writeln!(html, "<p class=\"type\">{}</p>", type_of(schema));
    } else if !types.is_empty() {
        let types: Vec<String> = types.iter().map(|t| type_of(t)).collect();
        let _ = writeln!(html, "<p class=\"type\">{}</p>", types.join(" and "));
    }
    if !rules.is_empty() {
        html.push_str("<p>Rules:</p>\n<ul class=\"rules\">\n");
        for r in &rules {
            let _ = writeln!(html, "<li>{}</li>", rule(r));
        }
        html.push_str("</ul>\n");
    }
    if let Some(mapping) = schema["discriminator"]["mapping"].as_object() {
        let field = schema["discriminator"]["propertyName"]
            .as_str()
            .unwrap_or("");
        let _ = write!(html, "<p>By <code>{}</code>:</p>\n<ul>\n", escape(field));
        for (value, target) in mapping {
            let target = ref_name(target.as_str().unwrap_or(""));
            let _ = writeln!(
                html,
                "<li><code>{}</code>: <a href=\"#{}\">{}</a></li>",
                escape(value),
                schema_anchor(target),
                escape(target)
            );
        }
        html.push_str("</ul>\n");
    }
    html.push_str(&fields(schema));
    for part in types {
        html.push_str(&fields(part));
    }
    html.push_str("</section>\n");
    html
}

/// A table of an object schema's fields (none: nothing).
fn fields(schema: &Value) -> String {
    let mut html = String::new();
    let Some(properties) = schema["properties"].as_object().filter(|p| !p.is_empty()) else {
        return html;
    };
    let required: Vec<&str> = schema["required"]
        .as_array()
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    html.push_str("<table>\n<tr><th>field</th><th>type</th><th>description</th></tr>\n");
    for (field, property) in properties {
        let mark = if required.contains(&field.as_str()) {
            " <span class=\"required\">required</span>"
        } else {
            ""
        };
        let _ = writeln!(
            html,
            "<tr><td><code>{}</code>{mark}</td><td>{}</td><td>{}</td></tr>",
            escape(field),
            type_of(property),
            inline(property["description"].as_str().unwrap_or("")),
        );
    }
    html.push_str("</table>\n");
    html
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// Every value of `attribute="…"` in the page.
    fn attribute_values(html: &str, attribute: &str) -> Vec<String> {
        let marker = format!("{attribute}=\"");
        html.split(&marker)
            .skip(1)
            .filter_map(|rest| rest.split('"').next().map(str::to_string))
            .collect()
    }

    #[test]
    fn every_operation_and_schema_of_the_document_is_on_the_page() {
        let doc = crate::api::openapi_value();
        let html = render(&doc);
        let ids: HashSet<String> = attribute_values(&html, "id").into_iter().collect();
        let ops = operations(&doc);
        assert!(ops.len() >= 16, "{} operations", ops.len());
        for (method, path, op) in &ops {
            let anchor = operation_anchor(method, path, op);
            assert!(ids.contains(&anchor), "{method} {path}: no #{anchor}");
            let title = format!(
                "<span class=\"method {method}\">{}</span> <code>{}</code></h3>",
                method.to_uppercase(),
                escape(path)
            );
            assert!(html.contains(&title), "{method} {path}: no title");
        }
        assert!(html.contains("Submit a job."));
        let schemas = doc["components"]["schemas"].as_object().expect("schemas");
        for name in schemas.keys() {
            assert!(ids.contains(&schema_anchor(name)), "schema {name}");
        }
        assert!(!html.contains(">any and any"), "a rule shown as a type");
        assert!(
            !html.contains("<p class=\"type\">any</p>"),
            "a rule shown as a type"
        );
        for field in ["alpha", "omega_ratio", "observations", "ground_motion"] {
            assert!(html.contains(&format!("<code>{field}</code>")), "{field}");
        }
    }

    #[test]
    fn every_link_within_the_page_has_its_target_and_nothing_is_fetched_elsewhere() {
        let html = render(&crate::api::openapi_value());
        let ids: HashSet<String> = attribute_values(&html, "id").into_iter().collect();
        let mut internal = 0;
        for href in attribute_values(&html, "href") {
            if let Some(anchor) = href.strip_prefix('#') {
                assert!(ids.contains(anchor), "#{anchor} has no target");
                internal += 1;
            } else {
                assert!(href.starts_with('/'), "{href}: not of this origin");
            }
        }
        assert!(internal > 100, "{internal} internal links");
        assert!(!html.contains("<script"), "the reference runs no script");
        assert!(!html.contains("style=\""), "no inline style");
        let sources = attribute_values(&html, "src");
        assert!(sources.is_empty(), "{sources:?}");
    }

    #[test]
    fn text_from_the_document_is_escaped() {
        assert_eq!(
            inline("a `<b>` & <script>'x'</script>"),
            "a <code>&lt;b&gt;</code> &amp; &lt;script&gt;&#39;x&#39;&lt;/script&gt;"
        );
        assert_eq!(prose("one\n\n\ntwo"), "<p>one</p>\n<p>two</p>\n");
        let schema = serde_json::json!({"type": ["number", "null"], "format": "double", "exclusiveMinimum": 0});
        assert_eq!(
            type_of(&schema),
            "number (double) | null <span class=\"bounds\">&gt; 0</span>"
        );
        let both_or_neither = serde_json::json!({"anyOf": [
            {"allOf": [{"required": ["b"]}, {"required": ["h"], "properties": {"h": {"not": {"type": "null"}}}}]},
            {"not": {"anyOf": [{"required": ["b"]}, {"required": ["h"]}]}}]});
        assert!(is_rule(&both_or_neither));
        assert_eq!(
            rule(&both_or_neither),
            "(<code>b</code> given and <code>h</code> given or neither <code>b</code> given nor <code>h</code> given)"
        );
        let one = serde_json::json!({"oneOf": [{"required": ["pulse"]}, {"properties": {"pulse": {"type": "null"}}}]});
        assert_eq!(
            rule(&one),
            "exactly one of (<code>pulse</code> given; no <code>pulse</code>)"
        );
        assert!(!is_rule(&serde_json::json!({"type": "object"})));
        let only_cn = serde_json::json!({"if": {"required": ["type"], "properties": {"type": {"not": {"enum": ["cn"]}}}},
                                         "then": {"properties": {"n": {"type": "null"}}}});
        assert_eq!(
            rule(&only_cn),
            "when <code>type</code> given and <code>type</code> not one of <code>&quot;cn&quot;</code>: no <code>n</code>"
        );
        let list = serde_json::json!({"type": "array", "items": {"$ref": "#/components/schemas/Observation"}});
        assert_eq!(
            type_of(&list),
            "array of <a href=\"#schema-Observation\">Observation</a>"
        );
    }

    #[tokio::test]
    async fn served_as_html_under_the_page_policy() {
        let response = index().await.into_response();
        let headers = response.headers();
        assert_eq!(headers[header::CONTENT_TYPE], "text/html; charset=utf-8");
        assert_eq!(headers[header::CONTENT_SECURITY_POLICY], CSP);
    }
}
