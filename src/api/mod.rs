//! The HTTP API: thin glue from requests to the job store and back. No physics
//! here.

// Handlers return `Result<_, Problem>`: the error is the response body itself.
#![allow(clippy::result_large_err)]

pub mod csv;
pub mod health;
pub mod jobs;
pub mod problem;

use std::time::Duration;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::{Request, StatusCode, header};
use axum::response::IntoResponse;
use axum::routing::get;
use tower_http::timeout::TimeoutLayer;
use tower_http::trace::TraceLayer;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;

use crate::service::AppState;
use problem::Problem;

/// The API description (merged with the routes' own).
#[derive(OpenApi)]
#[openapi(
    info(
        title = "topple",
        description = "Rocking and overturning of free-standing rigid blocks under cycloidal pulses (Makris & Zhang 2001). Submit a job spec, poll its status, fetch its result.",
        license(name = "MIT")
    ),
    tags(
        (name = "jobs", description = "Time histories, overturning spectra, friction-demand spectra"),
        (name = "operations", description = "Health, readiness, metrics")
    )
)]
pub struct ApiDoc;

/// Routes and their OpenAPI description, from one source.
pub fn routes() -> (Router<AppState>, utoipa::openapi::OpenApi) {
    OpenApiRouter::with_openapi(ApiDoc::openapi())
        .routes(routes!(jobs::create_job, jobs::list_jobs))
        .routes(routes!(jobs::get_job, jobs::cancel_job))
        .routes(routes!(jobs::get_result))
        .routes(routes!(health::healthz))
        .routes(routes!(health::readyz))
        .routes(routes!(health::metrics))
        .split_for_parts()
}

/// The OpenAPI document as YAML (what `openapi.yaml` holds).
pub fn openapi_yaml() -> String {
    let (_, mut api) = routes();
    api.paths.paths.insert(
        "/openapi.yaml".into(),
        utoipa::openapi::path::PathItem::new(
            utoipa::openapi::HttpMethod::Get,
            utoipa::openapi::path::OperationBuilder::new()
                .tag("operations")
                .summary(Some("This API description (OpenAPI 3.1, YAML)"))
                .response(
                    "200",
                    utoipa::openapi::ResponseBuilder::new()
                        .description("The description")
                        .content(
                            "application/yaml",
                            utoipa::openapi::ContentBuilder::new().build(),
                        )
                        .build(),
                )
                .build(),
        ),
    );
    api.to_yaml().unwrap_or_default()
}

async fn not_found() -> Problem {
    Problem::not_found("no such endpoint; see /openapi.yaml")
}

async fn method_not_allowed() -> Problem {
    Problem::new(
        StatusCode::METHOD_NOT_ALLOWED,
        "method-not-allowed",
        "Method not allowed",
        "this endpoint does not take that method; see /openapi.yaml",
    )
}

/// The whole application router.
pub fn router(state: AppState) -> Router {
    let (api, _) = routes();
    let yaml = openapi_yaml();
    let max_body = state.config.max_body_bytes;
    let timeout = state.config.max_wait + Duration::from_secs(15);
    api.route(
        "/openapi.yaml",
        get(move || {
            let yaml = yaml.clone();
            async move { ([(header::CONTENT_TYPE, "application/yaml")], yaml).into_response() }
        }),
    )
    .fallback(not_found)
    .method_not_allowed_fallback(method_not_allowed)
    .layer(DefaultBodyLimit::max(max_body))
    .layer(TimeoutLayer::with_status_code(
        StatusCode::SERVICE_UNAVAILABLE,
        timeout,
    ))
    .layer(
        TraceLayer::new_for_http().make_span_with(|req: &Request<_>| {
            tracing::info_span!(
                "request",
                method = %req.method(),
                path = %req.uri().path(),
                job_id = tracing::field::Empty,
            )
        }),
    )
    .with_state(state)
}
