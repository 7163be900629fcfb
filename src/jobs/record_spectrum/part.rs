//! The tasks of a record spectrum: a part is a range of block sizes and a
//! range of their scan levels. Sizes are grouped while a task stays short;
//! a size whose scan alone costs more than a task is split along the scale
//! axis, into ranges of levels that share their boundary level, so that
//! every pair of neighbouring levels is refined by exactly one task and the
//! scan and bisection guarantee ([`crate::spectrum::scan`]) holds across the
//! split: the parts assemble into what one task computes.
//!
//! A part's document keeps the levels as the bits of their `f64`s, so that
//! the assembled spectrum is identical to one computed whole whatever the
//! text of a stored document.

use serde::{Deserialize, Serialize};

use super::RecordSpectrumJob;
use crate::jobs::JobError;
use crate::spectrum::Control;
use crate::spectrum::overturning::{Found, scan_range};
use crate::spectrum::scan::{Direction, ModeChange, ScanError, ScanStats, Transition};

/// A task of a record spectrum: sizes `[from, to)` of the job's `p`, levels
/// `[first, last]` (both included) of each size's scan grid.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Part {
    /// Sizes `[from, to)`: indices into the job's `p`.
    pub sizes: [usize; 2],
    /// Levels `[first, last]` of the scan grid.
    pub levels: [usize; 2],
}

/// A transition with its levels as `f64` bits.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct TransitionBits {
    at: u64,
    up: bool,
    mode: u8,
    impacts: u64,
    bracket: [u64; 2],
}

/// A mode change with its levels as `f64` bits.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct ModeChangeBits {
    at: u64,
    from: u8,
    to: u8,
    bracket: [u64; 2],
}

/// What one part found on one size.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
struct LineBits {
    transitions: Vec<TransitionBits>,
    mode_changes: Vec<ModeChangeBits>,
}

/// Scan statistics of a part.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
struct StatsDoc {
    simulations: u64,
    steps: u64,
    rejected: u64,
    rhs_evaluations: u64,
    events: u64,
    max_error_estimate: f64,
}

/// The document of a part, assembled by [`assemble`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PartDoc {
    /// "record_spectrum_part".
    kind: String,
    part: Part,
    /// One entry per size of the part.
    lines: Vec<LineBits>,
    stats: StatsDoc,
    wall_time_s: f64,
}

const PART_KIND: &str = "record_spectrum_part";

impl From<&Transition> for TransitionBits {
    fn from(t: &Transition) -> Self {
        TransitionBits {
            at: t.at.to_bits(),
            up: t.direction == Direction::Up,
            mode: t.mode,
            impacts: t.impacts,
            bracket: [t.bracket.0.to_bits(), t.bracket.1.to_bits()],
        }
    }
}

impl From<&TransitionBits> for Transition {
    fn from(t: &TransitionBits) -> Self {
        Transition {
            at: f64::from_bits(t.at),
            direction: if t.up { Direction::Up } else { Direction::Down },
            mode: t.mode,
            impacts: t.impacts,
            bracket: (f64::from_bits(t.bracket[0]), f64::from_bits(t.bracket[1])),
        }
    }
}

impl From<&ModeChange> for ModeChangeBits {
    fn from(m: &ModeChange) -> Self {
        ModeChangeBits {
            at: m.at.to_bits(),
            from: m.from,
            to: m.to,
            bracket: [m.bracket.0.to_bits(), m.bracket.1.to_bits()],
        }
    }
}

impl From<&ModeChangeBits> for ModeChange {
    fn from(m: &ModeChangeBits) -> Self {
        ModeChange {
            at: f64::from_bits(m.at),
            from: m.from,
            to: m.to,
            bracket: (f64::from_bits(m.bracket[0]), f64::from_bits(m.bracket[1])),
        }
    }
}

impl From<&ScanStats> for StatsDoc {
    fn from(s: &ScanStats) -> Self {
        StatsDoc {
            simulations: s.simulations,
            steps: s.steps,
            rejected: s.rejected,
            rhs_evaluations: s.rhs_evaluations,
            events: s.events,
            max_error_estimate: s.max_error_estimate,
        }
    }
}

impl From<&StatsDoc> for ScanStats {
    fn from(s: &StatsDoc) -> Self {
        ScanStats {
            simulations: s.simulations,
            steps: s.steps,
            rejected: s.rejected,
            rhs_evaluations: s.rhs_evaluations,
            events: s.events,
            max_error_estimate: s.max_error_estimate,
        }
    }
}

impl Part {
    /// The part of `job` named by a task's `payload` (`{"sizes", "levels"}`),
    /// or why it does not fit the job.
    pub fn of(job: &RecordSpectrumJob, payload: &serde_json::Value) -> Result<Part, JobError> {
        let part: Part = serde_json::from_value(payload.clone())
            .map_err(|e| JobError::Task(format!("a task's part does not read: {e}")))?;
        let points = job.grid().points();
        let [from, to] = part.sizes;
        let [first, last] = part.levels;
        if from < to && to <= job.p.len() && first <= last && last < points {
            Ok(part)
        } else {
            Err(JobError::Task(format!(
                "a task's part {payload} does not fit its record_spectrum job ({} sizes, {points} levels)",
                job.p.len()
            )))
        }
    }
}

