//! `/v1/records`: upload an accelerogram file as it is (PEER AT2, CSV or
//! whitespace columns, JSON), read it back, list, delete. Jobs name a stored
//! record by id (`"ground_motion": {"record": id}`).

use axum::body::Body;
use axum::extract::rejection::PathRejection;
use axum::extract::{Extension, Path, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use utoipa::{IntoParams, ToSchema};
use uuid::Uuid;

use super::auth::Tenant;
use super::http::Query;
use super::problem::Problem;
use crate::records::{OptionTexts, ReadOptions, RecordMeta};
use crate::service::AppState;
use crate::service::records::is_record_id;
use crate::store::now_rfc3339;
use crate::store::records::{NewRecord, RecordDeleted, RecordRow};

/// Query of an upload.
#[derive(Debug, Default, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct UploadQuery {
    /// The file's format; detected from its content when absent.
    #[param(pattern = "^(at2|csv|txt|json)$")]
    pub format: Option<String>,
    /// The samples' unit: `g` | `m/s2` | `cm/s2` (also `gal`, `m/s^2`, …);
    /// required unless the file states it (an AT2 header, a column named
    /// `acc_g`, a JSON `unit`).
    #[param(value_type = Option<crate::jobs::schema::UnitInput>)]
    pub unit: Option<String>,
    /// Sampling interval, s: required for one column without a time column.
    #[param(minimum = 1e-5, maximum = 1.0)]
    pub dt: Option<f64>,
    /// The time column: a 1-based index or a header name.
    #[param(min_length = 1, max_length = 200)]
    pub time_column: Option<String>,
    /// The acceleration column: a 1-based index or a header name.
    #[param(min_length = 1, max_length = 200)]
    pub acc_column: Option<String>,
    /// The record's name (default: from the file).
    #[param(max_length = 200)]
    pub name: Option<String>,
    /// `true`: a PGA above 5 g in the stated unit is intended (otherwise it is
    /// refused as a likely unit mistake).
    pub allow_large_pga: Option<bool>,
}

/// Links of a record.
#[derive(Clone, Debug, Serialize, Deserialize, ToSchema)]
pub struct RecordLinks {
    /// This record's metadata (DELETE removes it).
    #[serde(rename = "self")]
    pub this: String,
    /// Its samples as a job spec's `ground_motion` (`dt`, `acc` in m/s²).
    pub json: String,
    /// Its samples as CSV (`t_s,acc_m_s2`).
    pub csv: String,
}

/// A stored record as the API shows it.
#[derive(Clone, Debug, Serialize, Deserialize, ToSchema)]
pub struct RecordView {
    /// Its id: derived from dt and the samples in m/s², so the same motion
    /// uploaded as AT2, CSV or JSON has the same id. Name it in a job spec
    /// as `"ground_motion": {"record": id}`.
    #[schema(pattern = "^[0-9a-f]{32}$")]
    pub id: String,
    /// What was read.
    #[serde(flatten)]
    pub meta: RecordMeta,
    /// RFC 3339: when this tenant uploaded it.
    #[schema(format = DateTime)]
    pub created_at: String,
    /// Links.
    pub links: RecordLinks,
}

impl RecordView {
    fn of(row: &RecordRow) -> Result<Self, Problem> {
        let meta: RecordMeta = serde_json::from_str(&row.meta).map_err(|e| {
            Problem::internal(format!("record {}'s metadata is unreadable: {e}", row.id))
        })?;
        let this = format!("/v1/records/{}", row.id);
        Ok(RecordView {
            id: row.id.clone(),
            meta: RecordMeta {
                name: row.name.clone(),
                ..meta
            },
            created_at: row.created_at.clone(),
            links: RecordLinks {
                json: format!("{this}?format=json"),
                csv: format!("{this}?format=csv"),
                this,
            },
        })
    }
}

/// The record id of a path, or a 400 naming `id`.
fn parse_record_id(path: Result<Path<String>, PathRejection>) -> Result<String, Problem> {
    let Path(raw) =
        path.map_err(|e| Problem::bad_request("invalid-parameter", e.body_text()).param("id"))?;
    if !is_record_id(&raw) {
        return Err(Problem::bad_request(
            "invalid-parameter",
            format!(
                "{:?} is not a record id (32 hexadecimal digits)",
                raw.chars().take(64).collect::<String>()
            ),
        )
        .param("id"));
    }
    Ok(raw)
}

/// A bad value of query parameter `name`: 400 naming it.
fn bad_param(name: &str, detail: String) -> Problem {
    Problem::bad_request("invalid-parameter", detail).param(name)
}

