//! A forensic query's scan lines and its tasks ([`crate::jobs::scan_parts`]).
//!
//! Each observation's block is scanned on its own grid of levels, in its
//! α g (or g α linear: eq. 8 and 9 scaled so that rocking starts at 1), from
//! where it starts to rock to the highest amplitude examined: one line per
//! pulse frequency, or one line under a record. The lines of an observation
//! share its grid and form a [`Group`]; a task is a range of an
//! observation's lines and of their levels, and the tasks' transitions
//! assemble into what one task finds.

use super::{
    AmplitudeRange, ForensicJob, ForensicResult, LineSet, overturning_set, slide_band_set,
};
use crate::dynamics::{Block, Problem, Pulse, SimError};
use crate::jobs::JobError;
use crate::jobs::cost;
use crate::jobs::kind::Size;
use crate::jobs::scan_parts::{self, Group, Part, PartDoc};
use crate::spectrum::Control;
use crate::spectrum::overturning::{Found, ScanGrid, threshold_alpha_g};
use crate::spectrum::scan::{ScanError, ScanStats};

/// The kind of a forensic query's part document.
const PART_KIND: &str = "forensic_part";

/// Levels a scan chunk holds (simulations that can run at once per chunk).
const LANE_POINTS: f64 = 48.0;

/// One observation's scan.
#[derive(Clone, Copy, Debug)]
pub struct ObservationScan {
    /// Its block.
    pub block: Block,
    /// Its α (slenderness), rad.
    pub alpha: f64,
    /// Where it starts to rock, in its α g.
    pub threshold: f64,
    /// Its grid; `None` when it does not rock in the range examined.
    pub grid: Option<ScanGrid>,
}

fn bad_block(e: impl Into<SimError>) -> ScanError {
    ScanError::Simulation(e.into())
}

impl ForensicJob {
    /// Lines of each observation: its pulse frequencies, or the record.
    pub fn lines_per_observation(&self) -> usize {
        if self.ground_motion.is_some() {
            1
        } else {
            self.frequency_hz.len()
        }
    }

    /// Every observation's block and grid.
    pub fn observation_scans(&self) -> Result<Vec<ObservationScan>, ScanError> {
        let AmplitudeRange { to, .. } = self.range_g();
        // A record's samples (its threshold under its own vertical samples).
        let horizontal: &[f64] = self.ground_motion.as_ref().map_or(&[], |g| &g.acc);
        self.observations
            .iter()
            .map(|o| {
                let block = o.block.block().map_err(bad_block)?;
                let alpha = block.slenderness();
                let threshold = threshold_alpha_g(self.formulation, &block);
                let threshold = match self.scaled_vertical() {
                    Some(v) => v.threshold(threshold, self.formulation, alpha, horizontal),
                    None => threshold,
                };
                // From the threshold, whatever `from` is: the state at the
                // range's start is then known, not assumed. A seen slide
                // is scanned from below where the block can first slip.
                let start = match (&self.contact, o.slid_m) {
                    (Some(c), Some(_)) => threshold.min(self.slip_free_g(c.mu) / alpha),
                    _ => threshold,
                };
                let grid = (to / alpha > start).then(|| ScanGrid {
                    from: start,
                    to: to / alpha,
                    step: self.scan_step_g / alpha,
                    tolerance: self.tolerance_g / alpha,
                    principal_relative_width: 0.0,
                });
                Ok(ObservationScan {
                    block,
                    alpha,
                    threshold,
                    grid,
                })
            })
            .collect()
    }

    /// An amplitude, g, below which a block on a floor of static friction
    /// `mu` cannot slip: half the least at which the ground's horizontal
    /// acceleration can exceed μ (g + ü_v). Under a vertical motion that
    /// stays above −g up to `range_g().to` (where [`ForensicJob::lift_off_g`]
    /// ends it), |ü_v| ≤ a/to g at amplitude a g, so a slip needs a > μ (1 − a/to).
    fn slip_free_g(&self, mu: f64) -> f64 {
        let to = self.range_g().to;
        let fall = if self.scaled_vertical().is_some() && to > 0.0 {
            1.0 / to
        } else {
            0.0
        };
        0.5 * mu / (1.0 + mu * fall)
    }