/// The parts of `job` whose sizes each cost about `per_size` CPU seconds,
/// each part at most about `budget` seconds, at most `max_tasks` of them
/// (longer parts where there would be more). One part is the whole job.
pub fn parts(job: &RecordSpectrumJob, per_size: f64, budget: f64, max_tasks: usize) -> Vec<Part> {
    let n = job.p.len();
    let points = job.grid().points();
    let last = points - 1;
    let budget = budget
        .max(per_size * n as f64 / max_tasks.max(1) as f64)
        .max(f64::MIN_POSITIVE);
    if per_size <= budget || last == 0 {
        let per = ((budget / per_size.max(f64::MIN_POSITIVE)).floor() as usize).clamp(1, n.max(1));
        return (0..n)
            .step_by(per)
            .map(|from| Part {
                sizes: [from, (from + per).min(n)],
                levels: [0, last],
            })
            .collect();
    }
    // Each size in ranges of levels sharing their boundaries.
    let ranges = ((per_size / budget).ceil() as usize)
        .min(max_tasks / n.max(1))
        .clamp(1, last);
    let per = last.div_ceil(ranges);
    (0..n)
        .flat_map(|i| {
            (0..last).step_by(per).map(move |k0| Part {
                sizes: [i, i + 1],
                levels: [k0, (k0 + per).min(last)],
            })
        })
        .collect()
}

/// Scans the sizes and levels of `part`.
pub fn run(job: &RecordSpectrumJob, part: Part, control: &Control) -> Result<PartDoc, ScanError> {
    let started = std::time::Instant::now();
    let problems = job.problems(&job.p[part.sizes[0]..part.sizes[1]])?;
    let (found, stats) = scan_range(
        &problems,
        job.solver.solver(),
        &job.grid(),
        part.levels,
        control,
    )?;
    Ok(PartDoc {
        kind: PART_KIND.into(),
        part,
        lines: found
            .iter()
            .map(|(t, m)| LineBits {
                transitions: t.iter().map(TransitionBits::from).collect(),
                mode_changes: m.iter().map(ModeChangeBits::from).collect(),
            })
            .collect(),
        stats: StatsDoc::from(&stats),
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

/// What the parts found on each size of `job` (in the order of `p`), their
/// statistics summed and their compute time: every size's levels covered,
/// else an error naming the first gap.
pub fn assemble(
    job: &RecordSpectrumJob,
    parts: &[PartDoc],
) -> Result<(Vec<Found>, ScanStats, f64), JobError> {
    let last = job.grid().points() - 1;
    let mut found: Vec<Found> = vec![(Vec::new(), Vec::new()); job.p.len()];
    let mut covered: Vec<Vec<[usize; 2]>> = vec![Vec::new(); job.p.len()];
    let mut stats = ScanStats::default();
    let mut wall = 0.0;
    for doc in parts {
        let [from, to] = doc.part.sizes;
        if doc.kind != PART_KIND || to > job.p.len() || to - from.min(to) != doc.lines.len() {
            return Err(JobError::Task(format!(
                "a task's part {:?} does not fit its record_spectrum job",
                doc.part
            )));
        }
        for (i, line) in (from..to).zip(&doc.lines) {
            found[i]
                .0
                .extend(line.transitions.iter().map(Transition::from));
            found[i]
                .1
                .extend(line.mode_changes.iter().map(ModeChange::from));
            covered[i].push(doc.part.levels);
        }
        stats.absorb(&ScanStats::from(&doc.stats));
        wall += doc.wall_time_s;
    }
    for (i, ranges) in covered.iter_mut().enumerate() {
        ranges.sort_unstable();
        let mut reached = 0;
        for &[first, end] in ranges.iter() {
            if first > reached {
                break;
            }
            reached = reached.max(end);
        }
        if reached < last || ranges.first().is_none_or(|r| r[0] != 0) {
            return Err(JobError::Task(format!(
                "the tasks' parts do not cover size {i}: its levels end at {reached} of {last}"
            )));
        }
    }
    Ok((found, stats, wall))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::Job;

    fn job(sizes: &str) -> RecordSpectrumJob {
        // Two cycles of a 2 Hz sine and a decaying tail: fragmented overturning sets.
        let acc: Vec<String> = (0..300)
            .map(|k| {
                let t = k as f64 * 0.01;
                let a = 0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp();
                format!("{a:.5}")
            })
            .collect();
        let spec = format!(
            r#"{{"kind":"record_spectrum","block":{{"alpha":0.2}},"R_m":{sizes},"scale":{{"to":4}},"ground_motion":{{"dt":0.01,"unit":"g","acc":[{}]}}}}"#,
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
                    sizes: [0, 2],
                    levels: [0, last]
                },
                Part {
                    sizes: [2, 3],
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
                .filter(|q| q.sizes == [i, i + 1])
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
    fn parts_that_leave_a_gap_are_refused() {
        let j = job("[0.5]");
        let last = j.grid().points() - 1;
        let control = Control::new();
        let doc = run(
            &j,
            Part {
                sizes: [0, 1],
                levels: [0, last / 2],
            },
            &control,
        )
        .expect("runs");
        let e = assemble(&j, &[doc]).expect_err("a gap");
        assert!(e.to_string().contains("do not cover size 0"), "{e}");
        assert!(Part::of(&j, &serde_json::json!({"sizes": [0, 2], "levels": [0, 1]})).is_err());
        assert!(
            Part::of(
                &j,
                &serde_json::json!({"sizes": [0, 1], "levels": [0, last]})
            )
            .is_ok()
        );
    }
}
