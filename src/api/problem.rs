//! RFC 9457 problem details: every error the API returns.

use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

/// An `application/problem+json` body.
#[derive(Clone, Debug, Serialize, utoipa::ToSchema)]
pub struct Problem {
    /// A URI naming the problem type.
    #[serde(rename = "type")]
    pub kind: String,
    /// Short summary of the problem type.
    pub title: String,
    /// HTTP status.
    pub status: u16,
    /// What went wrong here.
    pub detail: String,
    /// JSON pointer (RFC 6901) to the offending field of the request body.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pointer: Option<String>,
    /// The offending query or path parameter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parameter: Option<String>,
    /// Seconds before trying again (also sent as `Retry-After`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub retry_after: Option<u64>,
    /// The offending request header.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub header: Option<String>,
    /// The service limit a job exceeds (as its setting is named).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit: Option<String>,
    /// That limit's value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub maximum: Option<f64>,
    /// The job's value of the limited quantity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
}

impl Problem {
    /// A problem with `status`.
    pub fn new(status: StatusCode, kind: &str, title: &str, detail: impl Into<String>) -> Self {
        Problem {
            kind: format!("https://topple.dev/problems/{kind}"),
            title: title.into(),
            status: status.as_u16(),
            detail: detail.into(),
            pointer: None,
            parameter: None,
            retry_after: None,
            header: None,
            limit: None,
            maximum: None,
            value: None,
        }
    }

    /// With a JSON pointer into the body.
    pub fn at(mut self, pointer: impl Into<String>) -> Self {
        self.pointer = Some(pointer.into());
        self
    }

    /// Naming a query or path parameter.
    pub fn param(mut self, name: &str) -> Self {
        self.parameter = Some(name.into());
        self.pointer = Some(format!("#/{name}"));
        self
    }

    /// With a `Retry-After` of `seconds`.
    pub fn retry_after(mut self, seconds: u64) -> Self {
        self.retry_after = Some(seconds);
        self
    }

    /// Naming the service limit (as its setting is named) and its value.
    pub fn limit(mut self, name: &str, maximum: f64) -> Self {
        self.limit = Some(name.into());
        self.maximum = Some(maximum);
        self
    }

    /// Naming a request header.
    pub fn header_name(mut self, name: &str) -> Self {
        self.header = Some(name.into());
        self
    }

    /// 422 for a job over a service limit.
    pub fn over_limit(e: &crate::jobs::limits::LimitError) -> Self {
        let mut p = Problem::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "limit-exceeded",
            "Job exceeds a service limit",
            format!("{}: {}", e.pointer, e.message),
        )
        .at(e.pointer.clone());
        p.limit = Some(e.limit.into());
        p.maximum = Some(e.maximum);
        p.value = Some(e.value);
        p
    }

    /// 413: a body over `max` bytes (`max_body_bytes`).
    pub fn body_too_large(max: usize) -> Self {
        Problem::body_too_large_for(max, "max_body_bytes")
    }

    /// 413: a body over `max` bytes, the limit set by `limit`.
    pub fn body_too_large_for(max: usize, limit: &str) -> Self {
        let mut p = Problem::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "body-too-large",
            "Body too large",
            format!("the body is larger than this service's limit of {max} bytes ({limit})"),
        )
        .at("")
        .header_name("content-length");
        p.limit = Some(limit.into());
        p.maximum = Some(max as f64);
        p
    }

    /// 400, malformed request.
    pub fn bad_request(kind: &str, detail: impl Into<String>) -> Self {
        Problem::new(StatusCode::BAD_REQUEST, kind, "Bad request", detail)
    }

    /// 404.
    pub fn not_found(detail: impl Into<String>) -> Self {
        Problem::new(StatusCode::NOT_FOUND, "not-found", "Not found", detail)
    }

    /// 409.
    pub fn conflict(kind: &str, detail: impl Into<String>) -> Self {
        Problem::new(StatusCode::CONFLICT, kind, "Conflict", detail)
    }

    /// 500 (storage failures only; bad input never ends here).
    pub fn internal(detail: impl Into<String>) -> Self {
        Problem::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            "Internal error",
            detail,
        )
    }
}

/// The one place storage failures become HTTP: a full disk is 507, an
/// unreachable or failing database 503, both with `Retry-After`; only what is
/// neither (a bug, a corrupt row) is a 500.
impl From<crate::store::StoreError> for Problem {
    fn from(e: crate::store::StoreError) -> Self {
        use crate::store::Failure;
        match e.failure() {
            Failure::NoSpace => {
                tracing::warn!(error = %e, "storage full");
                Problem::new(
                    StatusCode::INSUFFICIENT_STORAGE,
                    "storage-full",
                    "Storage full",
                    "the service's storage is full: nothing was saved; retry later",
                )
                .retry_after(30)
            }
            Failure::Unavailable => {
                tracing::warn!(error = %e, "storage unavailable");
                Problem::new(
                    StatusCode::SERVICE_UNAVAILABLE,
                    "storage-unavailable",
                    "Storage unavailable",
                    "the service's database is unavailable: nothing was saved; retry shortly",
                )
                .retry_after(2)
            }
            Failure::Other => {
                tracing::error!(error = %e, "storage failure");
                Problem::internal("storage failure")
            }
        }
    }
}