    /// CPU seconds of one simulation (the record's, or the pulse's).
    fn simulation_s(&self) -> f64 {
        (match (&self.ground_motion, &self.pulse) {
            (Some(g), _) => cost::record_simulation_s(&g.acc),
            (None, Some(p)) => {
                cost::pulse_simulation_s(&p.shape(), self.formulation, self.solver.method)
            }
            (None, None) => 0.0,
        }) * cost::contact_factor(self.contact.as_ref())
    }

    /// Estimated simulations of a line of `points` levels on `grid`: scan
    /// plus bisection ([`cost`]).
    pub(super) fn line_simulations(&self, points: f64, grid: &ScanGrid) -> f64 {
        if self.ground_motion.is_some() {
            cost::record_line_simulations(points, grid.step, grid.tolerance)
        } else {
            cost::pulse_line_simulations(points, grid.step, grid.tolerance)
        }
    }

    /// The observations as groups of lines, each line costing what its
    /// scan is estimated to.
    pub fn groups(&self, scans: &[ObservationScan]) -> Vec<Group> {
        let per = self.simulation_s();
        scans
            .iter()
            .map(|s| {
                let points = s.grid.map_or(0, |g| g.points());
                Group {
                    lines: self.lines_per_observation(),
                    points,
                    line_s: s
                        .grid
                        .map_or(0.0, |g| self.line_simulations(points as f64, &g) * per),
                }
            })
            .collect()
    }

    /// The size of `part` of the query (`None`: the whole query): scan
    /// points, estimated simulations and CPU seconds of its lines.
    pub fn scan_size(&self, part: Option<Part>) -> Result<Size, ScanError> {
        let scans = self.observation_scans()?;
        let groups = self.groups(&scans);
        let per = self.simulation_s();
        let (mut points, mut work, mut lanes) = (0.0, 0.0, 0.0);
        let mut first = 0;
        for (s, g) in scans.iter().zip(&groups) {
            let range = first..first + g.lines;
            first = range.end;
            let Some(grid) = s.grid else { continue };
            let (lines, levels) = match part {
                Some(p) if range.contains(&p.lines[0]) => (
                    (p.lines[1] - p.lines[0]) as f64,
                    (p.levels[1] - p.levels[0] + 1) as f64,
                ),
                Some(_) => continue,
                None => (g.lines as f64, g.points as f64),
            };
            points += lines * levels;
            work += lines * self.line_simulations(levels, &grid);
            lanes += lines * (levels / LANE_POINTS).ceil();
        }
        Ok(Size {
            series_points: 0,
            grid_points: points.min(usize::MAX as f64) as usize,
            work,
            record_work: self
                .ground_motion
                .as_ref()
                .map_or(0.0, |g| work * g.acc.len() as f64),
            cpu_s: work * per,
            lanes,
        })
    }

