//! What a scan under a record will cost, measured on a sample of it.
//!
//! Under a pulse a line's bisection refines a handful of transitions
//! (Figs. 6, 10, 11 show at most four); under a record the outcome signature
//! (overturned, mode, impact count) changes between many neighbouring
//! levels, and under a chaotic record at nearly every scale, so that one
//! bracket of the scan grid costs anything from one simulation to 2^S (S
//! bisection steps). Nothing read off the record alone foresees which. A
//! sample of the grid's brackets, each classified and bisected as
//! [`Line::scan`](super::scan::Line::scan) bisects it, measures it
//! ([`sample`]); the verification that follows a scan is not sampled.

use crate::dynamics::Problem;

use super::control::Control;
use super::overturning::ScanGrid;
use super::scan::{Line, Model, Scalable, ScanError, ScanStats};

/// The fractional part of the golden ratio: brackets `j·φ` apart (mod 1)
/// spread evenly over a line without following its grid.
const PHI: f64 = 0.618_033_988_749_894_9;

/// The brackets a sample ran and what they cost.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sample {
    /// Brackets run (pairs of neighbouring levels).
    pub brackets: u64,
    /// Their cost, both ends of each bracket included.
    pub stats: ScanStats,
    /// CPU seconds their threads spent on them.
    pub cpu_s: f64,
}

impl Sample {
    /// Simulations of the scan of `lines` lines of `points` levels each, as
    /// this sample foresees them: every level once, and each bracket's
    /// bisection (a bracket's ends are levels; its bisection is what the
    /// sample ran beyond its two ends). `None` for an empty sample.
    pub fn simulations(&self, lines: usize, points: usize) -> Option<f64> {
        if self.brackets == 0 {
            return None;
        }
        let bisection = self.stats.simulations as f64 / self.brackets as f64 - 2.0;
        let brackets = (lines * points.saturating_sub(1)) as f64;
        Some((lines * points) as f64 + brackets * bisection.max(0.0))
    }

    /// CPU seconds of one of its simulations.
    pub fn simulation_cpu_s(&self) -> f64 {
        self.cpu_s / self.stats.simulations.max(1) as f64
    }

    fn absorb(&mut self, other: &Sample) {
        self.brackets += other.brackets;
        self.stats.absorb(&other.stats);
        self.cpu_s += other.cpu_s;
    }
}

/// CPU seconds the calling thread has run (`CLOCK_THREAD_CPUTIME_ID`): what
/// a sample costs, whatever else the machine runs beside it; 0 where the
/// system does not tell.
pub fn thread_cpu_s() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given, which lives
    // for the call.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    if status == 0 {
        t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
    } else {
        0.0
    }
}

