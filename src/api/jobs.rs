//! `/v1/jobs`: submit, inspect, fetch results, cancel, list.

use std::time::{Duration, Instant};

use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, PathRejection, QueryRejection};
use axum::extract::{Path, Query, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use tracing::info;
use utoipa::{IntoParams, ToSchema};
use uuid::Uuid;

use super::csv::to_csv;
use super::problem::Problem;
use crate::jobs::forensic::ForensicSpec;
use crate::jobs::friction::FrictionSpec;
use crate::jobs::key::cache_key;
use crate::jobs::spectrum::SpectrumSpec;
use crate::jobs::time_history::TimeHistorySpec;
use crate::jobs::{Job, KINDS};
use crate::service::AppState;
use crate::store::{JobRecord, ListQuery, Status, new_job_id, now_rfc3339};

/// A job spec: exactly what `topple run` accepts.
#[derive(ToSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub enum JobSpec {
    /// `"kind": "time_history"`.
    TimeHistory(TimeHistorySpec),
    /// `"kind": "spectrum"`.
    Spectrum(SpectrumSpec),
    /// `"kind": "friction_spectrum"`.
    FrictionSpectrum(FrictionSpec),
    /// `"kind": "forensic"`.
    Forensic(ForensicSpec),
}

/// Links of a job.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct Links {
    /// This job.
    #[serde(rename = "self")]
    pub this: String,
    /// Its result.
    pub result: String,
}

/// A job as the API shows it.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct JobView {
    /// Identifier (UUIDv7).
    pub id: String,
    /// "time_history" | "spectrum" | "friction_spectrum".
    pub kind: String,
    /// queued | running | succeeded | failed | canceled.
    pub status: Status,
    /// Fraction done, 0..1.
    pub progress: f64,
    /// Cache key (blake3 of the canonical spec and the engine version).
    pub key: String,
    /// On submission: an identical job already existed and is returned instead.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cached: Option<bool>,
    /// RFC 3339.
    pub created_at: String,
    /// RFC 3339.
    pub started_at: Option<String>,
    /// RFC 3339.
    pub finished_at: Option<String>,
    /// Why it failed.
    pub error: Option<String>,
    /// The numerics summary of the result, once done.
    #[schema(value_type = Option<Object>)]
    pub numerics: Option<serde_json::Value>,
    /// The normalised spec.
    #[schema(value_type = Object)]
    pub spec: serde_json::Value,
    /// Links.
    pub links: Links,
    /// The result, inline, when `?wait=` saw the job finish (or a submission
    /// found it done).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>)]
    pub result: Option<Box<serde_json::value::RawValue>>,
}

fn view(r: &JobRecord, cached: Option<bool>) -> JobView {
    let progress = r.progress;
    JobView {
        id: r.id.to_string(),
        kind: r.kind.clone(),
        status: r.status,
        progress,
        key: r.key.clone(),
        cached,
        created_at: r.created_at.clone(),
        started_at: r.started_at.clone(),
        finished_at: r.finished_at.clone(),
        error: r.error.clone(),
        numerics: r
            .numerics
            .as_deref()
            .and_then(|n| serde_json::from_str(n).ok()),
        spec: serde_json::from_str(&r.spec).unwrap_or(serde_json::Value::Null),
        links: Links {
            this: format!("/v1/jobs/{}", r.id),
            result: format!("/v1/jobs/{}/result", r.id),
        },
        result: None,
    }
}

/// Query of a submission.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct CreateQuery {
    /// Wait up to this many seconds for the job to finish and return its result inline.
    #[param(minimum = 0)]
    pub wait: Option<f64>,
}

/// The job id of a path, or a 400 naming `id`.
pub(crate) fn parse_id(path: Result<Path<String>, PathRejection>) -> Result<Uuid, Problem> {
    let Path(raw) =
        path.map_err(|e| Problem::bad_request("invalid-parameter", e.body_text()).param("id"))?;
    Uuid::parse_str(&raw).map_err(|_| {
        Problem::bad_request(
            "invalid-parameter",
            format!("{raw:?} is not a job id (a UUID)"),
        )
        .param("id")
    })
}

