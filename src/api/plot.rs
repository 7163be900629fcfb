//! `/v1/jobs/{id}/plot.svg`: the figure of a finished job's result.

use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};

use super::jobs::{finished_result, parse_id};
use super::problem::Problem;
use crate::service::AppState;

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
    let body = finished_result(&state, id).await?;
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
