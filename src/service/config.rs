//! How a service instance is set up.

use std::time::Duration;

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
}

impl Default for ServeConfig {
    fn default() -> Self {
        let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
        ServeConfig {
            addr: "127.0.0.1:8080".into(),
            database_url: "sqlite://topple.db".into(),
            workers,
            max_body_bytes: 1 << 20,
            max_wait: Duration::from_secs(60),
            shutdown_grace: Duration::from_secs(20),
            lease: Duration::from_secs(10),
            heartbeat: Duration::from_millis(100),
            instance: format!("{}-{}", hostname(), std::process::id()),
        }
    }
}

fn hostname() -> String {
    std::fs::read_to_string("/etc/hostname")
        .map(|s| s.trim().to_string())
        .ok()
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "topple".into())
}
