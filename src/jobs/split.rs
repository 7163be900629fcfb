//! Splitting a job into tasks that any instance may compute, and assembling
//! their results into the job's result document.

use serde_json::Value;

/// Most tasks a spectrum is split into.
pub const MAX_TASKS: usize = 256;

/// Simulations a task of a spectrum aims at (whole frequencies; a frequency
/// that needs more is a task of its own): about a seventh of a second of one
/// core. A task is the unit of turns — a small job waits for a task of a big
/// one to finish, not for the big one — and each costs a claim, heartbeats and
/// a write (a few milliseconds on PostgreSQL): small enough for turns, large
/// enough that the queue costs a few per cent.
pub const TASK_SIMULATIONS: f64 = 5_000.0;

/// Record samples one simulation of a pulse costs about as much as: a
/// simulation of a record of N samples counts as N/50 in a task's budget.
const SAMPLES_PER_PULSE_SIMULATION: f64 = 50.0;

/// Record samples stored over all the tasks of a record spectrum (each task
/// carries the record): a long record is split into fewer tasks.
pub const MAX_TASK_SAMPLES: usize = 5_000_000;

/// Chunks of `n` lines of `per_line` simulations each, at most `max_tasks`.
fn chunk_len(n: usize, per_line: f64, max_tasks: usize) -> usize {
    ((TASK_SIMULATIONS / per_line.max(1.0)).floor() as usize)
        .max(n.div_ceil(max_tasks.max(1)))
        .clamp(1, n)
}

/// Frequency chunks of a spectrum's `n` lines of `per_line` simulations
/// each, each record sample costing 1/[`SAMPLES_PER_PULSE_SIMULATION`] of a
/// simulation when the spectrum is of a record of `samples` samples (stored
/// with every task: their total is bounded by [`MAX_TASK_SAMPLES`]).
pub fn line_chunk(n: usize, per_line: f64, samples: Option<usize>) -> usize {
    match samples {
        Some(samples) => {
            let per_line = per_line * (samples as f64 / SAMPLES_PER_PULSE_SIMULATION).max(1.0);
            let max_tasks = MAX_TASKS.min((MAX_TASK_SAMPLES / samples.max(1)).max(1));
            chunk_len(n, per_line, max_tasks)
        }
        None => chunk_len(n, per_line, MAX_TASKS),
    }
}

/// Units of a job split by units of `per_unit_simulations` simulations each
/// (records of `longest_record` samples at most) per task.
pub fn units_per_task(units: usize, per_unit_simulations: f64, longest_record: usize) -> usize {
    let per_unit =
        per_unit_simulations * (longest_record as f64 / SAMPLES_PER_PULSE_SIMULATION).max(1.0);
    // Whole units, rounded up: a unit of long records is already most of a
    // task, and a task costs a claim and two writes.
    ((TASK_SIMULATIONS / per_unit).ceil() as usize)
        .max(units.div_ceil(MAX_TASKS))
        .clamp(1, units.max(1))
}

