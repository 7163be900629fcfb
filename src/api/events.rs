//! `/v1/jobs/{id}/events`: a job's status as Server-Sent Events.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::rejection::PathRejection;
use axum::extract::{Extension, Path, State};
use axum::http::HeaderMap;
use axum::response::sse::{Event, KeepAlive, Sse};
use futures_util::Stream;
use tokio::time::Instant;
use uuid::Uuid;

use super::auth::Tenant;
use super::http::NoQuery;
use super::http::Query;
use super::jobs::{load, parse_id, status_etag, summary, view};
use super::problem::Problem;
use crate::service::AppState;

/// At most this many events a second.
const MIN_GAP: Duration = Duration::from_millis(100);

/// How often the stream looks at the job when nothing wakes it.
const LOOK: Duration = Duration::from_millis(250);

/// Keep-alive comments this often, so proxies keep the stream open.
const KEEP_ALIVE: Duration = Duration::from_secs(15);

/// Where a stream is.
struct Follow {
    state: AppState,
    tenant: Tenant,
    id: Uuid,
    /// ETag of the last status sent.
    last: Option<String>,
    /// When the last event went out.
    sent: Option<Instant>,
    /// The final event went out.
    done: bool,
}

impl Follow {
    /// The next event: the job's status as soon as it differs from the last
    /// one sent (no sooner than [`MIN_GAP`] after it), `done` with the finished
    /// job, or the end of the stream (job gone, or the service stopping).
    async fn next(&mut self) -> Option<Event> {
        if self.done {
            return None;
        }
        let mut finished = self.state.finished.subscribe();
        let mut stopping = self.state.stopping.clone();
        loop {
            if let Some(sent) = self.sent {
                tokio::time::sleep_until(sent + MIN_GAP).await;
            }
            if *stopping.borrow() {
                return None;
            }
            let job = load(&self.state, &self.tenant, self.id).await.ok()?;
            let etag = status_etag(&job);
            let final_status = job.status.is_final();
            // A finished job always ends the stream with `done`, even for a
            // client that resumes having seen it (so it never waits in vain).
            if self.last.as_deref() != Some(etag.as_str()) || final_status {
                // Progress events are light summaries; the final one is the
                // whole job view.
                let shown = if final_status {
                    view(&job, None)
                } else {
                    summary(&job, None)
                };
                let data = serde_json::to_string(&shown).ok()?;
                self.last = Some(etag.clone());
                self.sent = Some(Instant::now());
                self.done = final_status;
                return Some(
                    Event::default()
                        .event(if final_status { "done" } else { "status" })
                        .id(etag)
                        .data(data),
                );
            }
            // Woken when a job finishes here, on shutdown, or after a while:
            // progress, and jobs other instances compute, show on the next look.
            tokio::select! {
                _ = finished.recv() => {}
                _ = stopping.changed() => {}
                _ = tokio::time::sleep(LOOK) => {}
            }
        }
    }
}

/// A job's status, live, as Server-Sent Events.
///
/// First the current state (`event: status`, data: the job view), then an
/// event at each change of status or progress (at most 10 a second), then
/// `event: done` with the finished job view, and the stream ends. Comments
/// keep the connection alive meanwhile. It works whichever instance computes
/// the job.
#[utoipa::path(
    get,
    path = "/v1/jobs/{id}/events",
    tag = "jobs",
    operation_id = "job_events",
    security((), ("bearer" = [])),
    params(
        ("id" = String, Path, description = "Job id (a UUID)", format = "uuid"),
        ("Last-Event-ID" = Option<String>, Header, description = "The `id` of the last event seen: a reconnecting client resumes after it (a finished job still ends with `done`)"),
    ),
    responses(
        (status = 200, description = "The stream: `status` events, then one `done` event; data is a JobView", body = crate::jobs::schema::JobEvent, content_type = "text/event-stream"),
        (status = 400, description = "Not a job id, or a query parameter", body = Problem, content_type = "application/problem+json"),
        (status = 401, description = "Reads need a token here (TOPPLE_AUTH_READS) and the request lacks it", body = Problem, content_type = "application/problem+json"),
        (status = 404, description = "No such job", body = Problem, content_type = "application/problem+json"),
    )
)]
pub async fn job_events(
    State(state): State<AppState>,
    Extension(tenant): Extension<Tenant>,
    path: Result<Path<String>, PathRejection>,
    q: Result<Query<NoQuery>, Problem>,
    headers: HeaderMap,
) -> Result<Sse<impl Stream<Item = Result<Event, Infallible>>>, Problem> {
    let id = parse_id(path)?;
    q?;
    tracing::Span::current().record("job_id", tracing::field::display(id));
    // A job that does not exist is a 404, not an empty stream.
    load(&state, &tenant, id).await?;
    // A client that reconnects (EventSource does) names the last event it
    // saw: the stream resumes after it instead of repeating it.
    let last = headers
        .get("last-event-id")
        .and_then(|v| v.to_str().ok())
        .filter(|v| v.len() <= 128)
        .map(str::to_string);
    let follow = Follow {
        state,
        tenant,
        id,
        last,
        sent: None,
        done: false,
    };
    let stream = futures_util::stream::unfold(follow, |mut f| async move {
        let event = f.next().await?;
        Some((Ok(event), f))
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::new().interval(KEEP_ALIVE)))
}
