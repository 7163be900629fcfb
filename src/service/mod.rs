//! The HTTP computation service: an axum server over the job store, with
//! workers that compute on a rayon pool.
//!
//! `Application::build` opens the store (applying migrations), requeues jobs
//! that a dead process left running, and binds the listener;
//! `Application::run_until` serves until the shutdown future resolves, then
//! stops accepting, lets requests in flight and running jobs finish within the
//! grace period, drops the connections left and requeues the jobs left.

pub mod config;
mod conn;
pub mod metrics;
pub mod records;
pub mod results;
pub mod retention;
pub mod tenants;
pub mod throughput;
pub mod worker;

use std::collections::HashMap;
use std::future::Future;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::{Notify, broadcast, watch};
use tracing::info;
use uuid::Uuid;

pub use config::ServeConfig;

use crate::spectrum::Control;
use crate::store::postgres::PgStore;
use crate::store::sqlite::SqliteStore;
use crate::store::{JobStore, StoreError};

/// What computes a job: [`crate::jobs::Job::run`] unless an embedding supplies its own.
pub type Engine = Arc<
    dyn Fn(&crate::jobs::Job, &Control) -> Result<serde_json::Value, crate::jobs::JobError>
        + Send
        + Sync,
>;

/// Large result documents (over [`results::MAX_BODY`]) parsed whole and
/// rendered at once (figures, tables other than a series): a document parsed
/// is several times its text.
pub const RENDERS: usize = 1;

/// Tasks computing in this instance, by (job, task index).
type Running = HashMap<(Uuid, i64), Arc<Control>>;

/// Shared state of one instance.
#[derive(Clone)]
pub struct AppState {
    /// Jobs and results.
    pub store: Arc<dyn JobStore>,
    /// Settings.
    pub config: Arc<ServeConfig>,
    /// Wakes an idle worker when a job is queued.
    pub wake: Arc<Notify>,
    /// Announces every job that reached a final status.
    pub finished: broadcast::Sender<Uuid>,
    /// Controls of the tasks computing in this instance (for cancellation).
    running: Arc<Mutex<Running>>,
    /// Metrics.
    pub metrics: Arc<metrics::Metrics>,
    /// Result documents in memory.
    pub results: Arc<results::ResultCache>,
    /// Turns to parse and render a large result document whole ([`RENDERS`]).
    pub renders: Arc<tokio::sync::Semaphore>,
    /// The measured computation rate (estimates, poll intervals).
    pub throughput: Arc<throughput::Throughput>,
    /// The compute pool.
    pub pool: Arc<rayon::ThreadPool>,
    /// What computes jobs.
    pub engine: Engine,
    /// How often idle workers look for work without being woken.
    pub idle_poll: Duration,
    /// Becomes true when the instance is shutting down.
    pub stopping: watch::Receiver<bool>,
    stop: Arc<watch::Sender<bool>>,
}

impl AppState {
    fn register(&self, id: Uuid, idx: i64, control: Arc<Control>) {
        if let Ok(mut m) = self.running.lock() {
            m.insert((id, idx), control);
        }
    }

    fn unregister(&self, id: Uuid, idx: i64) {
        if let Ok(mut m) = self.running.lock() {
            m.remove(&(id, idx));
        }
    }

    /// Stops the job's tasks computing in this instance; returns how many.
    pub fn cancel_local(&self, id: Uuid) -> usize {
        let controls: Vec<Arc<Control>> = self
            .running
            .lock()
            .map(|m| {
                m.iter()
                    .filter(|(k, _)| k.0 == id)
                    .map(|(_, c)| c.clone())
                    .collect()
            })
            .unwrap_or_default();
        for c in &controls {
            c.cancel();
        }
        controls.len()
    }

    /// Whether a task of the job computes in this instance.
    pub fn computing(&self, id: Uuid) -> bool {
        self.running
            .lock()
            .map(|m| m.keys().any(|k| k.0 == id))
            .unwrap_or(false)
    }

    fn announce(&self, id: Uuid) {
        let _ = self.finished.send(id);
    }
}

/// Why the service could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The address could not be listened on.
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        /// The address.
        addr: String,
        /// Why.
        source: std::io::Error,
    },
    /// Serving failed.
    #[error("io: {0}")]
    Io(#[from] std::io::Error),
    /// The compute pool could not be built.
    #[error("thread pool: {0}")]
    Pool(String),
    /// The database URL is not understood.
    #[error("unsupported database URL {0:?}: use sqlite://path or postgres://…")]
    DatabaseUrl(String),
}

