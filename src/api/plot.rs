//! `/v1/jobs/{id}/plot.svg`: the figure of a finished job's result.

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use uuid::Uuid;

use super::problem::Problem;
use crate::service::AppState;
use crate::store::Status;

fn parse_id(path: Result<Path<String>, PathRejection>) -> Result<Uuid, Problem> {
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

/// The stored result document of job `id`: 404 without the job, 409 until it
/// has succeeded.
async fn result_of(state: &AppState, id: Uuid) -> Result<std::sync::Arc<str>, Problem> {
    if let Some(body) = state.results.get(id) {
        return Ok(body);
    }
    let job = state
        .store
        .get(id)
        .await?
        .ok_or_else(|| Problem::not_found(format!("no job {id}")).param("id"))?;
    match job.status {
        Status::Succeeded => {}
        Status::Failed => {
            return Err(Problem::conflict(
                "job-failed",
                format!("job {id} failed: {}", job.error.unwrap_or_default()),
            ));
        }
        Status::Canceled => {
            return Err(Problem::conflict(
                "job-canceled",
                format!("job {id} was canceled"),
            ));
        }
        s => {
            return Err(Problem::conflict(
                "not-finished",
                format!("job {id} is {}; poll /v1/jobs/{id}", s.as_str()),
            ));
        }
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

/// A job's result as a figure (SVG).
///
/// The figure `topple run --plot FILE` writes: a time history's stacked
/// panels (ü_g/g, θ/α, θ̇/p, f_x/f_z), a spectrum's overturning regions by
/// mode, a friction spectrum's demand, a forensic map. A time history without
/// a series draws the pulse and the impacts; submit it with
/// `"outputs": {"series": 500}` for θ(t), θ̇(t) and f_x/f_z(t).
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}/plot.svg",
    tag = "jobs",
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid")),
    responses(
        (status = 200, description = "The figure", body = String, content_type = "image/svg+xml"),
        (status = 400, description = "Bad id, or a result with nothing to draw", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Not finished (or failed, or canceled)", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn get_plot(
    State(state): State<AppState>,
    path: Result<Path<String>, PathRejection>,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    let body = result_of(&state, id).await?;
    // Parsing and drawing are CPU work: the blocking pool, not the runtime.
    let figure = tokio::task::spawn_blocking(move || {
        serde_json::from_str::<serde_json::Value>(&body)
            .map_err(|e| e.to_string())
            .map(|v| crate::plot::svg(&v))
    })
    .await
    .map_err(|_| Problem::internal("figure rendering stopped"))?
    .map_err(Problem::internal)?
    .map_err(|e| Problem::bad_request("no-plot", e).param("id"))?;
    Ok(([(header::CONTENT_TYPE, "image/svg+xml")], figure).into_response())
}