    /// Scans the lines and levels of `part`.
    pub fn run_part(&self, part: Part, control: &Control) -> Result<PartDoc, ScanError> {
        let scans = self.observation_scans()?;
        let per = self.lines_per_observation().max(1);
        let o = part.lines[0] / per;
        let scan = scans.get(o).ok_or_else(|| bad_block(SimError::Tolerance))?;
        let grid = scan.grid.ok_or_else(|| bad_block(SimError::Tolerance))?;
        let lines = part.lines[0] - o * per..part.lines[1] - o * per;
        let solver = crate::spectrum::scan::Model {
            solver: self.solver.solver(),
            friction: self.contact.as_ref().map(|c| c.friction()),
            slide_band: self.observations.get(o).and_then(|o| o.slid_m),
        };
        match (&self.ground_motion, self.pulse) {
            (Some(gm), _) => {
                let record = gm.record().map_err(|_| bad_block(SimError::Tolerance))?;
                let on = |motion| Problem {
                    block: scan.block,
                    pulse: motion,
                    formulation: self.formulation,
                };
                match self.scaled_vertical() {
                    None => {
                        let problems: Vec<_> = lines.map(|_| on(record.clone())).collect();
                        scan_parts::run(PART_KIND, part, &problems, solver, &grid, control)
                    }
                    Some(v) => {
                        let pair = v.record_pair(record)?;
                        let problems: Vec<_> = lines
                            .map(|_| Problem {
                                block: scan.block,
                                pulse: pair.clone(),
                                formulation: self.formulation,
                            })
                            .collect();
                        scan_parts::run(PART_KIND, part, &problems, solver, &grid, control)
                    }
                }
            }
            (None, Some(family)) => {
                let p = scan.block.frequency_parameter();
                let problems = self.frequency_hz[lines]
                    .iter()
                    .map(|f| {
                        // ω_p as the pulse spectrum makes it, from ω_p/p.
                        let ratio = std::f64::consts::TAU * f / p;
                        let pulse = Pulse::new(
                            family.shape(),
                            scan.alpha * scan.block.gravity(),
                            ratio * p,
                        )
                        .map_err(|_| bad_block(SimError::Tolerance))?;
                        Ok(Problem {
                            block: scan.block,
                            pulse,
                            formulation: self.formulation,
                        })
                    })
                    .collect::<Result<Vec<_>, ScanError>>()?;
                match self.scaled_vertical() {
                    None => scan_parts::run(PART_KIND, part, &problems, solver, &grid, control),
                    Some(v) => {
                        let pairs = problems
                            .into_iter()
                            .map(|q| {
                                Ok(Problem {
                                    block: q.block,
                                    pulse: v
                                        .pulse_pair(q.pulse)
                                        .ok_or_else(|| bad_block(SimError::Tolerance))??,
                                    formulation: q.formulation,
                                })
                            })
                            .collect::<Result<Vec<_>, ScanError>>()?;
                        scan_parts::run(PART_KIND, part, &pairs, solver, &grid, control)
                    }
                }
            }
            (None, None) => Err(bad_block(SimError::Tolerance)),
        }
    }

    /// Runs the whole query: each observation's lines in one part.
    pub fn run(&self, control: &Control) -> Result<ForensicResult, ScanError> {
        let started = std::time::Instant::now();
        let scans = self.observation_scans()?;
        let groups = self.groups(&scans);
        let mut docs = Vec::new();
        let mut first = 0;
        for g in &groups {
            if g.points > 0 && g.lines > 0 {
                let part = Part {
                    lines: [first, first + g.lines],
                    levels: [0, g.points - 1],
                };
                docs.push(self.run_part(part, control)?);
            }
            first += g.lines;
        }
        let (found, stats, _) = scan_parts::assemble(PART_KIND, &groups, &docs)
            .map_err(|_| bad_block(SimError::Tolerance))?;
        self.result(&scans, found, &stats, started.elapsed().as_secs_f64(), None)
    }

    /// The whole query's result from its tasks' parts (in any order).
    pub fn result_of(&self, docs: &[PartDoc]) -> Result<ForensicResult, JobError> {
        let scans = self
            .observation_scans()
            .map_err(|e| JobError::Task(e.to_string()))?;
        let (found, stats, wall) = scan_parts::assemble(PART_KIND, &self.groups(&scans), docs)?;
        self.result(&scans, found, &stats, wall, Some(docs.len()))
            .map_err(|e| JobError::Task(e.to_string()))
    }

    /// The result from what was found on every line.
    fn result(
        &self,
        scans: &[ObservationScan],
        found: Vec<Found>,
        stats: &ScanStats,
        wall_time_s: f64,
        tasks: Option<usize>,
    ) -> Result<ForensicResult, ScanError> {
        let sets = self.overturning_sets(scans, found);
        let mut result = match &self.ground_motion {
            Some(gm) => super::record::result(self, gm, scans, &sets, stats)?,
            None => self.pulse_result(&sets, stats)?,
        };
        result.numerics.wall_time_s = wall_time_s;
        result.numerics.tasks = tasks;
        Ok(result)
    }

