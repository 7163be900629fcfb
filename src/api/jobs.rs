//! `/v1/jobs`: submit, inspect, fetch results, cancel, list.

use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::body::{Body, Bytes};
use axum::extract::rejection::{BytesRejection, PathRejection};
use axum::extract::{Extension, Path, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use tracing::info;
use utoipa::{IntoParams, ToSchema};
use uuid::Uuid;

use super::auth::Tenant;
use super::http::Query;
use super::problem::Problem;
use super::representation::Format;
use crate::kinds::{Job, JobSpec, KINDS};
use crate::service::AppState;
use crate::service::finished::{ResultError, finished};
use crate::service::inline::{self, Inline};
use crate::service::renderings::Rendering;
use crate::service::results::{Cached, SharedText};
use crate::service::submit::{self, Prepared};
use crate::service::succeeded::{Read, Rendered, read};
use crate::store::{Deleted, JobRecord, ListQuery, NewJob, Status, new_job_id, now_rfc3339};

/// Links of a job.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct Links {
    /// This job (GET: status; `?wait=N` long-polls).
    #[serde(rename = "self")]
    pub this: String,
    /// Its result document (JSON).
    pub result: String,
    /// Its result as CSV.
    pub csv: String,
    /// Its result as a figure (SVG).
    pub plot: String,
    /// Its status as Server-Sent Events.
    pub events: String,
    /// DELETE cancels it while queued or running and deletes it once
    /// finished; `POST {self}/cancel` only ever cancels.
    pub cancel: String,
}

impl Links {
    fn of(id: Uuid) -> Self {
        let this = format!("/v1/jobs/{id}");
        Links {
            result: format!("{this}/result"),
            csv: format!("{this}/result?format=csv"),
            plot: format!("{this}/plot.svg"),
            events: format!("{this}/events"),
            cancel: this.clone(),
            this,
        }
    }
}

/// What a job will take: its simulations and the time they are expected to
/// take on this instance, from the rate it has measured.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct Estimate {
    /// Simulations the job needs (estimated for scans: grid plus
    /// bisections, of a few transitions a line under a pulse and of most
    /// scan points under a record).
    pub simulations: f64,
    /// Expected compute time on this instance, s: the CPU time of its
    /// simulations (by pulse shape, formulation and method, or by the
    /// shaking part of its record) over the threads it can use, at the rate
    /// this instance measured for its kind.
    pub seconds: f64,
    /// `seconds` over `simulations`.
    pub seconds_per_simulation: f64,
    /// What the estimate is made of: the kind's model, or a sample of the
    /// job's own work run at submission (a record spectrum, or a forensic
    /// query under a record, of at least 10 model CPU seconds: brackets of
    /// its scans, bisected as the scan will, 2 % of the job's CPU time and
    /// at most two CPU seconds over two threads).
    pub basis: EstimateBasis,
}

/// What an estimate is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum EstimateBasis {
    /// The kind's model of its cost ([`crate::jobs::cost`]).
    Model,
    /// A sample of the job's work, run at submission.
    Sample,
}

/// A job as the API shows it.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct JobView {
    /// Identifier (UUIDv7).
    #[schema(format = "uuid")]
    pub id: String,
    /// The job's kind.
    #[schema(value_type = crate::kinds::JobKind)]
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
    #[schema(format = DateTime)]
    pub created_at: String,
    /// RFC 3339.
    #[schema(format = DateTime, required = true)]
    pub started_at: Option<String>,
    /// RFC 3339.
    #[schema(format = DateTime, required = true)]
    pub finished_at: Option<String>,
    /// Why it failed.
    #[schema(required = true)]
    pub error: Option<String>,
    /// The numerics summary of the result, once done (its `numerics`).
    #[schema(value_type = Option<Object>, required = true)]
    pub numerics: Option<serde_json::Value>,
    /// The normalised spec (in listings only with `?include=spec`).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::kinds::NormalizedSpec>)]
    pub spec: Option<Box<serde_json::value::RawValue>>,
    /// Links.
    pub links: Links,
    /// On submission: the simulations the job needs and the time expected.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub estimate: Option<Estimate>,
    /// The result, inline, when `?wait=` saw the job finish (or a submission
    /// found it done).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::kinds::JobResult>)]
    pub result: Option<Box<serde_json::value::RawValue>>,
}

