//! The application put together: the service's state and workers (see
//! [`crate::service`]) behind the API's router (see [`crate::api`]). The one
//! module that knows both, so that the service never reaches up into the API.
//!
//! [`Application::build`] binds the listener, opens the store (applying
//! migrations) and requeues jobs that a dead process left running;
//! [`Application::run_until`] serves until the shutdown future resolves, then
//! stops accepting, lets requests in flight and running jobs finish within
//! the grace period, drops the connections left and requeues the jobs left.

use std::future::Future;
use std::sync::Arc;

use tokio::net::TcpListener;
use tokio::sync::watch;
use tracing::info;

use crate::service::{AppState, Engine, ServeConfig, ServeError, conn, open_store};

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
        let state = AppState::new(store, config, engine)?;
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
            workers.push(tokio::spawn(crate::service::worker::run(
                state.clone(),
                n,
                state.stopping.clone(),
            )));
        }
        if let Some(retention) = state.config.retention {
            tokio::spawn(crate::service::retention::run(
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
        state.stop();
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