async fn load(state: &AppState, id: Uuid) -> Result<JobRecord, Problem> {
    state
        .store
        .get(id)
        .await?
        .ok_or_else(|| Problem::not_found(format!("no job {id}")).param("id"))
}

async fn load_result(state: &AppState, id: Uuid) -> Result<std::sync::Arc<str>, Problem> {
    if let Some(body) = state.results.get(id) {
        return Ok(body);
    }
    let body: std::sync::Arc<str> = state
        .store
        .result(id)
        .await?
        .ok_or_else(|| Problem::internal(format!("result of job {id} is missing")))?
        .into();
    state.results.put(id, body.clone());
    Ok(body)
}

/// A body that says it is something other than JSON is refused (415); one
/// that says nothing is read as JSON, and so is curl's default for `-d`
/// (`application/x-www-form-urlencoded`), which `curl -d @spec.json` sends.
fn check_json_content_type(headers: &HeaderMap) -> Result<(), Problem> {
    let Some(value) = headers.get(header::CONTENT_TYPE) else {
        return Ok(());
    };
    let essence = value
        .to_str()
        .unwrap_or("")
        .split(';')
        .next()
        .unwrap_or("")
        .trim()
        .to_ascii_lowercase();
    if essence == "application/json"
        || essence == "application/x-www-form-urlencoded"
        || (essence.starts_with("application/") && essence.ends_with("+json"))
    {
        return Ok(());
    }
    Err(Problem::new(
        StatusCode::UNSUPPORTED_MEDIA_TYPE,
        "unsupported-media-type",
        "Unsupported media type",
        format!(
            "a job spec is JSON: send it as application/json, not {essence:?} (curl: -H 'content-type: application/json')"
        ),
    )
    .header_name("content-type"))
}

/// Seconds a client told the queue is full waits before trying again.
const RETRY_AFTER_S: u64 = 2;

/// Refuses new work while the queue is full (429 with Retry-After); work
/// already known under `key` (queued, running or done) is always answered.
async fn admit(state: &AppState, key: &str) -> Result<(), Problem> {
    let max = state.config.max_queued;
    if max == u64::MAX || (state.store.queued().await? as u64) < max {
        return Ok(());
    }
    if let Some(job) = state.store.by_key(key).await?
        && !matches!(job.status, Status::Failed | Status::Canceled)
    {
        return Ok(());
    }
    state.metrics.rejected_full.increment(1);
    Err(Problem::new(
        StatusCode::TOO_MANY_REQUESTS,
        "queue-full",
        "Queue full",
        format!("{max} jobs are waiting (max_queued); try again in {RETRY_AFTER_S} s"),
    )
    .retry_after(RETRY_AFTER_S))
}

/// The stored result document of job `id`: 404 without the job, 409 until it
/// has succeeded.
pub(crate) async fn finished_result(
    state: &AppState,
    id: Uuid,
) -> Result<std::sync::Arc<str>, Problem> {
    if let Some(body) = state.results.get(id) {
        return Ok(body);
    }
    let job = load(state, id).await?;
    match job.status {
        Status::Succeeded => load_result(state, id).await,
        Status::Failed => Err(Problem::conflict(
            "job-failed",
            format!("job {id} failed: {}", job.error.unwrap_or_default()),
        )),
        Status::Canceled => Err(Problem::conflict(
            "job-canceled",
            format!("job {id} was canceled"),
        )),
        s => Err(Problem::conflict(
            "not-finished",
            format!("job {id} is {}; poll /v1/jobs/{id}", s.as_str()),
        )),
    }
}

/// Waits until job `id` reaches a final status or `limit` passes.
async fn wait_for(state: &AppState, id: Uuid, limit: Duration) -> Result<JobRecord, Problem> {
    let deadline = Instant::now() + limit;
    let mut events = state.finished.subscribe();
    let mut stopping = state.stopping.clone();
    loop {
        let job = load(state, id).await?;
        if job.status.is_final() || Instant::now() >= deadline || *stopping.borrow() {
            return Ok(job);
        }
        // Woken by this job finishing (or the channel lagging behind), by
        // shutdown, by the deadline, or every 250 ms: look again.
        let tick = Instant::now() + Duration::from_millis(250);
        loop {
            let until = deadline.min(tick);
            tokio::select! {
                r = tokio::time::timeout_at(until.into(), events.recv()) => {
                    match r {
                        Ok(Ok(done)) if done != id => continue,
                        _ => break,
                    }
                }
                _ = stopping.changed() => break,
            }
        }
    }
}

