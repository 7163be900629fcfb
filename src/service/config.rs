//! How a service instance is set up.

use std::path::PathBuf;
use std::time::Duration;

use crate::kinds::limits::Limits;

/// Settings of `topple serve`.
#[derive(Clone, Debug, PartialEq)]
pub struct ServeConfig {
    /// Address to listen on.
    pub addr: String,
    /// `sqlite://path` (default `sqlite://topple.db`) or `postgres://…`.
    pub database_url: String,
    /// Jobs computed at once, and threads of the compute pool.
    pub workers: usize,
    /// Largest request body, bytes.
    pub max_body_bytes: usize,
    /// Largest record file uploaded (`POST /v1/records`), bytes.
    pub max_record_bytes: usize,
    /// Most samples of an uploaded record.
    pub max_record_samples: usize,
    /// Longest `?wait=` honoured, s.
    pub max_wait: Duration,
    /// How long shutdown waits for running jobs before requeuing them.
    pub shutdown_grace: Duration,
    /// Lease of a claimed job; renewed by the heartbeat.
    pub lease: Duration,
    /// Heartbeat (progress, lease renewal, remote cancellation) interval.
    pub heartbeat: Duration,
    /// Name of this instance (lease owner).
    pub instance: String,
    /// Largest job accepted.
    pub limits: Limits,
    /// Most jobs waiting in the queue; a submission beyond answers 429.
    pub max_queued: u64,
    /// Longest computation of one task (a whole job, or one chunk of a
    /// spectrum); past it the job fails.
    pub job_timeout: Duration,
    /// Bearer token required by mutating routes (none: open).
    pub api_token: Option<String>,
    /// Whether reads need the token too.
    pub auth_reads: bool,
    /// The tenants and their tokens ([`super::tenants`]): with it, every request
    /// but the probes, the API description and the page needs a token, and
    /// belongs to the tenant the token names.
    pub tokens_file: Option<PathBuf>,
    /// Whether `/metrics` is open even where reads need a token.
    pub metrics_open: bool,
    /// How long a finished job is kept; none: forever.
    pub retention: Option<Duration>,
    /// Most jobs one tenant may have queued or running; a submission beyond
    /// answers 429. None: only [`ServeConfig::max_queued`] bounds them.
    pub max_queued_per_tenant: Option<u64>,
    /// Origins allowed by CORS (`*` for any); none: same origin only.
    pub cors_origins: Vec<String>,
    /// Longest time a client may take to send a request's headers, counted
    /// from the connection's opening or from the first byte of a request
    /// after an idle spell; past it the connection is closed.
    pub header_read_timeout: Duration,
    /// Longest time a connection stays open with no request in flight.
    pub idle_timeout: Duration,
    /// Longest time a client may take to send a request's body, counted from
    /// the end of its headers; past it the request is answered 408.
    pub body_read_timeout: Duration,
    /// Most connections served at once; more wait in the listen backlog.
    pub max_connections: usize,
    /// Most bytes of large result documents (over 512 KiB) held in memory at
    /// once for the requests reading them; a read beyond waits for room, then
    /// answers 503.
    pub result_memory: usize,
}

impl Default for ServeConfig {
    fn default() -> Self {
        let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
        ServeConfig {
            addr: "127.0.0.1:8080".into(),
            database_url: "sqlite://topple.db".into(),
            workers,
            max_body_bytes: 1 << 20,
            max_record_bytes: 64 << 20,
            max_record_samples: crate::jobs::spec::MAX_RECORD_SAMPLES,
            max_wait: Duration::from_secs(60),
            shutdown_grace: Duration::from_secs(20),
            lease: Duration::from_secs(10),
            heartbeat: Duration::from_millis(100),
            instance: format!("{}-{}", hostname(), std::process::id()),
            limits: Limits::default(),
            max_queued: 10_000,
            job_timeout: Duration::from_secs(600),
            api_token: None,
            auth_reads: false,
            tokens_file: None,
            metrics_open: false,
            retention: None,
            max_queued_per_tenant: None,
            cors_origins: Vec::new(),
            header_read_timeout: Duration::from_secs(10),
            idle_timeout: Duration::from_secs(60),
            body_read_timeout: Duration::from_secs(30),
            max_connections: 1024,
            result_memory: 128 << 20,
        }
    }
}

impl ServeConfig {
    /// Whether reading jobs needs a token (a tokens file, or the API token
    /// with `auth_reads`): what is read is then private to whoever presented
    /// it (`Cache-Control: private`).
    pub fn reads_need_token(&self) -> bool {
        self.tokens_file.is_some() || (self.api_token.is_some() && self.auth_reads)
    }
}

fn hostname() -> String {
    std::fs::read_to_string("/etc/hostname")
        .map(|s| s.trim().to_string())
        .ok()
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "topple".into())
}
