//! Retention: finished jobs older than `retention` are deleted, and with
//! them the computations and results no job refers to any more.

use std::time::{Duration, SystemTime};

use tokio::sync::watch;
use tracing::{info, warn};

use super::AppState;
use crate::store::rfc3339;

/// How often jobs past retention are looked for: a quarter of the retention
/// period, between 1 s and 10 min.
pub fn interval(retention: Duration) -> Duration {
    (retention / 4).clamp(Duration::from_secs(1), Duration::from_secs(600))
}

/// Purges jobs finished more than `retention` ago, at start and then every
/// [`interval`], until shutdown.
pub async fn run(state: AppState, retention: Duration, mut shutdown: watch::Receiver<bool>) {
    loop {
        if *shutdown.borrow() {
            break;
        }
        let before = rfc3339(
            SystemTime::now()
                .checked_sub(retention)
                .unwrap_or(SystemTime::UNIX_EPOCH),
        );
        match state.store.purge(&before).await {
            Ok(0) => {}
            Ok(n) => {
                info!(target: "audit", action = "purge", jobs = n, finished_before = %before, "audit")
            }
            Err(e) => warn!(error = %e, "purging jobs past retention failed"),
        }
        tokio::select! {
            _ = shutdown.changed() => {}
            _ = tokio::time::sleep(interval(retention)) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_four_times_per_period_within_bounds() {
        assert_eq!(interval(Duration::from_secs(40)), Duration::from_secs(10));
        assert_eq!(interval(Duration::from_millis(100)), Duration::from_secs(1));
        assert_eq!(
            interval(Duration::from_secs(30 * 86_400)),
            Duration::from_secs(600)
        );
    }
}
