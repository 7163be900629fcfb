//! Prometheus metrics of one instance (a recorder of its own, so that several
//! instances can live in one process, as in the tests).

use metrics::{Counter, Gauge, Histogram, Key, Label, Metadata, Recorder};
use metrics_exporter_prometheus::{PrometheusBuilder, PrometheusHandle, PrometheusRecorder};

use crate::kinds::KINDS;
use crate::store::Status;

const META: Metadata<'static> = Metadata::new("topple", metrics::Level::INFO, Some("topple"));

/// The instance's metrics.
pub struct Metrics {
    recorder: PrometheusRecorder,
    handle: PrometheusHandle,
    /// Submissions answered from an existing job.
    pub cache_hits: Counter,
    /// Jobs submitted (new work).
    pub submitted: Counter,
    /// Submissions refused because the queue was full.
    pub rejected_full: Counter,
    /// Jobs failed for running past the compute-time limit.
    pub timed_out: Counter,
    /// Connections open now.
    pub connections_open: Gauge,
    /// Connections accepted.
    pub connections_accepted: Counter,
    /// Connections closed for sending request headers too slowly.
    pub closed_header_timeout: Counter,
    /// Connections closed after idling past the idle timeout.
    pub closed_idle_timeout: Counter,
    /// Connections dropped when the shutdown grace period ran out.
    pub closed_at_shutdown: Counter,
    /// Failed accepts (other than connections reset before they were accepted).
    pub accept_errors: Counter,
    /// Requests answered 408 because their body came too slowly.
    pub body_timeouts: Counter,
    /// Reads of a succeeded job (status or result) answered from memory.
    pub succeeded_from_memory: Counter,
    /// Reads of a succeeded job that went to the database.
    pub succeeded_from_database: Counter,
    jobs: Vec<(Status, Gauge)>,
    queue_depth: Gauge,
    compute: Vec<(&'static str, Histogram)>,
}

impl std::fmt::Debug for Metrics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Metrics")
    }
}

impl Default for Metrics {
    fn default() -> Self {
        Metrics::new()
    }
}

impl Metrics {
    /// A fresh set.
    pub fn new() -> Self {
        let recorder = PrometheusBuilder::new().build_recorder();
        let handle = recorder.handle();
        let counter = |name: &'static str| recorder.register_counter(&Key::from_name(name), &META);
        let cache_hits = counter("topple_cache_hits_total");
        let submitted = counter("topple_jobs_submitted_total");
        let rejected_full = counter("topple_jobs_rejected_queue_full_total");
        let timed_out = counter("topple_jobs_timed_out_total");
        let connections_open =
            recorder.register_gauge(&Key::from_name("topple_connections_open"), &META);
        let connections_accepted = counter("topple_connections_accepted_total");
        let closed = |reason: &'static str| {
            let key = Key::from_parts(
                "topple_connections_closed_total",
                vec![Label::new("reason", reason)],
            );
            recorder.register_counter(&key, &META)
        };
        let closed_header_timeout = closed("header_timeout");
        let closed_idle_timeout = closed("idle_timeout");
        let closed_at_shutdown = closed("shutdown");
        let accept_errors = counter("topple_accept_errors_total");
        let body_timeouts = counter("topple_request_body_timeouts_total");
        let succeeded_read = |from: &'static str| {
            let key = Key::from_parts(
                "topple_succeeded_reads_total",
                vec![Label::new("from", from)],
            );
            recorder.register_counter(&key, &META)
        };
        let succeeded_from_memory = succeeded_read("memory");
        let succeeded_from_database = succeeded_read("database");
        let jobs = Status::ALL
            .iter()
            .map(|&s| {
                let key = Key::from_parts("topple_jobs", vec![Label::new("status", s.as_str())]);
                (s, recorder.register_gauge(&key, &META))
            })
            .collect();
        let queue_depth = recorder.register_gauge(&Key::from_name("topple_queue_depth"), &META);
        let compute = KINDS
            .iter()
            .map(|&k| {
                let key = Key::from_parts("topple_compute_seconds", vec![Label::new("kind", k)]);
                (k, recorder.register_histogram(&key, &META))
            })
            .collect();
        Metrics {
            recorder,
            handle,
            cache_hits,
            submitted,
            rejected_full,
            timed_out,
            connections_open,
            connections_accepted,
            closed_header_timeout,
            closed_idle_timeout,
            closed_at_shutdown,
            accept_errors,
            body_timeouts,
            succeeded_from_memory,
            succeeded_from_database,
            jobs,
            queue_depth,
            compute,
        }
    }

    /// Records the compute time of a job of `kind`.
    pub fn compute_seconds(&self, kind: &str, seconds: f64) {
        if let Some((_, h)) = self.compute.iter().find(|(k, _)| *k == kind) {
            h.record(seconds);
        }
    }

    /// Prometheus text, with the job counts as they are now.
    pub fn render(&self, counts: &[(Status, i64)]) -> String {
        for (status, gauge) in &self.jobs {
            let n = counts.iter().find(|(s, _)| s == status).map_or(0, |c| c.1);
            gauge.set(n as f64);
            if *status == Status::Queued {
                self.queue_depth.set(n as f64);
            }
        }
        let _ = &self.recorder;
        self.handle.render()
    }
}
