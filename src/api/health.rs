//! Liveness, readiness, metrics and the API description.

use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;

use super::problem::Problem;
use crate::service::AppState;

/// A health answer.
#[derive(Debug, Serialize, ToSchema)]
pub struct Health {
    /// "ok".
    pub status: String,
}

/// The process is up.
#[utoipa::path(get, path = "/healthz", tag = "operations", security(()),
    responses((status = 200, description = "Alive", body = Health)))]
pub async fn healthz() -> axum::Json<Health> {
    axum::Json(Health {
        status: "ok".into(),
    })
}

/// The database answers and takes writes, and the instance is not shutting down.
#[utoipa::path(get, path = "/readyz", tag = "operations", security(()),
    responses(
        (status = 200, description = "Ready", body = Health),
        (status = 503, description = "Not ready: the database does not answer or does not take writes (full disk), or shutting down", body = Problem, content_type = "application/problem+json",
            headers(("Retry-After" = String, description = "Seconds to wait"))),
    ))]
pub async fn readyz(State(state): State<AppState>) -> Result<axum::Json<Health>, Problem> {
    state.store.ping().await.map_err(|e| {
        tracing::error!(error = %e, "readiness: the database does not answer");
        Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "not-ready",
            "Not ready",
            "the database does not answer",
        )
        .retry_after(2)
    })?;
    state.store.writable().await.map_err(|e| {
        tracing::warn!(error = %e, "readiness: the database does not take writes");
        Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "not-ready",
            "Not ready",
            "the database does not take writes (full disk, or unavailable)",
        )
        .retry_after(2)
    })?;
    // A busy compute pool is working, not broken: readiness asks only that it
    // still has its threads.
    if state.pool.current_num_threads() == 0 || *state.stopping.borrow() {
        return Err(Problem::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "not-ready",
            "Not ready",
            "shutting down",
        )
        .retry_after(2));
    }
    Ok(axum::Json(Health {
        status: "ready".into(),
    }))
}

/// Prometheus metrics: jobs by status, queue depth, cache hits, compute seconds by kind.
#[utoipa::path(get, path = "/metrics", tag = "operations", security((), ("bearer" = [])),
    responses((status = 200, description = "Prometheus text exposition", body = String, content_type = "text/plain"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json")))]
pub async fn metrics(State(state): State<AppState>) -> Result<Response, Problem> {
    let counts = state.store.counts().await?;
    let text = state.metrics.render(&counts);
    Ok(([(header::CONTENT_TYPE, "text/plain; version=0.0.4")], text).into_response())
}
