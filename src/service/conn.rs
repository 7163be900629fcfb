//! Connections: the accept loop, and what a client may hold of the server.
//!
//! At most `max_connections` connections are served at once: a permit is
//! taken before `accept` and held for the connection's life, so that further
//! clients wait in the kernel's listen backlog. A failed `accept` (out of file
//! descriptors, say) is logged at most every few seconds and retried after a
//! pause that grows to a second; it never stops the server.
//!
//! Each connection has a watchdog: a client must send a request's headers
//! within `header_read_timeout` of connecting, or of the first byte of a
//! request that follows an idle spell, and may leave the connection idle (no
//! request in flight) for `idle_timeout`. Past either it is closed. A request
//! in flight (a long-poll, an event stream) is never timed out here.
//!
//! On shutdown the listener is closed, each connection finishes the request
//! in flight and closes, and when the grace period runs out the connections
//! left are dropped.

use std::convert::Infallible;
use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::Router;
use axum::body::{Body, Bytes};
use http_body::{Frame, SizeHint};
use hyper::body::Incoming;
use hyper::server::conn::http1;
use hyper::{Request, Response};
use hyper_util::rt::TokioIo;
use hyper_util::server::graceful::{GracefulShutdown, Watcher};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Notify, OwnedSemaphorePermit, Semaphore, watch};
use tokio::time::Instant;
use tower::ServiceExt;
use tracing::{debug, info, warn};

use super::ServeConfig;
use super::metrics::Metrics;

/// First pause after a failed accept; it doubles up to [`MAX_PAUSE`].
const MIN_PAUSE: Duration = Duration::from_millis(100);
/// Longest pause after a failed accept.
const MAX_PAUSE: Duration = Duration::from_secs(1);
/// Failed accepts are logged at most this often.
const LOG_EVERY: Duration = Duration::from_secs(10);
/// How long dropped connections get to go once the grace period is over.
const DROP_WAIT: Duration = Duration::from_millis(500);

/// The time limits of one connection.
#[derive(Clone, Copy, Debug)]
struct Timeouts {
    header: Duration,
    idle: Duration,
}

/// Serves `app` on `listener` until `stop` turns true, then drains the
/// connections within `config.shutdown_grace` and drops those left.
pub(crate) async fn serve(
    listener: TcpListener,
    app: Router,
    config: &ServeConfig,
    metrics: Arc<Metrics>,
    mut stop: watch::Receiver<bool>,
) {
    let timeouts = Timeouts {
        header: config.header_read_timeout,
        idle: config.idle_timeout,
    };
    let max = config
        .max_connections
        .clamp(1, Semaphore::MAX_PERMITS.min(u32::MAX as usize));
    let permits = Arc::new(Semaphore::new(max));
    let graceful = GracefulShutdown::new();
    let (drop_all, dropped) = watch::channel(false);
    let mut failures = AcceptFailures::default();
    loop {
        let permit = tokio::select! {
            biased;
            _ = stopped(&mut stop) => break,
            permit = permits.clone().acquire_owned() => match permit {
                Ok(permit) => permit,
                Err(_) => break,
            },
        };
        let stream = tokio::select! {
            biased;
            _ = stopped(&mut stop) => break,
            stream = accept(&listener, &mut failures, &metrics) => stream,
        };
        metrics.connections_accepted.increment(1);
        tokio::spawn(connection(
            stream,
            permit,
            app.clone(),
            timeouts,
            graceful.watcher(),
            dropped.clone(),
            metrics.clone(),
        ));
    }
    drop(listener);
    let open = graceful.count();
    if open > 0 {
        info!(
            connections = open,
            "no new connections; finishing requests in flight"
        );
    }
    if tokio::time::timeout(config.shutdown_grace, graceful.shutdown())
        .await
        .is_err()
    {
        info!(
            connections = max - permits.available_permits(),
            "grace period over: dropping the connections left"
        );
        let _ = drop_all.send(true);
        let all = u32::try_from(max).unwrap_or(u32::MAX);
        // Every permit back: every connection is gone.
        let _ = tokio::time::timeout(DROP_WAIT, permits.acquire_many(all)).await;
    }
}

