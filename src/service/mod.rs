//! The computation service behind the HTTP API: the state of one instance
//! (the job store, succeeded jobs, results and their renderings in memory,
//! the compute pool), workers that claim
//! tasks and compute them on a rayon pool, the connections the server holds,
//! and the job logic the API calls: a submission read, resolved (the records
//! and fragility jobs its spec names), validated and admitted; finished
//! results.
//!
//! It knows nothing of routes: `crate::startup` puts it together with the
//! API into the application.

pub mod config;
pub(crate) mod conn;
pub mod finished;
pub mod fragility_links;
pub mod inline;
pub mod lru;
pub mod metrics;
pub mod records;
pub mod renderings;
pub mod results;
pub mod retention;
pub mod submit;
pub mod succeeded;
pub mod tenants;
pub mod throughput;
pub mod worker;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::{Notify, watch};
use uuid::Uuid;

pub use config::ServeConfig;

use crate::spectrum::Control;
use crate::store::postgres::PgStore;
use crate::store::sqlite::SqliteStore;
use crate::store::{JobStore, StoreError};

/// What computes a task: [`crate::kinds::Task::run`] unless an embedding supplies its own.
pub type Engine = Arc<
    dyn Fn(&crate::kinds::Task, &Control) -> Result<serde_json::Value, crate::jobs::JobError>
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
    /// Announces every computation that reached a final status (the
    /// store's announcements: a success with the end its jobs took).
    pub finished: crate::store::Announcer,
    /// Controls of the tasks computing in this instance (for cancellation).
    running: Arc<Mutex<Running>>,
    /// Keys of the jobs computed in their requests now.
    pub in_flight: Arc<inline::InFlight>,
    /// When each tenant was last written as served by a job computed in
    /// its request.
    pub served: Arc<inline::Served>,
    /// Notified when a computation gives its compute slot back.
    freed: Arc<Notify>,
    /// Metrics.
    pub metrics: Arc<metrics::Metrics>,
    /// Result documents in memory.
    pub results: Arc<results::ResultCache>,
    /// Succeeded jobs in memory.
    pub succeeded: Arc<succeeded::SucceededJobs>,
    /// Tables and figures of results in memory.
    pub renderings: Arc<renderings::Renderings>,
    /// Turns to parse and render a large result document whole ([`RENDERS`]).
    pub renders: Arc<tokio::sync::Semaphore>,
    /// The turn to size a new job on a sample of its work: one at a time
    /// ([`submit::sample`]).
    pub sampling: Arc<tokio::sync::Semaphore>,
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
    /// The state of an instance with `config` over `store`, computing jobs
    /// with `engine` on a pool of `config.workers` threads.
    pub fn new(
        store: Arc<dyn JobStore>,
        config: ServeConfig,
        engine: Engine,
    ) -> Result<AppState, ServeError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(config.workers.max(1))
            .thread_name(|i| format!("topple-compute-{i}"))
            .build()
            .map_err(|e| ServeError::Pool(e.to_string()))?;
        let finished = store.finished();
        let (stop, stopping) = watch::channel(false);
        let results = Arc::new(results::ResultCache::new(config.result_memory));
        let succeeded = Arc::new(succeeded::SucceededJobs::new(store.deletions()));
        Ok(AppState {
            store,
            config: Arc::new(config),
            wake: Arc::new(Notify::new()),
            finished,
            running: Arc::new(Mutex::new(HashMap::new())),
            in_flight: Default::default(),
            served: Default::default(),
            freed: Arc::new(Notify::new()),
            metrics: Arc::new(metrics::Metrics::new()),
            results,
            succeeded,
            renderings: Arc::new(renderings::Renderings::default()),
            renders: Arc::new(tokio::sync::Semaphore::new(RENDERS)),
            sampling: Arc::new(tokio::sync::Semaphore::new(1)),
            throughput: Arc::new(throughput::Throughput::new(pool.current_num_threads())),
            pool: Arc::new(pool),
            engine,
            idle_poll: Duration::from_millis(500),
            stopping,
            stop: Arc::new(stop),
        })
    }

    /// The instance is stopping: workers stop claiming new work, and
    /// requests waiting on jobs answer at once.
    pub fn stop(&self) {
        let _ = self.stop.send(true);
        self.wake.notify_waiters();
    }

    fn register(&self, id: Uuid, idx: i64, control: Arc<Control>) {
        if let Ok(mut m) = self.running.lock() {
            m.insert((id, idx), control);
        }
    }

    /// Registers a computation in a free compute slot: `false` when as many
    /// tasks compute here as the pool has threads.
    fn try_register(&self, id: Uuid, idx: i64, control: Arc<Control>) -> bool {
        let Ok(mut m) = self.running.lock() else {
            return false;
        };
        if m.len() >= self.pool.current_num_threads() {
            return false;
        }
        m.insert((id, idx), control);
        true
    }

    /// Tasks computing on this instance now.
    fn busy(&self) -> usize {
        self.running.lock().map_or(1, |m| m.len())
    }

    fn unregister(&self, id: Uuid, idx: i64) {
        if let Ok(mut m) = self.running.lock() {
            m.remove(&(id, idx));
        }
        self.freed.notify_one();
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

    /// Announces that computation `id` ended (its waiters read their jobs
    /// again; a success the store announces itself, with its end).
    fn announce(&self, id: Uuid) {
        self.finished.announce(crate::store::Finished::ended(id));
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
