//! A record spectrum's tasks ([`crate::jobs::scan_parts`]): its sizes are
//! the lines of one scan grid; a task is a range of sizes and of their
//! levels.

use super::RecordSpectrumJob;
use super::run::Lines;
use crate::jobs::JobError;
use crate::jobs::scan_parts::{self, Group, Part, PartDoc};
use crate::spectrum::Control;
use crate::spectrum::overturning::Found;
use crate::spectrum::pilot::{self, Sample};
use crate::spectrum::scan::{ScanError, ScanStats};

/// The kind of a record spectrum's part document.
const PART_KIND: &str = "record_spectrum_part";

/// The sizes of `job`, one group of lines of `per_size` CPU seconds each.
fn groups(job: &RecordSpectrumJob, per_size: f64) -> [Group; 1] {
    [Group {
        lines: job.p.len(),
        points: job.grid().points(),
        line_s: per_size,
    }]
}

/// Whether `part`, read back from a task, is a part of `job`, or why not.
pub fn fits(job: &RecordSpectrumJob, part: &Part) -> Result<(), JobError> {
    part.fits(&groups(job, 0.0))
}

/// The parts of `job` whose sizes each cost about `per_size` CPU seconds,
/// each part at most about `budget` seconds, at most `max_tasks` of them.
pub fn parts(job: &RecordSpectrumJob, per_size: f64, budget: f64, max_tasks: usize) -> Vec<Part> {
    scan_parts::parts(&groups(job, per_size), budget, max_tasks)
}

/// Runs brackets of the scan of `job` spread over its sizes and levels, on
/// `threads` threads, until `spent` says each thread's have cost enough (or
/// stops them at `deadline`)
/// ([`crate::spectrum::pilot::sample`], at most
/// [`crate::jobs::cost::SAMPLE_BRACKETS`]).
pub fn sample(
    job: &RecordSpectrumJob,
    threads: usize,
    deadline: std::time::Duration,
    spent: impl Fn(&Sample) -> bool + Sync,
) -> Result<Sample, ScanError> {
    let (grid, model) = (job.grid(), job.model());
    let count = [crate::jobs::cost::SAMPLE_BRACKETS[1] as usize, threads];
    match job.lines(&job.p)? {
        Lines::Plain(q) => pilot::sample(&q, model, &grid, count, deadline, spent),
        Lines::Paired(q) => pilot::sample(&q, model, &grid, count, deadline, spent),
    }
}

/// Scans the sizes and levels of `part`.
pub fn run(job: &RecordSpectrumJob, part: Part, control: &Control) -> Result<PartDoc, ScanError> {
    let grid = job.grid();
    let model = job.model();
    match job.lines(&job.p[part.range()])? {
        Lines::Plain(q) => scan_parts::run(PART_KIND, part, &q, model, &grid, control),
        Lines::Paired(q) => scan_parts::run(PART_KIND, part, &q, model, &grid, control),
    }
}

/// What the parts found on each size of `job` (in the order of `p`), their
/// statistics summed and their compute time.
pub fn assemble(
    job: &RecordSpectrumJob,
    parts: &[PartDoc],
) -> Result<(Vec<Found>, ScanStats, f64), JobError> {
    scan_parts::assemble(PART_KIND, &groups(job, 0.0), parts)
}