/// The upload's options, from its query: a value that cannot be read is a
/// 400 naming its parameter.
fn options(q: &UploadQuery) -> Result<ReadOptions, Problem> {
    OptionTexts {
        format: q.format.as_deref(),
        unit: q.unit.as_deref(),
        dt: q.dt,
        time_column: q.time_column.as_deref(),
        acc_column: q.acc_column.as_deref(),
        name: q.name.as_deref(),
        allow_large_pga: q.allow_large_pga.unwrap_or(false),
    }
    .read()
    .map_err(|e| bad_param(&e.field, e.message))
}

/// 422 for a file that cannot be read as asked: naming the query parameter
/// to change, or the file's line, or (JSON) the field.
/// 422: a record over max_record_samples (`value` its count, or the
/// count at which reading stopped).
fn too_many_samples(samples: usize, max_samples: usize, at_least: bool) -> Problem {
    let mut p = Problem::new(
        StatusCode::UNPROCESSABLE_ENTITY,
        "limit-exceeded",
        "Record exceeds a service limit",
        format!(
            "the record has {}{samples} samples, more than this service's limit of {max_samples} (max_record_samples): shorten it or resample it to a longer time step",
            if at_least { "over " } else { "" }
        ),
    )
    .at("");
    p.limit = Some("max_record_samples".into());
    p.maximum = Some(max_samples as f64);
    p.value = Some(samples as f64 + if at_least { 1.0 } else { 0.0 });
    p
}

fn unreadable(e: crate::records::ReadError) -> Problem {
    let detail = match e.line {
        Some(line) => format!("line {line}: {}", e.message),
        None => e.message.clone(),
    };
    let p = Problem::new(
        StatusCode::UNPROCESSABLE_ENTITY,
        "invalid-record",
        "Record not readable as given",
        detail,
    );
    match e.field.as_ref() {
        "body" => p.at(""),
        f if f.starts_with('/') => p.at(f),
        f => p.param(f),
    }
}

/// The problem with a record file that could not be read whole: over
/// max_record_bytes (413), too slow (408, the connection closes), or broken.
fn body_error(state: &AppState, e: &axum::Error) -> Response {
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = cause {
        if err.is::<http_body_util::LengthLimitError>() {
            return Problem::body_too_large_for(state.config.max_record_bytes, "max_record_bytes")
                .into_response();
        }
        if err.is::<tower_http::timeout::TimeoutError>() {
            return super::jobs::body_timeout(state);
        }
        cause = err.source();
    }
    Problem::new(
        StatusCode::BAD_REQUEST,
        "invalid-body",
        "Unreadable body",
        "the body could not be read",
    )
    .at("")
    .into_response()
}