/// The one place a refused spec becomes HTTP: a body that is not JSON is
/// 400, a spec that does not validate 422; both name the field at fault.
impl From<crate::jobs::SpecError> for Problem {
    fn from(e: crate::jobs::SpecError) -> Self {
        use crate::jobs::error::SpecErrorKind;
        let status = match e.kind {
            SpecErrorKind::Syntax => StatusCode::BAD_REQUEST,
            SpecErrorKind::Invalid => StatusCode::UNPROCESSABLE_ENTITY,
        };
        // A pointer may hold a key the client sent, of any length.
        let shown: String = if e.pointer.is_empty() {
            "/".into()
        } else {
            e.pointer
                .split('/')
                .map(|segment| {
                    if segment.chars().count() > 40 {
                        segment.chars().take(40).chain(['…']).collect()
                    } else {
                        segment.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join("/")
        };
        Problem::new(
            status,
            "invalid-spec",
            "Invalid job spec",
            format!("{shown}: {}", e.message),
        )
        .at(e.pointer)
    }
}

/// A query string that does not read: 400, naming the parameter at fault.
impl From<super::http::BadQuery> for Problem {
    fn from(e: super::http::BadQuery) -> Self {
        use super::http::BadQuery;
        use crate::jobs::spec::shorten_echoes;
        match e {
            BadQuery::Value { name, message } => Problem::bad_request(
                "invalid-parameter",
                format!("{name}: {}", shorten_echoes(&message)),
            )
            .param(&name),
            BadQuery::Unknown { name, takes } => {
                let takes = if takes.is_empty() {
                    "none".to_string()
                } else {
                    takes.join(", ")
                };
                Problem::bad_request(
                    "invalid-parameter",
                    format!("unknown query parameter {name:?}: this endpoint takes {takes}"),
                )
                .param(&name)
            }
            BadQuery::Other { message, only } => {
                let p = Problem::bad_request("invalid-parameter", shorten_echoes(&message));
                match only {
                    Some(name) => p.param(&name),
                    None => p,
                }
            }
        }
    }
}

/// Longest `detail` a problem carries, bytes: it may quote the input, which
/// is never echoed at length.
const MAX_DETAIL: usize = 1000;
/// Longest `pointer`, `parameter` or `header`, bytes (a pointer may hold a
/// key the client sent).
const MAX_NAME: usize = 200;

/// `text` with control characters (which JSON would write six bytes long)
/// made visible as `?`, cut to at most `max` bytes at a character boundary,
/// the cut marked.
fn bounded(text: &mut String, max: usize) {
    if text.chars().any(char::is_control) {
        *text = text
            .chars()
            .map(|c| if c.is_control() { '?' } else { c })
            .collect();
    }
    if text.len() > max {
        let mut at = max;
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        text.truncate(at);
        text.push('…');
    }
}

impl IntoResponse for Problem {
    fn into_response(mut self) -> Response {
        // Whatever made it: a quotation of the input is cut to a few words.
        self.detail = crate::jobs::spec::shorten_echoes(&self.detail);
        bounded(&mut self.detail, MAX_DETAIL);
        for name in [&mut self.pointer, &mut self.parameter, &mut self.header]
            .into_iter()
            .flatten()
        {
            bounded(name, MAX_NAME);
        }
        let status = StatusCode::from_u16(self.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
        let body = serde_json::to_string(&self).unwrap_or_default();
        let mut r = (status, body).into_response();
        r.headers_mut().insert(
            header::CONTENT_TYPE,
            HeaderValue::from_static("application/problem+json"),
        );
        if let Some(s) = self.retry_after {
            r.headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(s));
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::SpecError;

    /// A spec's status comes from its kind: not JSON is 400, invalid 422;
    /// the text is the same either way.
    #[test]
    fn a_refused_spec_answers_by_its_kind() {
        let syntax = Problem::from(SpecError::syntax("not valid JSON: EOF while parsing"));
        assert_eq!(syntax.status, 400);
        assert_eq!(syntax.kind, "https://topple.dev/problems/invalid-spec");
        assert_eq!(syntax.title, "Invalid job spec");
        assert_eq!(syntax.detail, "/: not valid JSON: EOF while parsing");
        assert_eq!(syntax.pointer.as_deref(), Some(""));
        // A message that merely starts like one is still an invalid field.
        let invalid = Problem::from(SpecError::at("/label", "not valid JSON text"));
        assert_eq!(invalid.status, 422);
        assert_eq!(invalid.detail, "/label: not valid JSON text");
        assert_eq!(invalid.pointer.as_deref(), Some("/label"));
    }

    /// A pointer segment the client wrote long is shown cut, and kept whole
    /// in `pointer`.
    #[test]
    fn long_keys_are_cut_in_the_detail_only() {
        let key = "k".repeat(50);
        let p = Problem::from(SpecError::at(format!("/{key}"), "unknown field"));
        assert_eq!(p.detail, format!("/{}…: unknown field", "k".repeat(40)));
        assert_eq!(p.pointer, Some(format!("/{key}")));
    }
}