/// Submit a job.
///
/// The body is a job spec exactly as `topple run` accepts it. An identical job
/// (same canonical spec) already done or in flight is returned instead, flagged
/// `"cached": true`, with no recomputation. With `?wait=N` the call waits up to
/// N seconds and, when the job finishes in time, returns it with its result
/// inline.
#[utoipa::path(
    post,
    path = "/v1/jobs",
    tag = "jobs",
    params(CreateQuery),
    security((), ("bearer" = [])),
    request_body(content = JobSpec, description = "A job spec", content_type = "application/json"),
    responses(
        (status = 200, description = "Done (cached, or finished within `wait`)", body = JobView),
        (status = 202, description = "Queued or running", body = JobView,
            headers(("Location" = String, description = "The job's URL"))),
        (status = 400, description = "Not JSON, or a bad query", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is configured and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 413, description = "Body too large", body = Problem, content_type = "application/problem+json"),
        (status = 415, description = "Not sent as application/json", body = Problem, content_type = "application/problem+json"),
        (status = 422, description = "Invalid spec, or over a service limit; `pointer` names the field", body = Problem, content_type = "application/problem+json"),
        (status = 429, description = "Queue full; retry after the Retry-After seconds", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn create_job(
    State(state): State<AppState>,
    headers: HeaderMap,
    query: Result<Query<CreateQuery>, QueryRejection>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, Problem> {
    check_json_content_type(&headers)?;
    let Query(query) = query
        .map_err(|e| Problem::bad_request("invalid-parameter", e.body_text()).param("wait"))?;
    let body = body.map_err(|e| {
        let status = e.status();
        if status == StatusCode::PAYLOAD_TOO_LARGE {
            let max = state.config.max_body_bytes;
            let mut p = Problem::new(
                status,
                "body-too-large",
                "Body too large",
                format!(
                    "the body is larger than this service's limit of {max} bytes (max_body_bytes)"
                ),
            )
            .at("")
            .header_name("content-length");
            p.limit = Some("max_body_bytes".into());
            p.maximum = Some(max as f64);
            p
        } else {
            Problem::new(status, "invalid-body", "Unreadable body", e.body_text()).at("")
        }
    })?;
    let wait = match query.wait {
        None => None,
        Some(w) if w.is_finite() && w >= 0.0 => Some(
            Duration::try_from_secs_f64(w)
                .unwrap_or(Duration::MAX)
                .min(state.config.max_wait),
        ),
        Some(_) => {
            return Err(Problem::bad_request(
                "invalid-parameter",
                "wait must be a non-negative number of seconds",
            )
            .param("wait"));
        }
    };
    let text = std::str::from_utf8(&body)
        .map_err(|_| Problem::bad_request("invalid-body", "the body is not UTF-8"))?;
    let job = Job::parse(text).map_err(|e| {
        let status = if e.message.starts_with("not valid JSON") {
            StatusCode::BAD_REQUEST
        } else {
            StatusCode::UNPROCESSABLE_ENTITY
        };
        let pointer = e.pointer.clone();
        Problem::new(
            status,
            "invalid-spec",
            "Invalid job spec",
            format!(
                "{}: {}",
                if pointer.is_empty() { "/" } else { &pointer },
                e.message
            ),
        )
        .at(pointer)
    })?;
    job.check_limits(&state.config.limits)
        .map_err(|e| Problem::over_limit(&e))?;
    let key = cache_key(&job);
    admit(&state, &key).await?;
    let spec = serde_json::to_string(&job).map_err(|e| Problem::internal(e.to_string()))?;
    let tasks: Vec<String> = job
        .split()
        .iter()
        .map(|t| serde_json::to_string(t).unwrap_or_default())
        .collect();
    let submitted = state
        .store
        .submit(
            new_job_id(),
            &key,
            job.kind(),
            &spec,
            &now_rfc3339(),
            &tasks,
        )
        .await?;
    let id = submitted.job.id;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    if submitted.cached {
        state.metrics.cache_hits.increment(1);
    } else {
        state.metrics.submitted.increment(1);
        state.wake.notify_waiters();
        state.wake.notify_one();
        state.store.announce_queued().await;
    }
    info!(job_id = %id, cached = submitted.cached, kind = job.kind(), "submitted");
    let mut record = submitted.job;
    if let Some(limit) = wait
        && !record.status.is_final()
    {
        record = wait_for(&state, id, limit).await?;
    }
    let mut v = view(&record, Some(submitted.cached));
    // New work is accepted (202) unless the caller waited for it; existing work
    // that is done answers 200 with its result.
    let status = if record.status == Status::Succeeded && (wait.is_some() || submitted.cached) {
        // The stored document is inlined as it is, never parsed again.
        let body = load_result(&state, id).await?;
        v.result = serde_json::value::RawValue::from_string(body.to_string()).ok();
        StatusCode::OK
    } else {
        StatusCode::ACCEPTED
    };
    let mut response = (status, axum::Json(v)).into_response();
    if let Ok(loc) = HeaderValue::from_str(&format!("/v1/jobs/{id}")) {
        response.headers_mut().insert(header::LOCATION, loc);
    }
    Ok(response)
}

/// A job's status.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}",
    tag = "jobs",
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid")),
    responses(
        (status = 200, description = "The job", body = JobView),
        (status = 400, description = "Not a job id", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn get_job(
    State(state): State<AppState>,
    path: Result<Path<String>, PathRejection>,
) -> Result<axum::Json<JobView>, Problem> {
    let id = parse_id(path)?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let job = load(&state, id).await?;
    Ok(axum::Json(view(&job, None)))
}

/// Query of a result fetch.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ResultQuery {
    /// `json` (default) or `csv` (a header row names quantities and units:
    /// series, impacts or a summary of time histories, transitions of spectra,
    /// points of friction spectra, intervals of forensic queries).
    #[param(pattern = "^(json|csv)$")]
    pub format: Option<String>,
}

/// A job's result: the same document `topple run` prints.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}/result",
    tag = "jobs",
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid"), ResultQuery),
    responses(
        (status = 200, description = "The result document (JSON, or CSV with ?format=csv)", content(
            (Object = "application/json"),
            (String = "text/csv")
        )),
        (status = 400, description = "Bad id or format, or no CSV form", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Not finished (or failed, or canceled)", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn get_result(
    State(state): State<AppState>,
    path: Result<Path<String>, PathRejection>,
    query: Result<Query<ResultQuery>, QueryRejection>,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    let Query(query) = query
        .map_err(|e| Problem::bad_request("invalid-parameter", e.body_text()).param("format"))?;
    let csv = match query.format.as_deref() {
        None | Some("json") => false,
        Some("csv") => true,
        Some(other) => {
            return Err(Problem::bad_request(
                "invalid-parameter",
                format!("format {other:?}: expected json or csv"),
            )
            .param("format"));
        }
    };
    let body = finished_result(&state, id).await?;
    if csv {
        // Parsing and rendering a large result is not work for the runtime.
        // It goes to the blocking pool rather than the compute pool, where it
        // would queue behind running spectra.
        let doc = body.clone();
        let table = tokio::task::spawn_blocking(move || {
            serde_json::from_str::<serde_json::Value>(&doc)
                .map_err(|e| e.to_string())
                .map(|v| to_csv(&v))
        })
        .await
        .map_err(|_| Problem::internal("CSV rendering stopped"))?
        .map_err(Problem::internal)?
        .map_err(|e| Problem::bad_request("no-csv", e).param("format"))?;
        return Ok(([(header::CONTENT_TYPE, "text/csv; charset=utf-8")], table).into_response());
    }
    Ok((
        [(header::CONTENT_TYPE, "application/json")],
        body.to_string(),
    )
        .into_response())
}

/// Cancel a job: running work stops within milliseconds.
#[utoipa::path(
    delete,
    path = "/v1/jobs/{id}",
    tag = "jobs",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid")),
    responses(
        (status = 200, description = "Canceled (or already canceled)", body = JobView),
        (status = 400, description = "Not a job id", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Already finished", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is configured and the request lacks it", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn cancel_job(
    State(state): State<AppState>,
    path: Result<Path<String>, PathRejection>,
) -> Result<axum::Json<JobView>, Problem> {
    let id = parse_id(path)?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let job = state
        .store
        .cancel(id, &now_rfc3339())
        .await?
        .ok_or_else(|| Problem::not_found(format!("no job {id}")).param("id"))?;
    match job.status {
        Status::Canceled => {
            state.cancel_local(id);
            let _ = state.finished.send(id);
            info!(job_id = %id, "canceled");
            Ok(axum::Json(view(&job, None)))
        }
        s => Err(Problem::conflict(
            "already-finished",
            format!("job {id} already {}", s.as_str()),
        )),
    }
}

/// Query of a listing.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ListParams {
    /// Only jobs with this status.
    #[param(value_type = Option<Status>)]
    pub status: Option<String>,
    /// Only jobs of this kind.
    #[param(pattern = "^(time_history|spectrum|friction_spectrum)$")]
    pub kind: Option<String>,
    /// At most this many (1..=500, default 50).
    #[param(minimum = 1, maximum = 500)]
    pub limit: Option<u32>,
    /// The `next_cursor` of the previous page (empty: the first page).
    #[param(
        pattern = "^$|^[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}$"
    )]
    pub cursor: Option<String>,
}

/// A page of jobs.
#[derive(Debug, Serialize, ToSchema)]
pub struct JobPage {
    /// Newest first.
    pub jobs: Vec<JobView>,
    /// Pass as `cursor` for the next page; null on the last.
    pub next_cursor: Option<String>,
}

/// List jobs, newest first, with cursor pagination.
#[utoipa::path(
    get,
    path = "/v1/jobs",
    tag = "jobs",
    params(ListParams),
    responses(
        (status = 200, description = "A page of jobs", body = JobPage),
        (status = 400, description = "Bad parameter", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn list_jobs(
    State(state): State<AppState>,
    query: Result<Query<ListParams>, QueryRejection>,
) -> Result<axum::Json<JobPage>, Problem> {
    let Query(q) = query.map_err(|e| Problem::bad_request("invalid-parameter", e.body_text()))?;
    let status = match q.status.as_deref() {
        None => None,
        Some(s) => Some(Status::parse(s).ok_or_else(|| {
            Problem::bad_request(
                "invalid-parameter",
                format!("status {s:?}: expected queued, running, succeeded, failed or canceled"),
            )
            .param("status")
        })?),
    };
    if let Some(k) = q.kind.as_deref()
        && !KINDS.contains(&k)
    {
        return Err(Problem::bad_request(
            "invalid-parameter",
            format!("kind {k:?}: expected one of {}", KINDS.join(", ")),
        )
        .param("kind"));
    }
    let limit = q.limit.unwrap_or(50);
    if !(1..=500).contains(&limit) {
        return Err(Problem::bad_request(
            "invalid-parameter",
            "limit must satisfy 1 <= limit <= 500",
        )
        .param("limit"));
    }
    let before = match q.cursor.as_deref() {
        None | Some("") => None,
        Some(c) => Some(Uuid::parse_str(c).map_err(|_| {
            Problem::bad_request("invalid-parameter", "cursor is not one this API returned")
                .param("cursor")
        })?),
    };
    let jobs = state
        .store
        .list(&ListQuery {
            status,
            kind: q.kind.clone(),
            limit,
            before,
        })
        .await?;
    let next_cursor = if jobs.len() as u32 == limit {
        jobs.last().map(|j| j.id.to_string())
    } else {
        None
    };
    Ok(axum::Json(JobPage {
        jobs: jobs.iter().map(|j| view(j, None)).collect(),
        next_cursor,
    }))
}