/// The result document of a spectrum (`kind`, normalised spec `spec`) from
/// its tasks' documents: the lines (`spectrum`) concatenated in task order,
/// the numerics summed (`wall_time_s` is then the tasks' total compute time;
/// `error_estimate` their largest), the first task's `record` kept.
pub fn concatenate(kind: &str, spec: Value, parts: Vec<Value>) -> Value {
    let mut lines = Vec::new();
    let mut numerics = serde_json::Map::new();
    let sum_keys = [
        "simulations",
        "steps_accepted",
        "steps_rejected",
        "rhs_evaluations",
        "events",
    ];
    let mut sums = [0u64; 5];
    let (mut error, mut wall) = (0.0f64, 0.0f64);
    for part in &parts {
        if let Some(s) = part.get("spectrum").and_then(|s| s.as_array()) {
            lines.extend(s.iter().cloned());
        }
        if let Some(n) = part.get("numerics") {
            if numerics.is_empty()
                && let Some(o) = n.as_object()
            {
                numerics = o.clone();
            }
            for (k, key) in sum_keys.iter().enumerate() {
                sums[k] += n.get(*key).and_then(|v| v.as_u64()).unwrap_or(0);
            }
            error = error.max(
                n.get("error_estimate")
                    .and_then(|v| v.as_f64())
                    .unwrap_or(0.0),
            );
            wall += n.get("wall_time_s").and_then(|v| v.as_f64()).unwrap_or(0.0);
        }
    }
    for (k, key) in sum_keys.iter().enumerate() {
        numerics.insert((*key).into(), sums[k].into());
    }
    numerics.insert("error_estimate".into(), error.into());
    numerics.insert("wall_time_s".into(), wall.into());
    numerics.insert("tasks".into(), parts.len().into());
    let mut doc = serde_json::json!({
        "kind": kind,
        "spectrum": lines,
        "numerics": numerics,
        "spec": spec,
    });
    if let Some(record) = parts.first().and_then(|p| p.get("record")) {
        doc["record"] = record.clone();
    }
    doc
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::Job;
    use crate::spectrum::Control;

    #[test]
    fn a_split_spectrum_assembles_to_the_whole() {
        let job = Job::parse(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":{"from":1,"to":8,"steps":70}}"#,
        )
        .expect("valid");
        let tasks = job.split();
        let per = (TASK_SIMULATIONS / (job.size().work / 70.0)).floor() as usize;
        assert!(per >= 1);
        assert_eq!(tasks.len(), 70usize.div_ceil(per));
        let control = Control::new();
        let parts: Vec<Value> = tasks
            .iter()
            .map(|t| t.run(&control).expect("runs"))
            .collect();
        let assembled = job.assemble(parts).expect("assembles");
        let whole = job.run(&control).expect("runs");
        assert_eq!(assembled["spectrum"], whole["spectrum"]);
        assert_eq!(assembled["spec"], whole["spec"]);
        assert_eq!(
            assembled["numerics"]["simulations"],
            whole["numerics"]["simulations"]
        );
        assert_eq!(assembled["numerics"]["tasks"], tasks.len());
    }

    #[test]
    fn a_large_spectrum_is_split_into_at_most_max_tasks_of_about_task_simulations() {
        // A fine grid: one frequency is a task of its own, and 1,000 of them
        // make 250 tasks of 4.
        let job = Job::parse(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":{"from":1,"to":8,"steps":1000},"scan_step_alpha_g":0.002}"#,
        )
        .expect("valid");
        assert!(job.size().work / 1000.0 > TASK_SIMULATIONS);
        let tasks = job.split();
        assert_eq!(tasks.len(), 250);
        let per: Vec<usize> = tasks
            .iter()
            .map(|t| match t {
                Job::Spectrum(s) => s.omega_ratio.len(),
                _ => 0,
            })
            .collect();
        assert!(per.iter().all(|&n| n == 4), "{per:?}");
        // The default grid (about 1,100 simulations a frequency): tasks of 4.
        let job = Job::parse(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"nonlinear","omega_ratio":{"from":0.25,"to":10,"steps":400},"a_max_alpha_g":20,"tolerance":1e-4}"#,
        )
        .expect("valid");
        let per_frequency = job.size().work / 400.0;
        let tasks = job.split();
        for t in &tasks {
            let Job::Spectrum(s) = t else {
                panic!("a spectrum task");
            };
            assert!(s.omega_ratio.len() as f64 * per_frequency <= TASK_SIMULATIONS);
        }
        assert!(tasks.len() < 400 && tasks.len() > 50, "{}", tasks.len());
    }

    #[test]
    fn other_jobs_are_one_task() {
        let job = Job::parse(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":5,"a_p_alpha_g":4}}"#,
        )
        .expect("valid");
        assert_eq!(job.split(), vec![job.clone()]);
    }
}