/// The parts of `job` of `size` (its model's, or measured on a sample), of
/// about [`crate::jobs::cost::TASK_CPU_S`] each, each size costing its share
/// of the job's estimate.
pub fn cut(job: &RecordSpectrumJob, size: &crate::jobs::kind::Size) -> Vec<Part> {
    parts(
        job,
        size.cpu_s / job.p.len().max(1) as f64,
        crate::jobs::cost::TASK_CPU_S,
        crate::jobs::split::MAX_PART_TASKS,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::Job;

    fn job(sizes: &str) -> RecordSpectrumJob {
        job_on(sizes, "")
    }

    /// `job(sizes)` with `extra` fields (`,"contact":…`).
    fn job_on(sizes: &str, extra: &str) -> RecordSpectrumJob {
        // Two cycles of a 2 Hz sine and a decaying tail: fragmented overturning sets.
        let acc: Vec<String> = (0..300)
            .map(|k| {
                let t = k as f64 * 0.01;
                let a = 0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp();
                format!("{a:.5}")
            })
            .collect();
        let spec = format!(
            r#"{{"kind":"record_spectrum","block":{{"alpha":0.2}},"R_m":{sizes},"scale":{{"to":4}},"ground_motion":{{"dt":0.01,"unit":"g","acc":[{}]}}{extra}}}"#,
            acc.join(",")
        );
        match Job::parse(&spec).expect("valid") {
            Job::RecordSpectrum(j) => *j,
            other => panic!("not a record spectrum: {other:?}"),
        }
    }

    #[test]
    fn parts_tile_the_sizes_and_levels() {
        let j = job("[0.5, 1.0, 2.0]");
        let last = j.grid().points() - 1;
        // Cheap sizes: grouped, whole lines.
        let p = parts(&j, 0.1, 0.25, 256);
        assert_eq!(
            p,
            vec![
                Part {
                    lines: [0, 2],
                    levels: [0, last]
                },
                Part {
                    lines: [2, 3],
                    levels: [0, last]
                }
            ]
        );
        // Dear sizes: each split along the levels, ranges sharing boundaries.
        let p = parts(&j, 1.0, 0.3, 256);
        assert_eq!(p.len(), 3 * 4);
        for i in 0..3 {
            let ranges: Vec<[usize; 2]> = p
                .iter()
                .filter(|q| q.lines == [i, i + 1])
                .map(|q| q.levels)
                .collect();
            assert_eq!(ranges.first().map(|r| r[0]), Some(0));
            assert_eq!(ranges.last().map(|r| r[1]), Some(last));
            assert!(ranges.windows(2).all(|w| w[0][1] == w[1][0]), "{ranges:?}");
        }
        // At most max_tasks.
        assert!(parts(&j, 100.0, 0.01, 10).len() <= 10);
        assert!(parts(&j, 100.0, 0.01, 100).len() <= 100);
    }

    #[test]
    fn a_spectrum_split_along_the_scale_assembles_to_the_whole() {
        let j = job("[0.4, 1.5]");
        let control = Control::new();
        let whole = j.run(&control).expect("runs");
        let last = j.grid().points() - 1;
        assert!(last > 20, "{last}");
        let mut transitions_found = 0;
        for budget in [0.5, 0.2, 0.07] {
            let split = parts(&j, 1.0, budget, 256);
            assert!(split.len() > 2, "{split:?}");
            let docs: Vec<PartDoc> = split
                .iter()
                .map(|&p| {
                    // Through text, as a stored task result is.
                    let doc = run(&j, p, &control).expect("runs");
                    let text = serde_json::to_string(&doc).expect("writes");
                    serde_json::from_str(&text).expect("reads")
                })
                .collect();
            let assembled = j.result_of(&docs).expect("assembles");
            assert_eq!(assembled.spectrum, whole.spectrum);
            transitions_found = assembled.spectrum.iter().map(|s| s.transitions.len()).sum();
            // The same bisections; only levels where chunks or parts meet
            // are simulated twice.
            let (a, w) = (
                assembled.numerics.cost.simulations,
                whole.numerics.cost.simulations,
            );
            let meeting = 2 * (split.len() + 2 * (last / 48 + 1)) as u64;
            assert!(a.abs_diff(w) <= meeting, "{a} vs {w}");
        }
        assert!(transitions_found > 2, "{transitions_found}");
    }

    #[test]
    fn on_a_coulomb_floor_the_sizes_follow_it_and_parts_still_assemble() {
        let control = Control::new();
        let pure = job("[0.5, 2.0]").run(&control).expect("runs");
        // μ = 10 is never reached before these blocks overturn.
        let rough = job_on("[0.5, 2.0]", r#","contact":{"model":"coulomb","mu":10}"#);
        let r = rough.run(&control).expect("runs");
        for (a, b) in pure.spectrum.iter().zip(&r.spectrum) {
            assert!(a.min_overturn_scale.is_some());
            assert_eq!(a.min_overturn_scale, b.min_overturn_scale);
        }
        // μ = 0.15 < tan 0.2: the blocks slide and never overturn.
        let slick = job_on("[0.5, 2.0]", r#","contact":{"model":"coulomb","mu":0.15}"#);
        let s = slick.run(&control).expect("runs");
        assert!(
            s.spectrum.iter().all(|l| l.transitions.is_empty()),
            "{:?}",
            s.spectrum
        );
        // Split along the scale axis, the parts assemble to the whole.
        let last = rough.grid().points() - 1;
        let split = [
            Part {
                lines: [0, 2],
                levels: [0, last / 3],
            },
            Part {
                lines: [0, 2],
                levels: [last / 3, last],
            },
        ];
        let docs: Vec<PartDoc> = split
            .iter()
            .map(|&p| run(&rough, p, &control).expect("runs"))
            .collect();
        assert_eq!(
            rough.result_of(&docs).expect("assembles").spectrum,
            r.spectrum
        );
    }

    #[test]
    fn parts_that_leave_a_gap_are_refused() {
        let j = job("[0.5]");
        let last = j.grid().points() - 1;
        let control = Control::new();
        let doc = run(
            &j,
            Part {
                lines: [0, 1],
                levels: [0, last / 2],
            },
            &control,
        )
        .expect("runs");
        let e = assemble(&j, &[doc]).expect_err("a gap");
        assert!(e.to_string().contains("do not cover line 0"), "{e}");
        // A part as stored (its lines once named `sizes`), read back.
        let read = |v: serde_json::Value| serde_json::from_value::<Part>(v).expect("a part");
        let beyond = read(serde_json::json!({"sizes": [0, 2], "levels": [0, 1]}));
        assert!(fits(&j, &beyond).is_err());
        let first = read(serde_json::json!({"sizes": [0, 1], "levels": [0, last]}));
        assert!(fits(&j, &first).is_ok());
    }
}