pub(crate) fn view(r: &JobRecord, cached: Option<bool>) -> JobView {
    let mut v = summary(r, cached);
    // The stored text as it is: a spec may hold a long record, several times
    // its text once parsed.
    v.spec = serde_json::value::RawValue::from_string(r.spec.clone())
        .or_else(|_| serde_json::value::RawValue::from_string("null".into()))
        .ok();
    v
}

/// A job without its spec (listings).
pub(crate) fn summary(r: &JobRecord, cached: Option<bool>) -> JobView {
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
        spec: None,
        links: Links::of(r.id),
        estimate: None,
        result: None,
    }
}

/// The weak entity tag of a job's status: it changes with status, progress
/// and outcome.
pub(crate) fn status_etag(r: &JobRecord) -> String {
    let mut h = blake3::Hasher::new();
    h.update(r.id.as_bytes());
    h.update(r.status.as_str().as_bytes());
    h.update(&((r.progress * 1e4).round() as i64).to_le_bytes());
    h.update(r.finished_at.as_deref().unwrap_or("").as_bytes());
    h.update(r.error.as_deref().unwrap_or("").as_bytes());
    format!("W/\"{}\"", &h.finalize().to_hex()[..24])
}

/// A `wait` parameter as a duration, capped by the service's `max_wait`.
fn wait_duration(state: &AppState, wait: Option<f64>) -> Result<Option<Duration>, Problem> {
    match wait {
        None => Ok(None),
        Some(w) if w.is_finite() && w >= 0.0 => Ok(Some(
            Duration::try_from_secs_f64(w)
                .unwrap_or(Duration::MAX)
                .min(state.config.max_wait),
        )),
        Some(_) => Err(Problem::bad_request(
            "invalid-parameter",
            "wait must be a non-negative number of seconds",
        )
        .param("wait")),
    }
}

/// Longest spec, in bytes, [`poll_after`] parses for its work estimate.
const SMALL_SPEC: usize = 16 * 1024;

/// Seconds a poller of job `r` should wait: from its estimated remaining work
/// at this instance's measured rate.
fn poll_after(state: &AppState, r: &JobRecord) -> u64 {
    // A time history is one simulation; a spec holding records (a record
    // spectrum's, a forensic query's on a record, a fragility campaign's
    // suite) is not worth parsing on the runtime for each poll: its work is
    // taken as one simulation too, and the client polls at the shortest
    // interval. The other specs are small.
    let one = crate::jobs::kind::Size::one(1e-3);
    let work = if r.kind == "time_history" || r.spec.len() > SMALL_SPEC {
        one
    } else {
        serde_json::from_str::<serde_json::Value>(&r.spec)
            .ok()
            .and_then(|v| Job::from_value(&v).ok())
            .map_or(one, |job| job.size())
    };
    let left = 1.0 - r.progress.clamp(0.0, 1.0);
    super::http::poll_interval(state.throughput.seconds(&r.kind, &work) * left)
}

/// Query of a submission.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
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

/// No job `id` for the tenant asking.
fn no_job(id: Uuid) -> Problem {
    Problem::not_found(format!("no job {id}")).param("id")
}

/// The tenant's job `id`; another tenant's job is not found, as if it did
/// not exist (a 403 would confirm that it does).
pub(crate) async fn load(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
) -> Result<JobRecord, Problem> {
    state
        .store
        .get(tenant.name(), id)
        .await?
        .ok_or_else(|| no_job(id))
}

/// The status document of succeeded job `r` as served, with its entity tag.
fn render_status(r: &JobRecord) -> Result<Rendered, Problem> {
    let body = serde_json::to_vec(&view(r, None))
        .map_err(|e| Problem::internal(format!("status document: {e}")))?;
    Ok(Rendered {
        etag: status_etag(r),
        body: body.into(),
    })
}

