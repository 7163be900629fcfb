//! RFC 9457 problem details: every error the API returns.

use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

use crate::service::finished::{RESULT_WAIT, ResultError};
use crate::service::fragility_links::LinkError;
use crate::service::submit::SubmitError;

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
    pub fn over_limit(e: &crate::kinds::limits::LimitError) -> Self {
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

/// Seconds a client told that result reads are busy waits before trying again.
const BUSY_RETRY_S: u64 = 2;

impl Problem {
    /// 503: `what` stayed taken for [`RESULT_WAIT`] (the memory for large
    /// results, the database, the rendering turns).
    pub fn busy(what: &str) -> Self {
        Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "busy",
            "Busy",
            format!(
                "{what} stayed busy for {} s; try again in {BUSY_RETRY_S} s",
                RESULT_WAIT.as_secs()
            ),
        )
        .retry_after(BUSY_RETRY_S)
    }
}

/// A result that cannot be read: 404 without the job, 409 until it has
/// succeeded (a caller adds when to look again), 503 when busy.
impl From<ResultError> for Problem {
    fn from(e: ResultError) -> Self {
        match e {
            ResultError::NotFound(id) => Problem::not_found(format!("no job {id}")).param("id"),
            ResultError::Failed { id, error } => {
                Problem::conflict("job-failed", format!("job {id} failed: {error}"))
            }
            ResultError::Canceled(id) => {
                Problem::conflict("job-canceled", format!("job {id} was canceled"))
            }
            ResultError::NotFinished(job) => Problem::conflict(
                "not-finished",
                format!(
                    "job {id} is {}; poll /v1/jobs/{id} (?wait=N waits for it) or follow /v1/jobs/{id}/events",
                    job.status.as_str(),
                    id = job.id
                ),
            ),
            ResultError::Missing(id) => Problem::internal(format!("result of job {id} is missing")),
            ResultError::Busy => {
                Problem::busy("the memory for large results (result_memory) or the database")
            }
            ResultError::Store(e) => e.into(),
        }
    }
}

/// The fragility jobs a survival spec names: an invalid spec (422) when
/// they are named wrongly or cannot be read, saying why.
impl From<LinkError> for Problem {
    fn from(e: LinkError) -> Self {
        match e {
            LinkError::Invalid(e) => e.into(),
            LinkError::Unreadable {
                pointer,
                id,
                reason,
            } => {
                let why = Problem::from(reason).detail;
                crate::jobs::SpecError::at(pointer, format!("job {id} cannot be read: {why}"))
                    .into()
            }
            e @ (LinkError::Corrupt(_) | LinkError::Stopped(_)) => Problem::internal(e.to_string()),
        }
    }
}

/// Seconds a client told the queue is full waits before trying again.
const RETRY_AFTER_S: u64 = 2;

/// A submission refused: its body or spec (400, 422), a limit (422), the
/// queue or the tenant's quota (429, with when to try again), the store.
impl From<SubmitError> for Problem {
    fn from(e: SubmitError) -> Self {
        match e {
            SubmitError::NotUtf8 => Problem::bad_request("invalid-body", "the body is not UTF-8"),
            SubmitError::Spec(e) => e.into(),
            SubmitError::Link(e) => e.into(),
            SubmitError::Limit(e) => Problem::over_limit(&e),
            SubmitError::TenantQuota {
                tenant,
                live,
                quota,
            } => Problem::new(
                StatusCode::TOO_MANY_REQUESTS,
                "tenant-quota",
                "Tenant quota reached",
                format!(
                    "tenant {tenant:?} has {live} jobs queued or running, its quota (max_queued_per_tenant); try again in {RETRY_AFTER_S} s, once one finishes"
                ),
            )
            .limit("max_queued_per_tenant", quota as f64)
            .retry_after(RETRY_AFTER_S),
            SubmitError::QueueFull { max } => Problem::new(
                StatusCode::TOO_MANY_REQUESTS,
                "queue-full",
                "Queue full",
                format!("{max} jobs are waiting (max_queued); try again in {RETRY_AFTER_S} s"),
            )
            .limit("max_queued", max as f64)
            .retry_after(RETRY_AFTER_S),
            SubmitError::Store(e) => e.into(),
            e @ (SubmitError::Serialise(_) | SubmitError::Stopped(_)) => {
                Problem::internal(e.to_string())
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