/// Runs up to `count` brackets of the scan of `problems` over `grid` on
/// `threads` threads (bracket `j`: of line `j mod lines`, at `frac(½ + j·φ)`
/// along it; thread `t` runs the brackets `j ≡ t` mod `threads`), each
/// thread stopping early once `spent` says its brackets have cost enough
/// (it is asked after each, with that thread's sample so far). A sample
/// still running after `deadline` (a bracket of a long record can cost
/// hundreds of simulations) is stopped: [`ScanError::Canceled`].
pub fn sample<G: Scalable + Sync>(
    problems: &[Problem<G>],
    model: Model,
    grid: &ScanGrid,
    [count, threads]: [usize; 2],
    deadline: std::time::Duration,
    spent: impl Fn(&Sample) -> bool + Sync,
) -> Result<Sample, ScanError> {
    let points = grid.points();
    if problems.is_empty() || points < 2 {
        return Ok(Sample::default());
    }
    let threads = threads.clamp(1, count.max(1));
    let control = &Control::new();
    let run = |t: usize| -> Result<Sample, ScanError> {
        let mut sample = Sample::default();
        for j in (t..count).step_by(threads) {
            let line = Line {
                problem: problems[j % problems.len()].clone(),
                model,
                control,
            };
            let u = (0.5 + j as f64 * PHI).fract();
            let k = ((u * (points - 1) as f64) as usize).min(points - 2);
            let start = thread_cpu_s();
            line.bracket(
                grid.level(k),
                grid.level(k + 1),
                grid.tolerance,
                &mut sample.stats,
            )?;
            sample.cpu_s += thread_cpu_s() - start;
            sample.brackets += 1;
            if spent(&sample) {
                break;
            }
        }
        Ok(sample)
    };
    let parts: Vec<Result<Sample, ScanError>> = std::thread::scope(|scope| {
        // The watch: cancels the sample at its deadline, or ends with it.
        let (done, ended) = std::sync::mpsc::channel::<()>();
        scope.spawn(move || {
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = ended.recv_timeout(deadline) {
                control.cancel();
            }
        });
        let handles: Vec<_> = (1..threads).map(|t| scope.spawn(move || run(t))).collect();
        let mut parts = vec![run(0)];
        parts.extend(
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))),
        );
        drop(done);
        parts
    });
    let mut sample = Sample::default();
    for part in parts {
        sample.absorb(&part?);
    }
    Ok(sample)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Block, Formulation, Method, Record, Solver};
    use std::time::Duration;

    /// A deadline no test sample reaches.
    const LONG: Duration = Duration::from_secs(600);

    /// The block of size `r` m (α = 0.2) under a record of two cycles of a
    /// 2 Hz sine decaying over 1.5 s, 0.4 g.
    fn problem(r: f64) -> Problem<Record> {
        let acc: Vec<f64> = (0..300)
            .map(|k| {
                let t = k as f64 * 0.01;
                0.4 * 9.81 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp()
            })
            .collect();
        let p = (3.0 * 9.81 / (4.0 * r)).sqrt();
        Problem {
            block: Block::new(0.2, p, None, None, None).expect("a block"),
            pulse: Record::new(acc.into(), 0.01).expect("a record"),
            formulation: Formulation::Nonlinear,
        }
    }

    fn grid() -> ScanGrid {
        ScanGrid {
            from: 1.0,
            to: 4.0,
            step: 0.05,
            tolerance: 1e-4,
            principal_relative_width: 0.0,
        }
    }

    fn model() -> Model {
        Model {
            solver: Solver::RungeKutta {
                method: Method::Dop853,
                rtol: 1e-10,
                atol: 1e-12,
            },
            friction: None,
            slide_band: None,
        }
    }

    #[test]
    fn a_sample_of_every_bracket_foresees_the_scan_without_its_verification() {
        let problems = vec![problem(0.5), problem(1.5)];
        let (g, control) = (grid(), Control::new());
        let mut scan = ScanStats::default();
        for q in &problems {
            let line = Line {
                problem: q.clone(),
                model: model(),
                control: &control,
            };
            let levels = (0..g.points()).map(|k| g.level(k));
            line.scan(levels, g.step, g.tolerance, &mut scan)
                .expect("a scan");
        }
        let bisected = scan.simulations - scan.probes;
        // As many brackets as the grid has: each of them, once (the golden
        // ratio's sequence visits every bracket of a short line).
        let brackets = 2 * (g.points() - 1);
        let s = sample(&problems, model(), &g, [40 * brackets, 2], LONG, |s| {
            s.brackets as usize >= 10 * brackets
        })
        .expect("a sample");
        assert_eq!(s.brackets as usize, 20 * brackets);
        assert!(s.cpu_s > 0.0 && s.simulation_cpu_s() < s.cpu_s, "{s:?}");
        let foreseen = s.simulations(2, g.points()).expect("brackets");
        let ratio = foreseen / bisected as f64;
        assert!(
            (0.8..1.25).contains(&ratio),
            "{foreseen} foreseen, {bisected} bisected"
        );
    }

    #[test]
    fn a_sample_stops_when_it_has_cost_enough_and_an_empty_one_foresees_nothing() {
        let problems = vec![problem(1.0)];
        let s = sample(&problems, model(), &grid(), [100, 1], LONG, |s| {
            s.stats.simulations >= 10
        })
        .expect("a sample");
        assert!(s.brackets < 10 && s.stats.simulations >= 10, "{s:?}");
        let none = sample::<Record>(&[], model(), &grid(), [100, 2], LONG, |_| false)
            .expect("nothing to run");
        assert_eq!(none.simulations(1, 10), None);
    }

    #[test]
    fn a_sample_past_its_deadline_is_stopped() {
        // Every bracket of the line, without a budget: far beyond 1 ms.
        let problems = vec![problem(0.5), problem(1.5)];
        let started = std::time::Instant::now();
        let r = sample(
            &problems,
            model(),
            &grid(),
            [10_000, 2],
            Duration::from_millis(1),
            |_| false,
        );
        assert!(matches!(r, Err(ScanError::Canceled(_))), "{r:?}");
        assert!(started.elapsed() < Duration::from_secs(5));
    }
}
