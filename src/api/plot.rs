//! `/v1/jobs/{id}/plot.svg`: the figure of a finished job's result.

use axum::extract::rejection::PathRejection;
use axum::extract::{Extension, Path, State};
use axum::http::HeaderMap;
use axum::response::Response;
use serde::Deserialize;
use utoipa::IntoParams;

use super::auth::Tenant;
use super::http::Query;
use super::jobs::{parse_id, result_response};
use super::problem::Problem;
use super::representation::Format;
use crate::plot::Window;
use crate::service::AppState;

/// A job's result as a figure (SVG).
///
/// The figure `topple run --plot FILE` writes: a time history's stacked
/// panels (ü_g/g, θ/α, θ̇/p, f_x/f_z), a spectrum's overturning regions by
/// mode, a friction spectrum's demand, a forensic map. A time history without
/// a series draws the pulse and the impacts; submit it with
/// `"outputs": {"series": 500}` for θ(t), θ̇(t) and f_x/f_z(t). A time
/// history whose pulse takes under a quarter of it is drawn in two columns:
/// the pulse and the first impacts, and the whole history; `?window=t0,t1`
/// draws the span from t0 to t1 seconds instead.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}/plot.svg",
    tag = "jobs",
    operation_id = "get_plot",
    security((), ("bearer" = [])),
    params(("id" = String, Path, description = "Job id (a UUID)", format = "uuid"), PlotQuery,
        ("If-None-Match" = Option<String>, Header, description = "The ETag of the figure already held")),
    responses(
        (status = 200, description = "The figure", body = crate::jobs::schema::SvgFigure, content_type = "image/svg+xml",
            headers(("ETag" = String, description = "Strong: the job key, the format and the window"),
                    ("Cache-Control" = String, description = "immutable"))),
        (status = 304, description = "Unchanged (it never changes)"),
        (status = 400, description = "Bad id or window (or a window on a result without time axis), an unknown parameter, or a result with nothing to draw", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
        (status = 409, description = "Not finished (or failed, or canceled), or a stored result this engine cannot read (`result-unreadable`, naming the field: submit the spec again)", body = Problem, content_type = "application/problem+json"),
        (status = 503, description = "Busy: the memory for large results (result_memory) or the rendering turns stayed taken for 10 s, or the database is unavailable", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    )
)]
pub async fn get_plot(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<PlotQuery>, Problem>,
    headers: HeaderMap,
) -> Result<Response, Problem> {
    let id = parse_id(path)?;
    let Query(q) = q?;
    let window = q
        .window
        .as_deref()
        .map(Window::parse)
        .transpose()
        .map_err(|e| Problem::bad_request("invalid-parameter", e).param("window"))?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    result_response(&state, &tenant, id, Format::Svg(window), &headers).await
}

/// Query of a figure.
#[derive(Debug, Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct PlotQuery {
    /// A time history's span to draw, `t0,t1` in seconds with t0 < t1
    /// (e.g. `0,1.2`); without it the whole history.
    #[param(pattern = r"^\s*[^,]+\s*,\s*[^,]+\s*$", example = "0,1.2")]
    pub window: Option<String>,
}