/// Upload a record.
///
/// The body is the file as you have it: a PEER NGA `.AT2` file, CSV or
/// whitespace columns (an optional header of `#` lines or a row of names;
/// one column of accelerations with `dt`, or time and acceleration), or JSON
/// `{"name", "dt", "unit", "acc"}`. The answer describes what was read
/// (samples, dt, peaks, warnings) before any job uses it. The same motion
/// uploaded again, in any format, answers 200 with the stored record.
#[utoipa::path(
    post,
    path = "/v1/records",
    tag = "records",
    operation_id = "create_record",
    params(UploadQuery),
    security((), ("bearer" = [])),
    request_body(content = String, description = "The record file", content_type = "text/plain"),
    responses(
        (status = 200, description = "This tenant had the record already", body = RecordView),
        (status = 201, description = "Stored", body = RecordView,
            headers(("Location" = String, description = "The record's URL"))),
        (status = 400, description = "A bad query parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is configured and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 408, description = "The body did not arrive within the service's limit", body = Problem, content_type = "application/problem+json"),
        (status = 413, description = "The file is larger than max_record_bytes", body = Problem, content_type = "application/problem+json"),
        (status = 422, description = "The file cannot be read as given (`parameter` names the query parameter to give or change, e.g. `unit`; or `pointer` \"\" with the line in `detail`), or it holds more samples than max_record_samples", body = Problem, content_type = "application/problem+json"),
        (status = 503, description = "The database is unavailable; nothing was saved", body = Problem, content_type = "application/problem+json"),
        (status = 507, description = "The service's storage is full; nothing was saved", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn create_record(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    headers: HeaderMap,
    q: Result<Query<UploadQuery>, Problem>,
    body: Body,
) -> Result<Response, Problem> {
    let Query(q) = q?;
    let opts = options(&q)?;
    // The file has a limit of its own (max_record_bytes), not the JSON
    // body limit; a declared length over it was refused before any byte.
    let body = match axum::body::to_bytes(body, state.config.max_record_bytes).await {
        Ok(body) => body,
        Err(e) => return Ok(body_error(&state, &e)),
    };
    let max_samples = state.config.max_record_samples;
    // Reading a file of a million samples is no work for the runtime.
    let read = tokio::task::spawn_blocking(move || -> Result<_, Problem> {
        let text = std::str::from_utf8(&body).map_err(|e| {
            Problem::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "invalid-record",
                "Record not readable as given",
                format!(
                    "the file is not UTF-8 text (byte {}): send the text file as it is",
                    e.valid_up_to()
                ),
            )
            .at("")
        })?;
        let file = crate::records::read(text, &opts).map_err(|e| match e.more_samples_than {
            Some(n) => too_many_samples(n, max_samples, true),
            None => unreadable(e),
        })?;
        if file.acc.len() > max_samples {
            return Err(too_many_samples(file.acc.len(), max_samples, false));
        }
        let id = crate::records::record_id(file.dt, &file.acc);
        let meta = RecordMeta::of(&file).map_err(Problem::internal)?;
        let meta_text =
            serde_json::to_string(&meta).map_err(|e| Problem::internal(e.to_string()))?;
        Ok((file, id, meta, meta_text))
    })
    .await
    .map_err(|e| Problem::internal(format!("reading the record stopped: {e}")))??;
    let (file, id, meta, meta_text) = read;
    let (row, created) = state
        .store
        .put_record(NewRecord {
            tenant: tenant.name(),
            id: &id,
            entry: crate::store::new_job_id(),
            dt: file.dt,
            acc: &file.acc,
            name: &meta.name,
            meta: &meta_text,
            now: &now_rfc3339(),
        })
        .await?;
    tracing::info!(target: "audit", action = "record_upload", tenant = tenant.name(), record = %id, created, request_id = headers.get(&super::http::REQUEST_ID).and_then(|v| v.to_str().ok()).unwrap_or(""), "audit");
    let view = RecordView::of(&row)?;
    let status = if created {
        StatusCode::CREATED
    } else {
        StatusCode::OK
    };
    let mut r = (status, axum::Json(view)).into_response();
    if let Ok(v) = HeaderValue::from_str(&format!("/v1/records/{id}")) {
        r.headers_mut().insert(header::LOCATION, v);
    }
    Ok(r)
}

/// Query of a record read.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct ReadQuery {
    /// `json`: the samples as a job spec's `ground_motion` (`name`, `dt`,
    /// `acc` in m/s², `unit`); `csv`: `t_s,acc_m_s2`; absent: the metadata.
    #[param(pattern = "^(json|csv)$")]
    pub format: Option<String>,
}

/// A record's samples, as a job spec's `ground_motion` holds them.
#[derive(Debug, Serialize, Deserialize, ToSchema)]
pub struct RecordSamples {
    /// Its name.
    pub name: String,
    /// Sampling interval, s.
    pub dt: f64,
    /// Always "m/s2".
    pub unit: String,
    /// Accelerations, m/s², at t_k = k·dt.
    pub acc: Vec<f64>,
}

/// What `GET /v1/records/{id}` answers as JSON: the metadata, or with
/// `?format=json` the samples.
#[derive(ToSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub enum RecordRead {
    /// The metadata (no `format`).
    Meta(RecordView),
    /// The samples (`?format=json`).
    Samples(RecordSamples),
}

