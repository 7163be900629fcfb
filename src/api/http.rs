//! HTTP as clients expect it: request ids, query strings, entity tags and
//! conditional requests, cache headers, poll intervals.

use axum::body::Body;
use axum::extract::{FromRequestParts, Request};
use axum::http::request::Parts;
use axum::http::{HeaderMap, HeaderName, HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use serde::de::DeserializeOwned;
use utoipa::IntoParams;

use super::problem::Problem;

/// The request-id header, accepted from clients and echoed on every response.
pub static REQUEST_ID: HeaderName = HeaderName::from_static("x-request-id");

/// Longest client-chosen request id kept; a longer or unprintable one is
/// replaced by a generated id.
pub const MAX_REQUEST_ID: usize = 128;

/// Whether `value` may serve as a request id: 1 to [`MAX_REQUEST_ID`]
/// printable ASCII characters without spaces.
pub fn valid_request_id(value: &HeaderValue) -> bool {
    let b = value.as_bytes();
    !b.is_empty() && b.len() <= MAX_REQUEST_ID && b.iter().all(|c| (0x21..0x7f).contains(c))
}

/// Drops a request id a client sent that cannot be kept (too long, or not
/// printable): the request-id layer then generates one.
pub async fn sanitize_request_id(mut request: Request, next: Next) -> Response {
    if let Some(v) = request.headers().get(&REQUEST_ID)
        && !valid_request_id(v)
    {
        request.headers_mut().remove(&REQUEST_ID);
    }
    next.run(request).await
}

/// A query string read into `T`, whose parameters (as its [`IntoParams`]
/// describes them) are the ones the endpoint takes. Its rejection is the
/// problem to answer: a 400 naming the parameter at fault ([`BadQuery`]).
///
/// A handler that checks something before the query (the path's id, the
/// content type) takes `Result<Query<T>, Problem>` and looks at it in turn.
#[derive(Debug, Clone, Copy, Default)]
pub struct Query<T>(pub T);

impl<T, S> FromRequestParts<S> for Query<T>
where
    T: DeserializeOwned + IntoParams,
    S: Send + Sync,
{
    type Rejection = Problem;

    async fn from_request_parts(parts: &mut Parts, _state: &S) -> Result<Self, Problem> {
        read_query(parts.uri.query().unwrap_or_default())
            .map(Query)
            .map_err(Problem::from)
    }
}

/// Why a query string does not read.
#[derive(Clone, Debug, PartialEq)]
pub enum BadQuery {
    /// A parameter the endpoint takes, with a value that does not read.
    Value {
        /// The parameter.
        name: String,
        /// What is wrong with its value.
        message: String,
    },
    /// A parameter the endpoint does not take (the first given).
    Unknown {
        /// The parameter, as given (percent-decoded).
        name: String,
        /// The parameters the endpoint takes, in order.
        takes: Vec<String>,
    },
    /// Anything else (a parameter given twice).
    Other {
        /// What is wrong.
        message: String,
        /// The endpoint's parameter, when it takes just one.
        only: Option<String>,
    },
}

/// A query string that does not read: 400, naming the parameter at fault.
impl From<BadQuery> for Problem {
    fn from(e: BadQuery) -> Self {
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

/// `query` (a URL's query string, without `?`) read into `T`.
pub fn read_query<T: DeserializeOwned + IntoParams>(query: &str) -> Result<T, BadQuery> {
    let pairs = || form_urlencoded::parse(query.as_bytes());
    let deserializer = serde_urlencoded::Deserializer::new(pairs());
    serde_path_to_error::deserialize(deserializer).map_err(|e| {
        let takes: Vec<String> = T::into_params(|| None)
            .into_iter()
            .map(|p| p.name)
            .collect();
        if let Some(serde_path_to_error::Segment::Map { key }) = e.path().iter().next()
            && takes.contains(key)
        {
            return BadQuery::Value {
                name: key.clone(),
                message: e.inner().to_string(),
            };
        }
        // serde reads the pairs in order and stops at the first it cannot
        // take: a parameter the endpoint does not take, or one given twice.
        let mut seen = std::collections::HashSet::new();
        for (name, _) in pairs() {
            if !takes.iter().any(|t| *t == name) {
                return BadQuery::Unknown {
                    name: name.into_owned(),
                    takes,
                };
            }
            if !seen.insert(name) {
                break;
            }
        }
        BadQuery::Other {
            message: format!("Failed to deserialize query string: {e}"),
            only: (takes.len() == 1).then(|| takes[0].clone()),
        }
    })
}

/// problem+json bodies name the request they answer: `instance` is
/// `urn:topple:request:<id>` and `request_id` the id itself.
pub async fn problem_instance(request: Request, next: Next) -> Response {
    let id = request
        .headers()
        .get(&REQUEST_ID)
        .and_then(|v| v.to_str().ok())
        .map(str::to_owned);
    let response = next.run(request).await;
    let is_problem = response
        .headers()
        .get(header::CONTENT_TYPE)
        .is_some_and(|v| v.as_bytes().starts_with(b"application/problem+json"));
    let Some(id) = id.filter(|_| is_problem) else {
        return response;
    };
    let (mut parts, body) = response.into_parts();
    // Problem bodies are a few hundred bytes (their texts are bounded).
    let Ok(bytes) = axum::body::to_bytes(body, 64 * 1024).await else {
        return Problem::internal("the error could not be described").into_response();
    };
    let mut doc: serde_json::Value = match serde_json::from_slice(&bytes) {
        Ok(v) => v,
        Err(_) => return Response::from_parts(parts, Body::from(bytes)),
    };
    if let Some(o) = doc.as_object_mut() {
        o.entry("instance")
            .or_insert_with(|| format!("urn:topple:request:{id}").into());
        o.insert("request_id".into(), id.into());
    }
    let text = doc.to_string();
    parts.headers.remove(header::CONTENT_LENGTH);
    Response::from_parts(parts, Body::from(text))
}

/// Whether the request's `If-None-Match` matches `etag` (weak comparison,
/// RFC 9110 §13.1.2: `W/` prefixes are ignored; `*` matches any).
pub fn if_none_match(headers: &HeaderMap, etag: &str) -> bool {
    let opaque = |t: &str| t.trim().trim_start_matches("W/").to_owned();
    let ours = opaque(etag);
    headers
        .get_all(header::IF_NONE_MATCH)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(','))
        .any(|t| t.trim() == "*" || opaque(t) == ours)
}

/// `304 Not Modified` with the validators a 200 would carry.
pub fn not_modified(etag: &str, cache_control: &str) -> Response {
    let mut r = StatusCode::NOT_MODIFIED.into_response();
    set_validators(r.headers_mut(), etag, cache_control);
    r
}

/// Sets `ETag` and `Cache-Control`.
pub fn set_validators(headers: &mut HeaderMap, etag: &str, cache_control: &str) {
    if let Ok(v) = HeaderValue::from_str(etag) {
        headers.insert(header::ETAG, v);
    }
    if let Ok(v) = HeaderValue::from_str(cache_control) {
        headers.insert(header::CACHE_CONTROL, v);
    }
}

/// Cache-Control of a result: it never changes. Shared caches may keep it
/// unless reads need a token.
pub fn immutable(private: bool) -> &'static str {
    if private {
        "private, max-age=31536000, immutable"
    } else {
        "public, max-age=31536000, immutable"
    }
}

/// Cache-Control of a job's status: it changes; revalidate with its ETag.
pub const REVALIDATE: &str = "no-cache";

/// The strong entity tag of a result representation: the job's cache key
/// (blake3 of the canonical spec and the engine version) and the format.
pub fn result_etag(key: &str, format: &str) -> String {
    format!("\"{}-{format}\"", &key[..key.len().min(32)])
}

/// A poll interval, in whole seconds from 1 to 30, for work expected to take
/// `seconds` more: about a fifth of it.
pub fn poll_interval(seconds: f64) -> u64 {
    if !seconds.is_finite() {
        return 30;
    }
    (seconds / 5.0).ceil().clamp(1.0, 30.0) as u64
}

/// Middleware: a body whose declared `Content-Length` is over the limit is
/// refused with 413 before a byte of it is read — and so before hyper sends
/// `100 Continue` to a client that asked with `Expect: 100-continue`.
pub async fn refuse_oversized_bodies(
    axum::extract::State(state): axum::extract::State<crate::service::AppState>,
    req: Request,
    next: Next,
) -> Response {
    // A record file has a limit of its own.
    let (max, limit) = if req.uri().path() == "/v1/records" {
        (state.config.max_record_bytes, "max_record_bytes")
    } else {
        (state.config.max_body_bytes, "max_body_bytes")
    };
    let declared = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if declared.is_some_and(|n| n > max as u64) {
        return Problem::body_too_large_for(max, limit).into_response();
    }
    next.run(req).await
}

/// The audit line of a write (submit, cancel, delete): one structured log
/// line with the tenant, the job and the request's id, under target `audit`.
pub fn audit(
    action: &str,
    tenant: &super::auth::Tenant,
    job: uuid::Uuid,
    headers: &axum::http::HeaderMap,
) {
    let request_id = headers
        .get(&REQUEST_ID)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("");
    tracing::info!(target: "audit", action, tenant = tenant.name(), job_id = %job, request_id, "audit");
}

/// A route that takes no query parameters.
#[derive(Debug, serde::Deserialize, IntoParams)]
#[serde(deny_unknown_fields)]
pub struct NoQuery {}

#[cfg(test)]
mod tests {
    use super::*;

    /// The problem a query string gets: (detail, parameter), or `None` when
    /// it reads.
    fn refusal<T: DeserializeOwned + IntoParams>(query: &str) -> Option<(String, Option<String>)> {
        let p = Problem::from(read_query::<T>(query).err()?);
        assert_eq!(p.status, 400);
        assert_eq!(p.kind, "https://topple.dev/problems/invalid-parameter");
        assert_eq!(p.title, "Bad request");
        assert_eq!(p.pointer, p.parameter.as_ref().map(|n| format!("#/{n}")));
        Some((p.detail, p.parameter))
    }

    fn says(detail: &str, parameter: Option<&str>) -> Option<(String, Option<String>)> {
        Some((detail.to_string(), parameter.map(str::to_string)))
    }

    /// What a query string gets and what clients have always read.
    type Case = (
        Option<(String, Option<String>)>,
        Option<(String, Option<String>)>,
    );

    /// The problems of bad query strings of POST /v1/jobs (wait only).
    fn create_query_cases() -> Vec<Case> {
        use crate::api::jobs::CreateQuery;
        type Create = CreateQuery;
        vec![
            (refusal::<Create>("wait=1"), None),
            (
                refusal::<Create>("wait=abc"),
                says("wait: invalid float literal", Some("wait")),
            ),
            (
                refusal::<Create>("wait="),
                says("wait: cannot parse float from empty string", Some("wait")),
            ),
            (
                refusal::<Create>("wait=1&foo=2"),
                says(
                    "unknown query parameter \"foo\": this endpoint takes wait",
                    Some("foo"),
                ),
            ),
            // serde stops at the first pair at fault.
            (
                refusal::<Create>("wait=abc&foo=2"),
                says("wait: invalid float literal", Some("wait")),
            ),
            (
                refusal::<Create>("foo=2&wait=abc"),
                says(
                    "unknown query parameter \"foo\": this endpoint takes wait",
                    Some("foo"),
                ),
            ),
            (
                refusal::<Create>("=1"),
                says(
                    "unknown query parameter \"\": this endpoint takes wait",
                    Some(""),
                ),
            ),
            (
                refusal::<Create>("wait=1&wait=2&foo=1"),
                says(
                    "Failed to deserialize query string: duplicate field `wait`",
                    Some("wait"),
                ),
            ),
            // A name with a backquote is named whole.
            (
                refusal::<Create>("a%60b=1"),
                says(
                    "unknown query parameter \"a`b\": this endpoint takes wait",
                    Some("a`b"),
                ),
            ),
        ]
    }

    /// The problems of bad query strings of the endpoints that take none, of
    /// the list of jobs and of the upload of a record.
    fn other_query_cases() -> Vec<Case> {
        use crate::api::http::NoQuery;
        use crate::api::jobs::ListParams;
        use crate::api::records::UploadQuery;
        vec![
            (refusal::<NoQuery>(""), None),
            (refusal::<NoQuery>("&&"), None),
            (
                refusal::<NoQuery>("x=1"),
                says(
                    "unknown query parameter \"x\": this endpoint takes none",
                    Some("x"),
                ),
            ),
            (
                refusal::<ListParams>("limit=-1"),
                says("limit: invalid digit found in string", Some("limit")),
            ),
            (
                refusal::<ListParams>("bogus=1"),
                says(
                    "unknown query parameter \"bogus\": this endpoint takes status, kind, limit, cursor, include",
                    Some("bogus"),
                ),
            ),
            // Of several parameters none is the one given twice.
            (
                refusal::<ListParams>("limit=1&limit=2"),
                says(
                    "Failed to deserialize query string: duplicate field `limit`",
                    None,
                ),
            ),
            (
                refusal::<UploadQuery>("allow_large_pga=yes"),
                says(
                    "allow_large_pga: provided string was not `true` or `false`",
                    Some("allow_large_pga"),
                ),
            ),
            (refusal::<UploadQuery>("dt=1e999"), None),
            (
                refusal::<UploadQuery>("x+y=1"),
                says(
                    "unknown query parameter \"x y\": this endpoint takes format, unit, dt, time_column, acc_column, name, allow_large_pga",
                    Some("x y"),
                ),
            ),
        ]
    }

    /// The problems of bad query strings, as clients have always read them:
    /// the first parameter at fault, in order, is named.
    #[test]
    fn a_query_that_does_not_read_names_its_parameter() {
        let cases = create_query_cases().into_iter().chain(other_query_cases());
        for (i, (got, want)) in cases.enumerate() {
            assert_eq!(got, want, "case {i}");
        }
    }

    #[test]
    fn request_ids_are_bounded_and_printable() {
        assert!(valid_request_id(&HeaderValue::from_static("abc-123_X")));
        assert!(!valid_request_id(&HeaderValue::from_static("two words")));
        assert!(!valid_request_id(&HeaderValue::from_static("")));
        let long = "x".repeat(MAX_REQUEST_ID + 1);
        assert!(!valid_request_id(
            &HeaderValue::from_str(&long).expect("ascii")
        ));
    }

    #[test]
    fn if_none_match_compares_weakly_and_takes_lists_and_stars() {
        let mut h = HeaderMap::new();
        h.insert(
            header::IF_NONE_MATCH,
            HeaderValue::from_static("\"a\", W/\"b\""),
        );
        assert!(if_none_match(&h, "\"b\""));
        assert!(if_none_match(&h, "W/\"a\""));
        assert!(!if_none_match(&h, "\"c\""));
        h.insert(header::IF_NONE_MATCH, HeaderValue::from_static("*"));
        assert!(if_none_match(&h, "\"anything\""));
        assert!(!if_none_match(&HeaderMap::new(), "\"a\""));
    }

    #[test]
    fn poll_intervals_stay_between_one_and_thirty_seconds() {
        assert_eq!(poll_interval(0.001), 1);
        assert_eq!(poll_interval(12.0), 3);
        assert_eq!(poll_interval(1e6), 30);
        assert_eq!(poll_interval(f64::NAN), 30);
    }
}