/// Opens the store named by `url`: `sqlite://path` (or a plain path) or
/// `postgres://…`.
pub async fn open_store(url: &str, connections: u32) -> Result<Arc<dyn JobStore>, ServeError> {
    if url.starts_with("postgres://") || url.starts_with("postgresql://") {
        Ok(Arc::new(PgStore::open(url, connections).await?))
    } else if url.starts_with("sqlite:") || !url.contains("://") {
        Ok(Arc::new(SqliteStore::open(url, connections).await?))
    } else {
        Err(ServeError::DatabaseUrl(url.to_string()))
    }
}

/// A built, bound, not yet running instance.
pub struct Application {
    listener: TcpListener,
    state: AppState,
}

impl Application {
    /// Opens the store, recovers interrupted jobs and binds the address.
    pub async fn build(config: ServeConfig) -> Result<Self, ServeError> {
        Self::build_with_engine(config, Arc::new(|job, control| job.run(control))).await
    }

    /// As [`Application::build`], computing jobs with `engine`.
    pub async fn build_with_engine(
        config: ServeConfig,
        engine: Engine,
    ) -> Result<Self, ServeError> {
        // The address first: a taken port is reported before anything is
        // created (a SQLite file, a migrated database).
        let listener =
            TcpListener::bind(&config.addr)
                .await
                .map_err(|source| ServeError::Bind {
                    addr: config.addr.clone(),
                    source,
                })?;
        let store = open_store(&config.database_url, (config.workers as u32 + 4).max(8)).await?;
        let recovered = store.recover().await?;
        if recovered > 0 {
            info!(recovered, "requeued jobs interrupted by a previous stop");
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(config.workers.max(1))
            .thread_name(|i| format!("topple-compute-{i}"))
            .build()
            .map_err(|e| ServeError::Pool(e.to_string()))?;
        let (finished, _) = broadcast::channel(1024);
        let (stop, stopping) = watch::channel(false);
        let results = Arc::new(results::ResultCache::new(config.result_memory));
        let state = AppState {
            store,
            config: Arc::new(config),
            wake: Arc::new(Notify::new()),
            finished,
            running: Arc::new(Mutex::new(HashMap::new())),
            metrics: Arc::new(metrics::Metrics::new()),
            results,
            renders: Arc::new(tokio::sync::Semaphore::new(RENDERS)),
            throughput: Arc::new(throughput::Throughput::default()),
            pool: Arc::new(pool),
            engine,
            idle_poll: Duration::from_millis(500),
            stopping,
            stop: Arc::new(stop),
        };
        Ok(Application { listener, state })
    }

    /// The bound port.
    pub fn port(&self) -> u16 {
        self.listener.local_addr().map(|a| a.port()).unwrap_or(0)
    }

    /// The shared state (for tests and embedding).
    pub fn state(&self) -> &AppState {
        &self.state
    }

    /// Serves until `shutdown` resolves, then drains gracefully.
    pub async fn run_until<F>(self, shutdown: F) -> Result<(), ServeError>
    where
        F: Future<Output = ()> + Send + 'static,
    {
        let Application { listener, state } = self;
        let mut workers = Vec::new();
        for n in 0..state.config.workers.max(1) {
            workers.push(tokio::spawn(worker::run(
                state.clone(),
                n,
                state.stopping.clone(),
            )));
        }
        if let Some(retention) = state.config.retention {
            tokio::spawn(retention::run(
                state.clone(),
                retention,
                state.stopping.clone(),
            ));
        }
        let app = crate::api::router(state.clone());
        info!(addr = %listener.local_addr()?, workers = state.config.workers, "serving");
        let (signal_tx, signal_rx) = watch::channel(false);
        let server = tokio::spawn({
            let config = state.config.clone();
            let metrics = state.metrics.clone();
            async move { conn::serve(listener, app, &config, metrics, signal_rx).await }
        });
        shutdown.await;
        info!("shutting down: no new requests, draining requests and jobs");
        let _ = signal_tx.send(true);
        // Workers stop claiming; requests waiting on jobs answer at once.
        let _ = state.stop.send(true);
        state.wake.notify_waiters();
        for w in workers {
            let _ = w.await;
        }
        if let Err(e) = server.await {
            return Err(ServeError::Io(std::io::Error::other(e.to_string())));
        }
        info!("stopped");
        Ok(())
    }
}

/// Resolves on Ctrl-C or SIGTERM.
pub async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {}
        _ = term => {}
    }
}