/// A record: its metadata, or its samples.
#[utoipa::path(
    get,
    path = "/v1/records/{id}",
    tag = "records",
    operation_id = "get_record",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Record id", pattern = "^[0-9a-f]{32}$"), ReadQuery),
    responses(
        (status = 200, description = "The record's metadata; with `?format=json` its samples; with `?format=csv` a table",
            content(
                (RecordRead = "application/json"),
                (String = "text/csv"),
            )),
        (status = 400, description = "Bad id or parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such record (of this tenant)", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn get_record(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<ReadQuery>, Problem>,
) -> Result<Response, Problem> {
    let id = parse_record_id(path)?;
    let Query(q) = q?;
    let row = state
        .store
        .get_record(tenant.name(), &id)
        .await?
        .ok_or_else(|| Problem::not_found(format!("no record {id}")).param("id"))?;
    let format = q.format.as_deref();
    match format {
        None => Ok(axum::Json(RecordView::of(&row)?).into_response()),
        Some("json" | "csv") => {
            let (dt, acc) = state
                .store
                .record_samples(tenant.name(), &id)
                .await?
                .ok_or_else(|| Problem::not_found(format!("no record {id}")).param("id"))?;
            let csv = format == Some("csv");
            let name = row.name.clone();
            let body = tokio::task::spawn_blocking(move || {
                if csv {
                    let mut out = String::with_capacity(acc.len() * 24 + 16);
                    out.push_str("t_s,acc_m_s2\n");
                    for (k, a) in acc.iter().enumerate() {
                        out.push_str(&format!("{},{a}\n", k as f64 * dt));
                    }
                    Ok(out)
                } else {
                    serde_json::to_string(&RecordSamples {
                        name,
                        dt,
                        unit: "m/s2".into(),
                        acc,
                    })
                }
            })
            .await
            .map_err(|e| Problem::internal(e.to_string()))?
            .map_err(|e| Problem::internal(e.to_string()))?;
            let (content_type, disposition) = if csv {
                (
                    "text/csv; charset=utf-8",
                    format!("attachment; filename=\"record-{id}.csv\""),
                )
            } else {
                (
                    "application/json",
                    format!("inline; filename=\"record-{id}.json\""),
                )
            };
            Ok((
                [
                    (header::CONTENT_TYPE, content_type.to_string()),
                    (header::CONTENT_DISPOSITION, disposition),
                ],
                body,
            )
                .into_response())
        }
        Some(other) => Err(bad_param(
            "format",
            format!(
                "format {:?}: expected json or csv",
                other.chars().take(40).collect::<String>()
            ),
        )),
    }
}

/// Delete a record: 204; 409 while a queued or running job of this tenant
/// uses it (jobs that finished keep their results: their specs hold the
/// samples).
#[utoipa::path(
    delete,
    path = "/v1/records/{id}",
    tag = "records",
    operation_id = "delete_record",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Record id", pattern = "^[0-9a-f]{32}$")),
    responses(
        (status = 204, description = "Deleted"),
        (status = 400, description = "Bad id", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "A token is configured and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such record (of this tenant)", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "A live job uses it", body = Problem, content_type = "application/problem+json"),
        (status = 503, description = "The database is unavailable", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn delete_record(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
) -> Result<Response, Problem> {
    let id = parse_record_id(path)?;
    match state.store.delete_record(tenant.name(), &id).await? {
        RecordDeleted::Gone => Ok(StatusCode::NO_CONTENT.into_response()),
        RecordDeleted::NotFound => Err(Problem::not_found(format!("no record {id}")).param("id")),
        RecordDeleted::InUse(jobs) => Err(Problem::conflict(
            "record-in-use",
            format!(
                "record {id} is used by live job(s) {}: cancel them or wait until they finish",
                jobs.iter()
                    .map(Uuid::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// Query of a record listing.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct RecordListParams {
    /// At most this many (1..=500, default 50).
    #[param(minimum = 1, maximum = 500)]
    pub limit: Option<u32>,
    /// The `next_cursor` of the previous page (empty: the first page).
    #[param(
        pattern = "^$|^[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}$"
    )]
    pub cursor: Option<String>,
}

/// A page of records.
#[derive(Debug, Serialize, Deserialize, ToSchema)]
pub struct RecordPage {
    /// Newest first.
    pub records: Vec<RecordView>,
    /// Pass as `cursor` for the next page; null on the last.
    pub next_cursor: Option<String>,
}

/// List this tenant's records, newest first, with cursor pagination (as
/// jobs: `next_cursor` and a `Link: <…>; rel="next"` header).
#[utoipa::path(
    get,
    path = "/v1/records",
    tag = "records",
    operation_id = "list_records",
    security((), ("bearer" = [])),
    params(RecordListParams),
    responses(
        (status = 200, description = "A page of records", body = RecordPage,
            headers(("Link" = Option<String>, description = "The next page: <url>; rel=\"next\""))),
        (status = 400, description = "Bad parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here and the request lacks it", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn list_records(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    q: Result<Query<RecordListParams>, Problem>,
) -> Result<Response, Problem> {
    let Query(q) = q?;
    let limit = q.limit.unwrap_or(50);
    if !(1..=500).contains(&limit) {
        return Err(bad_param(
            "limit",
            "limit must satisfy 1 <= limit <= 500".into(),
        ));
    }
    let before = match q.cursor.as_deref() {
        None | Some("") => None,
        Some(c) => Some(
            Uuid::parse_str(c)
                .map_err(|_| bad_param("cursor", "cursor is not one this API returned".into()))?,
        ),
    };
    let rows = state
        .store
        .list_records(tenant.name(), limit, before)
        .await?;
    let next_cursor = if rows.len() as u32 == limit {
        rows.last().map(|r| r.entry.to_string())
    } else {
        None
    };
    let page = RecordPage {
        records: rows.iter().map(RecordView::of).collect::<Result<_, _>>()?,
        next_cursor: next_cursor.clone(),
    };
    let mut r = axum::Json(page).into_response();
    if let Some(v) = next_cursor.and_then(|c| {
        HeaderValue::from_str(&format!(
            "</v1/records?limit={limit}&cursor={c}>; rel=\"next\""
        ))
        .ok()
    }) {
        r.headers_mut().insert(header::LINK, v);
    }
    Ok(r)
}