    /// Each observation's overturning set on each of its lines, g.
    fn overturning_sets(&self, scans: &[ObservationScan], found: Vec<Found>) -> Vec<Vec<LineSet>> {
        let AmplitudeRange { from, to } = self.range_g();
        let per = self.lines_per_observation();
        let mut found = found.into_iter();
        scans
            .iter()
            .zip(&self.observations)
            .map(|(s, o)| {
                (0..per)
                    .map(|_| {
                        let f = found.next().unwrap_or_default();
                        match s.grid {
                            Some(grid) => {
                                let line = grid.line(f);
                                LineSet {
                                    overturning: overturning_set(
                                        &line.transitions,
                                        s.alpha,
                                        from,
                                        to,
                                    ),
                                    decided_to: to,
                                    lift_off_g: None,
                                    mixed: line.mixed.iter().map(|z| z.scaled(s.alpha)).collect(),
                                    // At the grid's first level the block
                                    // has not moved: it slid 0.
                                    slide_band: o.slid_m.map(|[lo, _]| {
                                        slide_band_set(
                                            &line.slide_band,
                                            lo <= 0.0,
                                            s.alpha,
                                            from,
                                            to,
                                        )
                                    }),
                                }
                            }
                            // It does not move in the range: it slid 0.
                            None => LineSet {
                                overturning: Vec::new(),
                                decided_to: to,
                                lift_off_g: None,
                                mixed: Vec::new(),
                                slide_band: o.slid_m.map(|[lo, _]| {
                                    if lo <= 0.0 {
                                        vec![[from, to]]
                                    } else {
                                        Vec::new()
                                    }
                                }),
                            },
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

impl ForensicJob {
    /// The parts of the query of `size` (its model's, or measured on a
    /// sample: its lines' costs scaled alike), of about
    /// [`cost::TASK_CPU_S`] each.
    pub fn cut(&self, size: &Size) -> Vec<Part> {
        self.observation_scans().map_or(Vec::new(), |scans| {
            let mut groups = self.groups(&scans);
            let model: f64 = groups.iter().map(|g| g.lines as f64 * g.line_s).sum();
            if model > 0.0 && size.cpu_s > 0.0 {
                for g in &mut groups {
                    g.line_s *= size.cpu_s / model;
                }
            }
            scan_parts::parts(
                &groups,
                cost::TASK_CPU_S,
                crate::jobs::split::MAX_PART_TASKS,
            )
        })
    }

    /// Whether `part`, read back from a task, is a part of the query.
    pub fn fits(&self, part: &Part) -> Result<(), JobError> {
        let scans = self
            .observation_scans()
            .map_err(|e| JobError::Task(e.to_string()))?;
        part.fits(&self.groups(&scans))
    }
}

#[cfg(test)]
mod tests {
    use crate::jobs::scan_parts::PartDoc;
    use crate::kinds::Job;
    use crate::kinds::forensic::ForensicJob;
    use crate::spectrum::Control;

    fn query(spec: &str) -> ForensicJob {
        match Job::parse(spec).expect("valid") {
            Job::Forensic(j) => *j,
            other => panic!("not a forensic query: {other:?}"),
        }
    }

    fn record_query() -> ForensicJob {
        // Two cycles of a 2 Hz sine and a decaying tail: fragmented sets.
        let acc: Vec<String> = (0..300)
            .map(|k| {
                let t = k as f64 * 0.01;
                let a = 0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp();
                format!("{a:.5}")
            })
            .collect();
        query(&format!(
            r#"{{"kind":"forensic","observations":[
                {{"name":"tall","overturned":true,"block":{{"alpha":0.2,"p":2.2}}}},
                {{"name":"squat","overturned":false,"block":{{"alpha":0.3,"p":1.6}}}},
                {{"name":"never","overturned":false,"block":{{"alpha":1.2,"p":2.0}}}}],
              "scale":{{"to":4}},"scan_step_g":0.005,
              "ground_motion":{{"dt":0.01,"unit":"g","acc":[{}]}}}}"#,
            acc.join(",")
        ))
    }

    /// Runs `job` in the parts cut with `budget` CPU seconds, each document
    /// through JSON text as a stored task result is.
    fn in_parts(job: &ForensicJob, budget: f64) -> (usize, super::ForensicResult) {
        let scans = job.observation_scans().expect("blocks");
        let parts = crate::jobs::scan_parts::parts(&job.groups(&scans), budget, 4096);
        let control = Control::new();
        let docs: Vec<PartDoc> = parts
            .iter()
            .map(|&p| {
                let doc = job.run_part(p, &control).expect("runs");
                let text = serde_json::to_string(&doc).expect("writes");
                serde_json::from_str(&text).expect("reads")
            })
            .collect();
        (parts.len(), job.result_of(&docs).expect("assembles"))
    }

    #[test]
    fn a_record_query_split_along_the_scale_assembles_to_the_whole() {
        let job = record_query();
        let whole = job.run(&Control::new()).expect("runs");
        let sets = whole.per_observation.as_ref().expect("record sets");
        // Something to find: the tall block overturns in pieces.
        assert!(sets[0].overturning_scale.len() > 1, "{sets:?}");
        assert!(sets[2].overturning_scale.is_empty());
        let line_s = job.groups(&job.observation_scans().expect("blocks"))[0].line_s;
        for budget in [line_s / 3.0, line_s / 10.0] {
            let (n, split) = in_parts(&job, budget);
            assert!(n >= 6, "{n} parts");
            assert_eq!(split.numerics.tasks, Some(n));
            assert_eq!(split.per_observation, whole.per_observation);
            assert_eq!(split.consistent_scale, whole.consistent_scale);
            assert_eq!(split.bounds, whole.bounds);
        }
    }

    #[test]
    fn a_pulse_query_split_by_frequency_assembles_to_the_whole() {
        let job = query(
            r#"{"kind":"forensic","pulse":{"type":"one_sine"},
                "observations":[
                  {"name":"a","overturned":true,"block":{"alpha":0.2,"p":2.0}},
                  {"name":"b","overturned":false,"block":{"alpha":0.25,"p":1.5}}],
                "frequency_hz":{"from":0.5,"to":3,"steps":9},"a_p_g":{"from":0.05,"to":1.5}}"#,
        );
        let whole = job.run(&Control::new()).expect("runs");
        let line_s = job.groups(&job.observation_scans().expect("blocks"))[0].line_s;
        let (n, split) = in_parts(&job, line_s * 2.5);
        assert!(n >= 4, "{n} parts");
        assert_eq!(split.frequencies, whole.frequencies);
        assert_eq!(split.bounds, whole.bounds);
        assert!(whole.frequencies.iter().any(|f| !f.consistent_g.is_empty()));
    }

    #[test]
    fn a_task_names_its_part_and_is_sized_by_it() {
        let job = record_query();
        let whole = job.scan_size(None).expect("sized");
        let scans = job.observation_scans().expect("blocks");
        let groups = job.groups(&scans);
        let parts = crate::jobs::scan_parts::parts(&groups, groups[0].line_s / 4.0, 4096);
        let mut points = 0;
        for &p in &parts {
            points += job.scan_size(Some(p)).expect("sized").grid_points;
            job.fits(&p).expect("fits");
        }
        // Parts meet at a shared level: each boundary counted twice.
        assert!(
            points >= whole.grid_points,
            "{points} vs {}",
            whole.grid_points
        );
        assert!(points <= whole.grid_points + parts.len(), "{points}");
        // The never-rocking block has no part.
        assert!(parts.iter().all(|p| p.lines[0] != 2));
    }
}
