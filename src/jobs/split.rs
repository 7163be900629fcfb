//! Splitting a job into tasks that any instance may compute, and assembling
//! their results into the job's result document.

/// Most tasks a job of cheap lines (a pulse spectrum, a fragility
/// campaign) is split into: past this, its tasks grow longer than
/// [`TASK_CPU_S`] — a big job pays less for the queue, and its tasks stay
/// well under a second (a 2,000-frequency spectrum's hold 8 frequencies).
pub const MAX_TASKS: usize = 256;

/// Most tasks of a job whose lines are dear (a record spectrum, split along
/// its scale axis): its tasks stay short however long its record.
pub const MAX_PART_TASKS: usize = 4096;

pub use super::cost::TASK_CPU_S;

/// Lines per task of a job of `n` lines of `per_line` CPU seconds each: as
/// many as fit in [`TASK_CPU_S`] (a line that costs more is a task of its
/// own), in at most [`MAX_TASKS`] tasks. A task is the unit of turns — a
/// small job waits for a task of a big one to finish, not for the big one —
/// and each costs a claim, heartbeats and a write: short enough for turns,
/// long enough that the queue costs a few per cent.
pub fn per_task(n: usize, per_line: f64) -> usize {
    let fit = (TASK_CPU_S / per_line.max(f64::MIN_POSITIVE)).floor();
    (fit.min(n as f64) as usize)
        .max(n.div_ceil(MAX_TASKS))
        .clamp(1, n.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::Job;
    use crate::spectrum::Control;
    use serde_json::Value;

    #[test]
    fn a_split_spectrum_assembles_to_the_whole() {
        // Pure rocking; and on a Coulomb floor with the pure-rocking
        // spectrum beside it, whose tasks carry both lines.
        for (spec, lines, beside) in [
            (
                r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":{"from":1,"to":8,"steps":70}}"#,
                70,
                false,
            ),
            (
                r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":{"from":2,"to":6,"steps":6},"a_max_alpha_g":5,"tolerance":1e-3,"scan_step_alpha_g":0.02,"contact":{"model":"coulomb","mu":0.3},"no_sliding_beside":true}"#,
                6,
                true,
            ),
        ] {
            let job = Job::parse(spec).expect("valid");
            let tasks = job.split();
            let per = per_task(lines, job.size().cpu_s / lines as f64);
            assert!((1..lines).contains(&per), "{per}");
            assert_eq!(tasks.len(), lines.div_ceil(per));
            let control = Control::new();
            let parts: Vec<Value> = tasks
                .iter()
                .map(|t| t.run(&control).expect("runs"))
                .collect();
            let assembled = job.assemble(parts).expect("assembles");
            let whole = job.run(&control).expect("runs");
            assert_eq!(assembled["spectrum"], whole["spectrum"]);
            assert_eq!(assembled.get("no_sliding"), whole.get("no_sliding"));
            assert_eq!(
                whole["no_sliding"].as_array().map(Vec::len),
                beside.then_some(lines),
                "{spec}"
            );
            assert_eq!(assembled["spec"], whole["spec"]);
            assert_eq!(
                assembled["numerics"]["simulations"],
                whole["numerics"]["simulations"]
            );
            assert_eq!(assembled["numerics"]["tasks"], tasks.len());
        }
    }

    #[test]
    fn a_spectrum_is_split_into_tasks_of_about_task_cpu_s() {
        // A fine grid (10,000 scan points a frequency) of 1,000 frequencies:
        // 250 tasks of 4; the default grid: a few frequencies a task.
        for spec in [
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":{"from":1,"to":8,"steps":1000},"scan_step_alpha_g":0.002}"#,
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14,"eta":0.9},"pulse":{"type":"one_sine"},"formulation":"nonlinear","omega_ratio":{"from":0.25,"to":10,"steps":400},"a_max_alpha_g":20,"tolerance":1e-4}"#,
        ] {
            let job = Job::parse(spec).expect("valid");
            let whole = job.size();
            let tasks = job.split();
            assert!(tasks.len() > 1 && tasks.len() <= MAX_TASKS);
            let mut lines = 0;
            for t in &tasks {
                let crate::kinds::Task::Spectrum(s) = t else {
                    panic!("a spectrum task");
                };
                lines += s.job.omega_ratio.len();
                // At most TASK_CPU_S, unless MAX_TASKS tasks must hold
                // the job: then its lines spread evenly over them.
                let line = whole.cpu_s / job_lines(&job) as f64;
                let least = job_lines(&job).div_ceil(MAX_TASKS) as f64 * line;
                assert!(
                    t.size().cpu_s <= TASK_CPU_S.max(least) * (1.0 + 1e-12),
                    "{:?}",
                    t.size()
                );
                // Not much shorter either: tasks are filled.
                assert!(
                    t.size().cpu_s > TASK_CPU_S / 2.0 || t == tasks.last().expect("a task"),
                    "{:?}",
                    t.size()
                );
            }
            assert_eq!(lines, job_lines(&job));
            assert!(
                (tasks.iter().map(|t| t.size().cpu_s).sum::<f64>() - whole.cpu_s).abs()
                    < 1e-9 * whole.cpu_s
            );
        }
    }

    fn job_lines(job: &Job) -> usize {
        match job {
            Job::Spectrum(s) => s.omega_ratio.len(),
            _ => 0,
        }
    }

    #[test]
    fn other_jobs_are_one_task() {
        let job = Job::parse(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":5,"a_p_alpha_g":4}}"#,
        )
        .expect("valid");
        assert_eq!(job.split(), vec![crate::kinds::Task::whole(job.clone())]);
    }
}