/// Resolves once `stop` is true (or its sender is gone).
async fn stopped(stop: &mut watch::Receiver<bool>) {
    let _ = stop.wait_for(|s| *s).await;
}

/// The next connection; failed accepts are retried after a pause.
async fn accept(
    listener: &TcpListener,
    failures: &mut AcceptFailures,
    metrics: &Metrics,
) -> TcpStream {
    loop {
        match listener.accept().await {
            Ok((stream, _)) => {
                failures.pause = MIN_PAUSE;
                return stream;
            }
            Err(e) => {
                if let Some(pause) = failures.record(&e, metrics) {
                    tokio::time::sleep(pause).await;
                }
            }
        }
    }
}

/// Failed accepts: the next pause, and the rate-limited log.
#[derive(Debug)]
struct AcceptFailures {
    pause: Duration,
    logged: Option<Instant>,
    unlogged: u64,
}

impl Default for AcceptFailures {
    fn default() -> Self {
        AcceptFailures {
            pause: MIN_PAUSE,
            logged: None,
            unlogged: 0,
        }
    }
}

impl AcceptFailures {
    /// Counts and (at most every [`LOG_EVERY`]) logs a failed accept; returns
    /// the pause before the next one, none for a connection that its client
    /// reset before it was accepted.
    fn record(&mut self, e: &io::Error, metrics: &Metrics) -> Option<Duration> {
        if matches!(
            e.kind(),
            io::ErrorKind::ConnectionAborted
                | io::ErrorKind::ConnectionReset
                | io::ErrorKind::ConnectionRefused
        ) {
            debug!(error = %e, "a connection went before it was accepted");
            return None;
        }
        metrics.accept_errors.increment(1);
        let now = Instant::now();
        if self.logged.is_none_or(|t| now >= t + LOG_EVERY) {
            warn!(
                error = %e,
                failures_not_logged = self.unlogged,
                "accepting a connection failed; retrying"
            );
            self.logged = Some(now);
            self.unlogged = 0;
        } else {
            self.unlogged += 1;
        }
        let pause = self.pause;
        self.pause = (self.pause * 2).min(MAX_PAUSE);
        Some(pause)
    }
}

/// Why a connection was closed by the server.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Closed {
    HeaderTimeout,
    IdleTimeout,
}

/// Serves one connection until it ends, a timeout closes it, or shutdown
/// drops it.
async fn connection(
    stream: TcpStream,
    permit: OwnedSemaphorePermit,
    app: Router,
    timeouts: Timeouts,
    watcher: Watcher,
    mut dropped: watch::Receiver<bool>,
    metrics: Arc<Metrics>,
) {
    let _permit = permit;
    metrics.connections_open.increment(1.0);
    let _ = stream.set_nodelay(true);
    let activity = Arc::new(Activity::new());
    let io = TokioIo::new(Watched {
        stream,
        activity: activity.clone(),
    });
    let service = Tracked {
        app,
        activity: activity.clone(),
    };
    // The watchdog times headers and idle spells: hyper's own header timer
    // would also run through every idle spell.
    let conn = http1::Builder::new()
        .keep_alive(true)
        .header_read_timeout(None)
        .serve_connection(io, service);
    tokio::select! {
        served = watcher.watch(conn) => {
            if let Err(e) = served {
                debug!(error = %e, "connection ended with an error");
            }
        }
        why = watchdog(&activity, timeouts) => {
            match why {
                Closed::HeaderTimeout => metrics.closed_header_timeout.increment(1),
                Closed::IdleTimeout => metrics.closed_idle_timeout.increment(1),
            }
            debug!(reason = ?why, "connection closed");
        }
        _ = stopped(&mut dropped) => {
            metrics.closed_at_shutdown.increment(1);
            debug!("connection dropped at the end of the grace period");
        }
    }
    metrics.connections_open.decrement(1.0);
}