/// A status document already rendered, or 304 when the client holds it.
fn rendered_status(status: &Rendered, headers: &HeaderMap) -> Response {
    if super::http::if_none_match(headers, &status.etag) {
        return super::http::not_modified(&status.etag, super::http::REVALIDATE);
    }
    let mut r = (
        [(header::CONTENT_TYPE, "application/json")],
        Body::from(Bytes::from_owner(status.body.clone())),
    )
        .into_response();
    super::http::set_validators(r.headers_mut(), &status.etag, super::http::REVALIDATE);
    r
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

/// The stored result document of job `id`: 404 without the job, 409 until it
/// has succeeded (with when to look again).
pub(crate) async fn finished_result(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
) -> Result<Cached, Problem> {
    finished(state, tenant.name(), id)
        .await
        .map_err(|e| match e {
            ResultError::NotFinished(job) => {
                let after = poll_after(state, &job);
                Problem::from(ResultError::NotFinished(job)).retry_after(after)
            }
            e => e.into(),
        })
}

/// Waits until the tenant's job `id` reaches a final status or `limit` passes.
async fn wait_for(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
    limit: Duration,
) -> Result<JobRecord, Problem> {
    let deadline = Instant::now() + limit;
    let mut events = state.finished.subscribe();
    let mut stopping = state.stopping.clone();
    loop {
        let job = load(state, tenant, id).await?;
        if job.status.is_final() || Instant::now() >= deadline || *stopping.borrow() {
            return Ok(job);
        }
        // Answered by the announcement of its computation's success (the
        // job as the store now holds it), or woken by its other end (or the
        // channel lagging behind), by shutdown, by the deadline, or every
        // 250 ms: look again.
        let tick = Instant::now() + Duration::from_millis(250);
        loop {
            let until = deadline.min(tick);
            tokio::select! {
                r = tokio::time::timeout_at(until.into(), events.recv()) => {
                    match r {
                        Ok(Ok(done)) if done.computation != job.computation => continue,
                        Ok(Ok(done)) => match done.apply(&job) {
                            Some(finished) => return Ok(finished),
                            None => break,
                        },
                        _ => break,
                    }
                }
                _ = stopping.changed() => break,
            }
        }
    }
}

/// Whether the body was cut off by the body read deadline.
pub(crate) fn body_timed_out(e: &BytesRejection) -> bool {
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = cause {
        if err.is::<tower_http::timeout::TimeoutError>() {
            return true;
        }
        cause = err.source();
    }
    false
}

/// 408 for a body that came too slowly; the connection closes after it (the
/// rest of the body is never read).
pub(crate) fn body_timeout(state: &AppState) -> Response {
    state.metrics.body_timeouts.increment(1);
    let limit = state.config.body_read_timeout.as_secs_f64();
    let mut p = Problem::new(
        StatusCode::REQUEST_TIMEOUT,
        "body-timeout",
        "Body too slow",
        format!(
            "the body did not arrive within this service's limit of {limit} s (body_read_timeout)"
        ),
    )
    .at("");
    p.limit = Some("body_read_timeout".into());
    p.maximum = Some(limit);
    let mut response = p.into_response();
    response
        .headers_mut()
        .insert(header::CONNECTION, HeaderValue::from_static("close"));
    response
}

/// The problem with an unreadable body: too large (413), or otherwise broken.
pub(crate) fn body_problem(state: &AppState, e: &BytesRejection) -> Problem {
    let status = e.status();
    if status == StatusCode::PAYLOAD_TOO_LARGE {
        Problem::body_too_large(state.config.max_body_bytes)
    } else {
        Problem::new(status, "invalid-body", "Unreadable body", e.body_text()).at("")
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
    operation_id = "create_job",
    params(CreateQuery),
    security((), ("bearer" = [])),
    request_body(content = JobSpec, description = "A job spec", content_type = "application/json"),
    responses(
        (status = 200, description = "Done (cached, or finished within `wait`)", body = JobView),
        (status = 202, description = "Queued or running", body = JobView,
            headers(("Location" = String, description = "The job's URL"))),
        (status = 400, description = "Not JSON, or a bad query", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is configured and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 408, description = "The body did not arrive within the service's limit (body_read_timeout); the connection is closed", body = Problem, content_type = "application/problem+json"),
        (status = 413, description = "Body too large", body = Problem, content_type = "application/problem+json"),
        (status = 415, description = "Not sent as application/json", body = Problem, content_type = "application/problem+json"),
        (status = 422, description = "Invalid spec, or over a service limit; `pointer` names the field", body = Problem, content_type = "application/problem+json"),
        (status = 429, description = "Queue full; retry after the Retry-After seconds", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
        (status = 503, description = "The database is unavailable; nothing was saved", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
        (status = 507, description = "The service's storage is full; nothing was saved", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn create_job(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    headers: HeaderMap,
    query: Result<Query<CreateQuery>, Problem>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, Problem> {
    check_json_content_type(&headers)?;
    let Query(query) = query?;
    let body = match body {
        Ok(body) => body,
        Err(e) if body_timed_out(&e) => return Ok(body_timeout(&state)),
        Err(e) => return Err(body_problem(&state, &e)),
    };
    let wait = wait_duration(&state, query.wait)?;
    let prepared = submit::prepare(&state, tenant.name(), body).await?;
    // A small job waited for may be computed in this request (which then
    // admits it too); any other is admitted, sized, stored and waited for.
    let small = wait.filter(|w| !w.is_zero() && inline::offered(&state, &prepared));
    let (prepared, record, cached, wait, body) = if let Some(limit) = small {
        match inline::run(&state, tenant.name(), &prepared, limit).await? {
            Inline::Done(record, body) => {
                super::http::audit("submit", &tenant, record.id, &headers);
                (prepared, *record, false, Some(limit), Some(body))
            }
            Inline::Declined(left) => {
                let (record, cached) =
                    submit_and_wait(&state, &tenant, &headers, &prepared, Some(left)).await?;
                (prepared, record, cached, Some(left), None)
            }
        }
    } else {
        let admission = submit::admit(&state, tenant.name(), &prepared.key).await?;
        let prepared = submit::sample(&state, prepared, admission.as_ref()).await?;
        let (record, cached) = submit_and_wait(&state, &tenant, &headers, &prepared, wait).await?;
        (prepared, record, cached, wait, None)
    };
    let id = record.id;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let (kind, size) = (prepared.job.kind(), &prepared.size);
    let mut v = view(&record, Some(cached));
    let seconds = if prepared.sampled {
        state.throughput.seconds_measured(size)
    } else {
        state.throughput.seconds(kind, size)
    };
    v.estimate = Some(Estimate {
        simulations: size.work,
        seconds,
        seconds_per_simulation: seconds / size.work.max(1.0),
        basis: if prepared.sampled {
            EstimateBasis::Sample
        } else {
            EstimateBasis::Model
        },
    });
    // New work is accepted (202) unless the caller waited for it; existing work
    // that is done, and work waited for that ended (succeeded, failed or
    // canceled), answers 200.
    let status = if record.status.is_final() && (wait.is_some() || cached) {
        if record.status == Status::Succeeded {
            // The stored document is inlined as it is, never parsed again.
            let text = match body {
                Some(body) => body,
                None => crate::service::finished::stored(&state, &record)
                    .await?
                    .body
                    .as_str()
                    .to_string(),
            };
            v.result = serde_json::value::RawValue::from_string(text).ok();
        }
        StatusCode::OK
    } else {
        StatusCode::ACCEPTED
    };
    let mut response = (status, axum::Json(v)).into_response();
    if let Ok(loc) = HeaderValue::from_str(&format!("/v1/jobs/{id}")) {
        response.headers_mut().insert(header::LOCATION, loc);
    }
    if status == StatusCode::ACCEPTED {
        response.headers_mut().insert(
            header::RETRY_AFTER,
            HeaderValue::from(poll_after(&state, &record)),
        );
    }
    Ok(response)
}

/// Stores the tenant's prepared job (or finds its own, or joins the
/// computation of its key) and wakes workers for the work it queued; then,
/// with `wait`, waits for it to finish. The job, and whether existing work
/// answered it.
async fn submit_and_wait(
    state: &AppState,
    tenant: &Tenant,
    headers: &HeaderMap,
    prepared: &Prepared,
    wait: Option<Duration>,
) -> Result<(JobRecord, bool), Problem> {
    let submitted = state
        .store
        .submit(NewJob {
            tenant: tenant.name(),
            id: new_job_id(),
            key: &prepared.key,
            kind: prepared.job.kind(),
            spec: &prepared.spec,
            now: &now_rfc3339(),
            tasks: &prepared.tasks,
            records: &prepared.records,
        })
        .await?;
    let id = submitted.job.id;
    super::http::audit("submit", tenant, id, headers);
    if submitted.cached {
        state.metrics.cache_hits.increment(1);
    } else {
        state.metrics.submitted.increment(1);
        // One idle worker woken per task queued, each claims one.
        for _ in 0..prepared.tasks.len().min(state.config.workers.max(1)) {
            state.wake.notify_one();
        }
        state.store.announce_queued().await;
    }
    info!(job_id = %id, cached = submitted.cached, kind = prepared.job.kind(), "submitted");
    let mut record = submitted.job;
    if let Some(limit) = wait
        && !record.status.is_final()
    {
        record = wait_for(state, tenant, id, limit).await?;
    }
    Ok((record, submitted.cached))
}

/// Query of a status read.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct JobQuery {
    /// Long-poll: wait up to this many seconds (capped as for POST) for the job
    /// to finish, or, with `If-None-Match`, for its status to change.
    #[param(minimum = 0)]
    pub wait: Option<f64>,
}

/// A job's status.
///
/// Carries a weak `ETag` that changes with status and progress: a poller that
/// sends it back as `If-None-Match` gets a bodiless 304 while nothing changed.
/// With `?wait=N` the call returns as soon as the job is finished (or, with
/// `If-None-Match`, as soon as its status differs), or after N seconds.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}",
    tag = "jobs",
    operation_id = "get_job",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid"), JobQuery,
        ("If-None-Match" = Option<String>, Header, description = "The ETag of a status already seen")),
    responses(
        (status = 200, description = "The job", body = JobView,
            headers(("ETag" = String, description = "Changes with status and progress"),
                    ("Retry-After" = Option<String>, description = "While unfinished: seconds until a poll is worthwhile"))),
        (status = 304, description = "Unchanged since the ETag sent in If-None-Match"),
        (status = 400, description = "Not a job id, or a bad or unknown query parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn get_job(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<JobQuery>, Problem>,
    headers: HeaderMap,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    let Query(q) = q?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let wait = wait_duration(&state, q.wait)?;
    let mut job = match read(&state, tenant.name(), id).await? {
        None => return Err(no_job(id)),
        Some(Read::Other(job)) => *job,
        // A succeeded job's document is made once. Only a long poll for a
        // change of it waits, as for any job (only its deletion ends it).
        Some(Read::Succeeded(done)) => {
            let status = match done.status.get() {
                Some(status) => status,
                None => {
                    let rendered = render_status(&done.record)?;
                    done.status.get_or_init(|| rendered)
                }
            };
            if wait.is_none() || !super::http::if_none_match(&headers, &status.etag) {
                return Ok(rendered_status(status, &headers));
            }
            done.record.clone()
        }
    };
    if let Some(limit) = wait {
        let seen = super::http::if_none_match(&headers, &status_etag(&job));
        if seen || !job.status.is_final() {
            job = wait_for_change(&state, &tenant, id, limit, seen).await?;
        }
    }
    let etag = status_etag(&job);
    if super::http::if_none_match(&headers, &etag) {
        let mut r = super::http::not_modified(&etag, super::http::REVALIDATE);
        if !job.status.is_final() {
            r.headers_mut().insert(
                header::RETRY_AFTER,
                HeaderValue::from(poll_after(&state, &job)),
            );
        }
        return Ok(r);
    }
    let mut r = axum::Json(view(&job, None)).into_response();
    super::http::set_validators(r.headers_mut(), &etag, super::http::REVALIDATE);
    if !job.status.is_final() {
        r.headers_mut().insert(
            header::RETRY_AFTER,
            HeaderValue::from(poll_after(&state, &job)),
        );
    }
    Ok(r)
}

/// Waits up to `limit` for job `id` to finish, or, when `on_any_change`, for
/// its status ETag to change.
async fn wait_for_change(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
    limit: Duration,
    on_any_change: bool,
) -> Result<JobRecord, Problem> {
    if !on_any_change {
        return wait_for(state, tenant, id, limit).await;
    }
    let deadline = Instant::now() + limit;
    let first = status_etag(&load(state, tenant, id).await?);
    let mut stopping = state.stopping.clone();
    loop {
        let job = load(state, tenant, id).await?;
        if status_etag(&job) != first || Instant::now() >= deadline || *stopping.borrow() {
            return Ok(job);
        }
        let tick = (Instant::now() + Duration::from_millis(100)).min(deadline);
        tokio::select! {
            _ = tokio::time::sleep_until(tick.into()) => {}
            _ = stopping.changed() => {}
        }
    }
}

/// Query of a result fetch.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct ResultQuery {
    /// `json` (default), `csv` (a header row names quantities and units:
    /// series, impacts or a summary of time histories, transitions of spectra,
    /// points of friction spectra, intervals of forensic queries) or `svg`
    /// (the figure). Without it, the `Accept` header chooses: `text/csv`,
    /// `image/svg+xml`, else JSON.
    #[param(pattern = "^(json|csv|svg)$")]
    pub format: Option<String>,
}

/// The result in `format`, with its entity tag and cache headers; a matching
/// `If-None-Match` gets a 304 without rendering anything.
pub(crate) async fn result_response(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
    format: Format,
    headers: &HeaderMap,
) -> Result<Response, Problem> {
    let found = finished_result(state, tenant, id).await?;
    let etag = super::http::result_etag(&found.key, &format.name());
    let cache = super::http::immutable(state.config.reads_need_token());
    if super::http::if_none_match(headers, &etag) {
        return Ok(super::http::not_modified(&etag, cache));
    }
    let body = found.body;
    let mut response = match format {
        // The stored text as it is: neither parsed nor copied.
        Format::Json => (
            [(header::CONTENT_TYPE, "application/json")],
            Body::from(Bytes::from_owner(SharedText(body))),
        )
            .into_response(),
        Format::Csv => super::representation::csv_response(state, id, &found.key, body).await?,
        Format::Svg(window) => {
            let name = format.name();
            let figure = match state.renderings.get(&found.key, &name) {
                Some(held) => held,
                None => {
                    let figure = super::representation::figure(state, body, window).await?;
                    let made = Arc::new(Rendering {
                        body: figure.into_bytes().into(),
                        kind: String::new(),
                    });
                    state.renderings.put(&found.key, &name, made.clone());
                    made
                }
            };
            (
                [(header::CONTENT_TYPE, "image/svg+xml")],
                Body::from(Bytes::from_owner(figure.body.clone())),
            )
                .into_response()
        }
    };
    super::http::set_validators(response.headers_mut(), &etag, cache);
    Ok(response)
}

/// A job's result: the same document `topple run` prints.
///
/// Results never change: each representation has a strong `ETag` (from the
/// job's cache key, which includes the engine version) and
/// `Cache-Control: immutable`; `If-None-Match` answers 304.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}/result",
    tag = "jobs",
    operation_id = "get_result",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid"), ResultQuery,
        ("If-None-Match" = Option<String>, Header, description = "The ETag of the representation already held")),
    responses(
        (status = 200, description = "The result document (JSON), or CSV or SVG by ?format= or Accept", content(
            (crate::kinds::JobResult = "application/json"),
            (crate::jobs::schema::CsvTable = "text/csv"),
            (crate::jobs::schema::SvgFigure = "image/svg+xml")
        ), headers(("ETag" = String, description = "Strong: the job key and the format"),
                   ("Cache-Control" = String, description = "immutable"),
                   ("Content-Disposition" = Option<String>, description = "CSV: a file name"))),
        (status = 304, description = "Unchanged (it never changes)"),
        (status = 400, description = "Bad id or format, an unknown parameter, or no CSV form", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Not finished (Retry-After says when to look again), failed, or canceled; or, for CSV and SVG, a stored result this engine cannot read (`result-unreadable`, naming the field: submit the spec again)", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = Option<String>, description = "Seconds until a poll is worthwhile"))),
        (status = 503, description = "Busy: the memory for large results (result_memory) or the rendering turns stayed taken for 10 s, or the database is unavailable", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn get_result(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<ResultQuery>, Problem>,
    headers: HeaderMap,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    let Query(q) = q?;
    let format = Format::negotiate(q.format.as_deref(), &headers)?;
    result_response(&state, &tenant, id, format, &headers).await
}

/// Cancel a job, or delete a finished one.
///
/// A queued or running job is canceled (200 with the job): its computation
/// stops within milliseconds unless another tenant's job over the same
/// computation still needs it. A finished job (succeeded, failed or canceled)
/// is deleted (204): gone from listings, its id answers 404, and its result is
/// purged once no job refers to it.
#[utoipa::path(
    delete,
    path = "/v1/jobs/{id}",
    tag = "jobs",
    operation_id = "cancel_job",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid")),
    responses(
        (status = 200, description = "Canceled", body = JobView),
        (status = 204, description = "Deleted: the job had finished"),
        (status = 400, description = "Not a job id", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is needed and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job (of this tenant)", body = Problem, content_type = "application/problem+json"),
        (status = 503, description = "The database is unavailable; nothing changed", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn cancel_job(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    headers: HeaderMap,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<super::http::NoQuery>, Problem>,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    q?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let job = match cancel(&state, &tenant, id, &headers).await? {
        Ok(canceled) => return Ok(axum::Json(view(&canceled, None)).into_response()),
        Err(finished) => finished,
    };
    match state.store.delete(tenant.name(), id).await? {
        Deleted::Gone => {
            super::http::audit("delete", &tenant, id, &headers);
            info!(job_id = %id, status = job.status.as_str(), "deleted");
            Ok(StatusCode::NO_CONTENT.into_response())
        }
        Deleted::NotFound => Err(no_job(id)),
        // Queued again (resubmitted) between the two steps: it stays.
        Deleted::NotFinished(job) => Err(Problem::conflict(
            "not-finished",
            format!("job {id} is {} again; cancel it first", job.status.as_str()),
        )),
    }
}

/// Cancels the tenant's job `id` if it is queued or running: `Ok` with the
/// job canceled, `Err` with the job as it was if it had finished already.
async fn cancel(
    state: &AppState,
    tenant: &Tenant,
    id: Uuid,
    headers: &HeaderMap,
) -> Result<Result<JobRecord, JobRecord>, Problem> {
    let canceled = state
        .store
        .cancel(tenant.name(), id, &now_rfc3339())
        .await?
        .ok_or_else(|| no_job(id))?;
    if !canceled.changed {
        return Ok(Err(canceled.job));
    }
    let job = canceled.job;
    if canceled.stopped {
        state.cancel_local(job.computation);
    }
    // Whoever waits on this job looks again.
    state
        .finished
        .announce(crate::store::Finished::ended(job.computation));
    super::http::audit("cancel", tenant, id, headers);
    info!(job_id = %id, computation_stopped = canceled.stopped, "canceled");
    Ok(Ok(job))
}

/// Cancel a job, never delete it.
///
/// As `DELETE /v1/jobs/{id}` on a queued or running job; a job that finished
/// meanwhile is left as it is (409), never deleted.
#[utoipa::path(
    post,
    path = "/v1/jobs/{id}/cancel",
    tag = "jobs",
    operation_id = "cancel_only",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid")),
    responses(
        (status = 200, description = "Canceled", body = JobView),
        (status = 400, description = "Not a job id", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is needed and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job (of this tenant)", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Already finished", body = Problem, content_type = "application/problem+json"),
        (status = 503, description = "The database is unavailable; nothing changed", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn cancel_only(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    headers: HeaderMap,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<super::http::NoQuery>, Problem>,
) -> Result<axum::Json<JobView>, Problem> {
    let id = parse_id(path)?;
    q?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    match cancel(&state, &tenant, id, &headers).await? {
        Ok(job) => Ok(axum::Json(view(&job, None))),
        Err(job) => Err(Problem::conflict(
            "already-finished",
            format!("job {id} already {}", job.status.as_str()),
        )),
    }
}

/// The most jobs one page of a listing holds (`limit`).
pub const MAX_LIST_LIMIT: u32 = 500;

/// Query of a listing.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct ListParams {
    /// Only jobs with this status.
    #[param(value_type = Option<Status>)]
    pub status: Option<String>,
    /// Only jobs of this kind.
    #[param(value_type = Option<crate::kinds::JobKind>)]
    pub kind: Option<String>,
    /// At most this many (1..=500, default 50).
    #[param(minimum = 1, maximum = 500)]
    pub limit: Option<u32>,
    /// The `next_cursor` of the previous page (empty: the first page).
    #[param(
        pattern = "^$|^[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}$"
    )]
    pub cursor: Option<String>,
    /// `spec`: each job with its normalised spec (listings are light
    /// summaries without it by default).
    #[param(pattern = "^spec$")]
    pub include: Option<String>,
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
///
/// Each job is a light summary (no spec, no result) unless `?include=spec`.
/// The next page is both `next_cursor` and a `Link: <…>; rel="next"` header.
#[utoipa::path(
    get,
    path = "/v1/jobs",
    tag = "jobs",
    operation_id = "list_jobs",
    security((), ("bearer" = [])),
    params(ListParams),
    responses(
        (status = 200, description = "A page of jobs", body = JobPage,
            headers(("Link" = Option<String>, description = "The next page: <url>; rel=\"next\""))),
        (status = 400, description = "Bad parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn list_jobs(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    q: Result<Query<ListParams>, Problem>,
) -> Result<Response, Problem> {
    let Query(q) = q?;
    let with_spec = match q.include.as_deref() {
        None => false,
        Some("spec") => true,
        Some(other) => {
            return Err(Problem::bad_request(
                "invalid-parameter",
                format!("include {other:?}: expected spec"),
            )
            .param("include"));
        }
    };
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
    if !(1..=MAX_LIST_LIMIT).contains(&limit) {
        return Err(Problem::bad_request(
            "invalid-parameter",
            format!("limit must satisfy 1 <= limit <= {MAX_LIST_LIMIT}"),
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
        .list(
            tenant.name(),
            &ListQuery {
                status,
                kind: q.kind.clone(),
                limit,
                before,
            },
        )
        .await?;
    let next_cursor = if jobs.len() as u32 == limit {
        jobs.last().map(|j| j.id.to_string())
    } else {
        None
    };
    let link = next_cursor.as_ref().map(|c| {
        let mut url = format!("/v1/jobs?limit={limit}&cursor={c}");
        if let Some(s) = status {
            url.push_str(&format!("&status={}", s.as_str()));
        }
        if let Some(k) = &q.kind {
            url.push_str(&format!("&kind={k}"));
        }
        if with_spec {
            url.push_str("&include=spec");
        }
        format!("<{url}>; rel=\"next\"")
    });
    let page = JobPage {
        jobs: jobs
            .iter()
            .map(|j| {
                if with_spec {
                    view(j, None)
                } else {
                    summary(j, None)
                }
            })
            .collect(),
        next_cursor,
    };
    let mut r = axum::Json(page).into_response();
    if let Some(v) = link.and_then(|l| HeaderValue::from_str(&l).ok()) {
        r.headers_mut().insert(header::LINK, v);
    }
    Ok(r)
}