/// Resolves when the connection has waited too long for headers or idled too
/// long.
async fn watchdog(activity: &Activity, timeouts: Timeouts) -> Closed {
    loop {
        let phase = activity.phase();
        let (deadline, why) = match phase {
            Phase::Busy(_) => {
                activity.changed.notified().await;
                continue;
            }
            Phase::Head(since) => (since + timeouts.header, Closed::HeaderTimeout),
            Phase::Idle(since) => (since + timeouts.idle, Closed::IdleTimeout),
        };
        tokio::select! {
            _ = tokio::time::sleep_until(deadline) => {
                if activity.phase() == phase {
                    return why;
                }
            }
            _ = activity.changed.notified() => {}
        }
    }
}

/// What a connection is doing.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// No request in flight and none begun since then.
    Idle(Instant),
    /// Waiting for the rest of a request's headers (since the connection
    /// opened or the first byte after an idle spell).
    Head(Instant),
    /// Requests in flight: from their headers to the end of their response.
    Busy(usize),
}

/// A connection's phase, shared by its IO, its service and its watchdog.
#[derive(Debug)]
struct Activity {
    phase: Mutex<Phase>,
    changed: Notify,
}

impl Activity {
    fn new() -> Self {
        Activity {
            phase: Mutex::new(Phase::Head(Instant::now())),
            changed: Notify::new(),
        }
    }

    fn phase(&self) -> Phase {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn update(&self, next: impl FnOnce(Phase) -> Phase) {
        let mut phase = self.phase.lock().unwrap_or_else(|e| e.into_inner());
        let new = next(*phase);
        if new != *phase {
            *phase = new;
            self.changed.notify_one();
        }
    }

    /// Bytes arrived: after an idle spell, they begin a request.
    fn received(&self) {
        self.update(|p| match p {
            Phase::Idle(_) => Phase::Head(Instant::now()),
            other => other,
        });
    }

    /// A request's headers arrived; it is in flight until the guard goes.
    fn begin(self: &Arc<Self>) -> InFlight {
        self.update(|p| match p {
            Phase::Busy(n) => Phase::Busy(n + 1),
            _ => Phase::Busy(1),
        });
        InFlight(self.clone())
    }
}

/// A request in flight; dropped with its response body.
#[derive(Debug)]
struct InFlight(Arc<Activity>);

impl Drop for InFlight {
    fn drop(&mut self) {
        self.0.update(|p| match p {
            Phase::Busy(n) if n > 1 => Phase::Busy(n - 1),
            _ => Phase::Idle(Instant::now()),
        });
    }
}

/// The TCP stream, noting every read that brings bytes.
struct Watched {
    stream: TcpStream,
    activity: Arc<Activity>,
}

impl AsyncRead for Watched {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let before = buf.filled().len();
        let polled = Pin::new(&mut this.stream).poll_read(cx, buf);
        if matches!(polled, Poll::Ready(Ok(()))) && buf.filled().len() > before {
            this.activity.received();
        }
        polled
    }
}

impl AsyncWrite for Watched {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write(cx, buf)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.stream.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_shutdown(cx)
    }
}

/// The router, marking each request in flight until its response body ends.
#[derive(Clone)]
struct Tracked {
    app: Router,
    activity: Arc<Activity>,
}

impl hyper::service::Service<Request<Incoming>> for Tracked {
    type Response = Response<TrackedBody>;
    type Error = Infallible;
    type Future = Pin<Box<dyn Future<Output = Result<Self::Response, Infallible>> + Send>>;

    fn call(&self, req: Request<Incoming>) -> Self::Future {
        let in_flight = self.activity.begin();
        let app = self.app.clone();
        Box::pin(async move {
            let response = app.oneshot(req.map(Body::new)).await?;
            Ok(response.map(|body| TrackedBody {
                body,
                _in_flight: in_flight,
            }))
        })
    }
}

/// A response body that keeps its request in flight until it is dropped.
struct TrackedBody {
    body: Body,
    _in_flight: InFlight,
}

impl http_body::Body for TrackedBody {
    type Data = Bytes;
    type Error = axum::Error;

    fn poll_frame(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, axum::Error>>> {
        Pin::new(&mut self.get_mut().body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}
