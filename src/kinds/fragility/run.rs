//! How a fragility job is computed.

use super::result::{CurvePoint, FragilityNumerics, FragilityResult, LognormalFit, StripeResult};
use super::spec::{BOOTSTRAP, CHUNK, FragilityJob, UncertainNorm, Z95};
use crate::dynamics::block::housner_restitution;
use crate::dynamics::{
    Block, Formulation, Options, Problem, Pulse, PulsePair, Record, RecordPair, Response, simulate,
};
use crate::jobs::JobError;
use crate::jobs::names::{Im, tag};
use crate::probability::fragility::{Stripe, fit_lognormal, log_likelihood, wilson};
use crate::probability::normal;
use crate::spectrum::Control;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
/// Why one sample of a fragility could not be simulated: its sampled block
/// or pulse is not one the engine takes, or the engine refused it.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    /// The sampled block.
    #[error(transparent)]
    Block(#[from] crate::dynamics::block::BlockError),
    /// The sampled pulse.
    #[error(transparent)]
    Pulse(#[from] crate::dynamics::excitation::PulseError),
    /// The engine.
    #[error(transparent)]
    Simulation(#[from] crate::dynamics::SimError),
    /// A sample without what it needs (a validated job always has it).
    #[error("{0}")]
    Incomplete(&'static str),
}

/// The ChaCha8 stream of stripe `k`, chunk `c`.
pub(super) fn stream(seed: u64, k: usize, c: usize) -> ChaCha8Rng {
    // SplitMix64 of the three, so that neighbouring chunks get unrelated seeds.
    let mut x = seed
        ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (c as u64).wrapping_mul(0xD1B5_4A32_D192_ED03);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ChaCha8Rng::seed_from_u64(x ^ (x >> 31))
}

/// A uniform in (0, 1).
pub(super) fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// One simulation of `block` under `ground` (a motion, or a pair with its
/// vertical component), on a Coulomb floor when `friction` is given.
pub(super) fn run<G: crate::dynamics::sliding::Kinematics>(
    block: Block,
    ground: G,
    formulation: Formulation,
    options: &Options,
    friction: Option<crate::dynamics::sliding::Friction>,
) -> Result<Response, crate::dynamics::SimError> {
    let problem = Problem {
        block,
        pulse: ground,
        formulation,
    };
    match friction {
        None => simulate(&problem, options),
        Some(f) => crate::dynamics::floor::run_coulomb(&problem, options, f).map(|h| h.response),
    }
}

/// A record of the suite, ready to scale.
pub(super) struct SuiteRecord {
    /// ü_g.
    record: Record,
    /// Its own ü_v, on the same samples.
    vertical: Option<Record>,
    /// Its PGA (m/s²) or PGV (m/s).
    per_unit: f64,
}

/// What one sample did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Verdict {
    /// Still standing at the end.
    Stands,
    /// Toppled, in mode 1 (after an impact) or 2 (without one).
    Topples(u8),
    /// The ground fell away faster than g: no verdict.
    LiftOff,
    /// The history reached a bound on its work first: no verdict.
    Undecided,
}

impl Verdict {
    fn of(r: &Response) -> Verdict {
        if r.lift_off.is_some() {
            Verdict::LiftOff
        } else if r.reached_limit() {
            Verdict::Undecided
        } else if r.overturned {
            Verdict::Topples(r.mode.map_or(0, |m| m.number()))
        } else {
            Verdict::Stands
        }
    }
}

/// What some units of a stripe counted.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct StripeCounts {
    /// Simulations.
    pub n: u64,
    /// Toppled.
    pub overturned: u64,
    /// Toppled after an impact.
    pub mode_1: u64,
    /// Toppled without one.
    pub mode_2: u64,
    /// Lifted off (no verdict).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub lift_off: u64,
    /// Reached a bound on its work first (no verdict).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub undecided: u64,
}

pub(super) fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl StripeCounts {
    fn add(&mut self, other: &StripeCounts) {
        self.n += other.n;
        self.overturned += other.overturned;
        self.mode_1 += other.mode_1;
        self.mode_2 += other.mode_2;
        self.lift_off += other.lift_off;
        self.undecided += other.undecided;
    }

    /// The samples with a verdict.
    fn decided(&self) -> u64 {
        self.n - self.lift_off - self.undecided
    }
}

/// A task's result: its units' counts per stripe (not a job's result: the
/// service assembles the parts into one).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FragilityPart {
    /// "fragility".
    pub kind: String,
    /// The units `[from, to)` it counted.
    pub part: [usize; 2],
    /// Per stripe, in the job's order.
    pub counts: Vec<StripeCounts>,
    /// Simulations run.
    pub simulations: u64,
    /// Its compute time, s.
    pub wall_time_s: f64,
}

/// The tasks a result was assembled from.
pub(super) struct Tasks {
    count: usize,
    compute_s: f64,
}

impl FragilityJob {
    /// The block of one sample from its uniforms.
    fn block_at(&self, u: [f64; 3]) -> Result<Block, SampleError> {
        let b = &self.block;
        let (alpha, p) = match (&b.alpha, &b.p, &b.b, &b.h) {
            (Some(a), Some(p), _, _) => (a.at(u[0]), p.at(u[1])),
            (_, _, Some(bb), Some(hh)) => {
                let (half_b, half_h) = (bb.at(u[0]), hh.at(u[1]));
                let r = half_b.hypot(half_h);
                ((half_b / half_h).atan(), (3.0 * b.g / (4.0 * r)).sqrt())
            }
            _ => {
                return Err(SampleError::Incomplete(
                    "the block has neither α and p nor b and h",
                ));
            }
        };
        let eta = b
            .eta
            .map_or_else(|| housner_restitution(alpha), |e| e.at(u[2]));
        Ok(Block::new(alpha, p, Some(eta), None, Some(b.g))?)
    }

    /// What one sample does: stands, topples (and its mode), or lifts off
    /// (the ground falls away faster than g: no verdict). `ratio` is its
    /// ü_v/ü_g, when the campaign has one.
    fn sample(
        &self,
        im: f64,
        j: usize,
        u: [f64; 4],
        ratio: Option<f64>,
        records: &[SuiteRecord],
    ) -> Result<Verdict, SampleError> {
        let block = self.block_at([u[0], u[1], u[2]])?;
        let options = Options::outcome(self.solver.solver());
        let formulation = self.formulation;
        let friction = self.contact.as_ref().map(|c| c.friction());
        let ratio = ratio.filter(|r| *r != 0.0);
        let r = if let Some(pulse) = &self.pulse {
            let omega = match (&pulse.omega_p, &pulse.omega_ratio) {
                (Some(w), _) => w.at(u[3]),
                (_, Some(ratio)) => ratio.at(u[3]) * block.frequency_parameter(),
                _ => return Err(SampleError::Incomplete("the pulse has no frequency")),
            };
            let unit = Pulse::new(pulse.family.shape(), 1.0, omega)?;
            let a_p = if self.im == Im::PgaG {
                im * block.gravity()
            } else {
                im / unit.peak_velocity()
            };
            let pulse = unit.with_amplitude(a_p);
            match ratio.and_then(|r| PulsePair::proportional(pulse, r)) {
                Some(pair) => run(block, pair, formulation, &options, friction)?,
                None => run(block, pulse, formulation, &options, friction)?,
            }
        } else {
            let suite = &records[j % records.len()];
            let factor = if self.im == Im::PgaG {
                im * block.gravity() / suite.per_unit
            } else {
                im / suite.per_unit
            };
            let record = suite.record.scaled(factor);
            let pair = match (&suite.vertical, ratio) {
                (Some(v), _) => Some(RecordPair {
                    horizontal: record.clone(),
                    vertical: v.scaled(factor),
                }),
                (None, Some(r)) => RecordPair::proportional(record.clone(), r),
                (None, None) => None,
            };
            match pair {
                Some(pair) => run(block, pair, formulation, &options, friction)?,
                None => run(block, record, formulation, &options, friction)?,
            }
        };
        Ok(Verdict::of(&r))
    }

    /// Chunks of [`CHUNK`] samples per stripe.
    pub fn chunks(&self) -> usize {
        (self.samples as usize).div_ceil(CHUNK)
    }

    /// The job's units of work and of seeding: (stripe k, chunk c) in the
    /// order unit `k · chunks + c`. A task computes a range of them.
    pub fn units(&self) -> usize {
        self.stripes.len() * self.chunks()
    }

    /// Each record of the suite with its vertical component (padded to the
    /// same length) and its PGA (m/s²) or PGV (m/s): what one unit of scale
    /// gives.
    fn records(&self) -> Vec<SuiteRecord> {
        self.ground_motions
            .iter()
            .flatten()
            .filter_map(|m| {
                let (record, vertical) = match m.motion.pair() {
                    Some(pair) => {
                        let pair = pair.ok()?;
                        (pair.horizontal, Some(pair.vertical))
                    }
                    None => (m.motion.record().ok()?, None),
                };
                let peaks = crate::dynamics::peaks::of_record(&record);
                let per_unit = if self.im == Im::PgaG {
                    peaks.pga
                } else {
                    peaks.pgv
                };
                (per_unit > 0.0).then_some(SuiteRecord {
                    record,
                    vertical,
                    per_unit,
                })
            })
            .collect()
    }

    /// Whether its samples may lift off: a vertical motion is given.
    pub fn has_vertical(&self) -> bool {
        self.vertical.is_some()
            || self
                .ground_motions
                .iter()
                .flatten()
                .any(|m| m.motion.vertical.is_some())
    }

    /// Samples of the suite's longest record (0 for a pulse family).
    pub fn longest_record(&self) -> usize {
        self.ground_motions
            .iter()
            .flatten()
            .map(|m| m.motion.acc.len())
            .max()
            .unwrap_or(0)
    }

    /// Expected CPU seconds of one of its simulations ([`crate::jobs::cost`]): a
    /// record of the suite's on average, or a pulse of its family: at
    /// stripes many of which do not rock the block, about 0.6 of a
    /// spectrum's average simulation (measured 35 µs for a one-sine), or of
    /// a record's whole shaking.
    pub fn simulation_s(&self) -> f64 {
        use crate::jobs::cost;
        (match (&self.ground_motions, &self.pulse) {
            (Some(suite), _) if !suite.is_empty() => {
                0.6 * suite
                    .iter()
                    .map(|m| cost::record_simulation_s(&m.motion.acc))
                    .sum::<f64>()
                    / suite.len() as f64
            }
            (_, Some(p)) => {
                0.6 * cost::pulse_simulation_s(
                    &p.family.shape(),
                    self.formulation,
                    self.solver.method,
                )
            }
            _ => 0.0,
        }) * crate::jobs::cost::contact_factor(self.contact.as_ref())
    }

    /// Simulations the units `part` of this job run (`None`: the whole
    /// job).
    pub fn simulations(&self, part: Option<[usize; 2]>) -> u64 {
        let [from, to] = part.unwrap_or([0, self.units()]);
        self.samples_in(from, to)
    }

    /// Samples in units `from..to`.
    fn samples_in(&self, from: usize, to: usize) -> u64 {
        let (chunks, samples) = (self.chunks(), self.samples as usize);
        (from..to)
            .map(|i| {
                let c = i % chunks;
                ((c + 1) * CHUNK).min(samples) - c * CHUNK
            })
            .sum::<usize>() as u64
    }

    /// Simulates units `from..to` (rayon over them) and counts per stripe
    /// (stripes outside the range count zero).
    fn count(
        &self,
        from: usize,
        to: usize,
        control: &Control,
    ) -> Result<Vec<StripeCounts>, JobError> {
        let (chunks, samples) = (self.chunks(), self.samples as usize);
        let records = self.records();
        control.add_total(self.samples_in(from, to));
        let counted: Vec<Result<(usize, StripeCounts), JobError>> = (from..to)
            .into_par_iter()
            .map(|i| {
                let (k, c) = (i / chunks, i % chunks);
                let mut rng = stream(self.seed, k, c);
                let mut counts = StripeCounts::default();
                for j in c * CHUNK..((c + 1) * CHUNK).min(samples) {
                    control.check().map_err(|_| JobError::Canceled)?;
                    let u = [
                        uniform(&mut rng),
                        uniform(&mut rng),
                        uniform(&mut rng),
                        uniform(&mut rng),
                    ];
                    // A fifth uniform only for a distributed ratio: a fixed
                    // one (or none) keeps every other sample's stream.
                    let ratio = self.vertical.map(|v| match v.ratio {
                        UncertainNorm::Fixed(r) => r,
                        d => d.at(uniform(&mut rng)),
                    });
                    let outcome = self
                        .sample(self.stripes[k], j, u, ratio, &records)
                        .map_err(|e| JobError::AtSample {
                            stripe: k,
                            level: format!("{} {}", self.stripes[k], self.im),
                            sample: j,
                            source: Box::new(e),
                        })?;
                    counts.n += 1;
                    match outcome {
                        Verdict::Stands => {}
                        Verdict::LiftOff => counts.lift_off += 1,
                        Verdict::Undecided => counts.undecided += 1,
                        Verdict::Topples(mode) => {
                            counts.overturned += 1;
                            if mode == 2 {
                                counts.mode_2 += 1;
                            } else {
                                counts.mode_1 += 1;
                            }
                        }
                    }
                    control.add_done(1);
                }
                Ok((k, counts))
            })
            .collect();
        let mut per_stripe = vec![StripeCounts::default(); self.stripes.len()];
        for r in counted {
            let (k, counts) = r?;
            per_stripe[k].add(&counts);
        }
        Ok(per_stripe)
    }

    /// Runs the Monte Carlo and the fit (rayon over chunks) of the whole
    /// job.
    pub fn run(&self, control: &Control) -> Result<FragilityResult, JobError> {
        let started = std::time::Instant::now();
        let counts = self.count(0, self.units(), control)?;
        self.finish(&counts, None, started)
    }

    /// Runs the units `[from, to)` of a task: their counts per stripe, for
    /// [`FragilityJob::assemble`].
    pub fn run_part(
        &self,
        [from, to]: [usize; 2],
        control: &Control,
    ) -> Result<FragilityPart, JobError> {
        let started = std::time::Instant::now();
        let counts = self.count(from, to, control)?;
        let wall = started.elapsed().as_secs_f64();
        Ok(FragilityPart {
            kind: "fragility".into(),
            part: [from, to],
            simulations: counts.iter().map(|c| c.n).sum(),
            wall_time_s: wall,
            counts,
        })
    }

    /// The whole job's result from its tasks' parts (in any order): each
    /// unit counted exactly once, else an error naming the first gap or
    /// overlap.
    pub fn assemble(&self, parts: &[FragilityPart]) -> Result<FragilityResult, JobError> {
        let started = std::time::Instant::now();
        let mut ranges: Vec<[usize; 2]> = parts.iter().map(|p| p.part).collect();
        ranges.sort_unstable();
        let mut next = 0;
        for [from, to] in &ranges {
            if *from != next {
                return Err(JobError::Task(if *from > next {
                    format!("the tasks' parts do not tile the job: unit {next} is missing")
                } else {
                    format!("the tasks' parts do not tile the job: unit {from} is counted twice")
                }));
            }
            next = *to;
        }
        if next != self.units() {
            return Err(JobError::Task(format!(
                "the tasks' parts do not tile the job: units {next}..{} are missing",
                self.units()
            )));
        }
        let mut counts = vec![StripeCounts::default(); self.stripes.len()];
        for part in parts {
            if part.counts.len() != counts.len() {
                return Err(JobError::Task(
                    "a task's counts do not match the job's stripes".into(),
                ));
            }
            for (total, c) in counts.iter_mut().zip(&part.counts) {
                total.add(c);
            }
        }
        let tasks = Tasks {
            count: parts.len(),
            compute_s: parts.iter().map(|p| p.wall_time_s).sum(),
        };
        self.finish(&counts, Some(tasks), started)
    }

    /// The result from the counts per stripe: the Wilson intervals, the
    /// monotonicity flag, the fit and its band.
    fn finish(
        &self,
        per_stripe: &[StripeCounts],
        tasks: Option<Tasks>,
        started: std::time::Instant,
    ) -> Result<FragilityResult, JobError> {
        if let Some((k, c)) = per_stripe
            .iter()
            .enumerate()
            .find(|(_, c)| c.n != u64::from(self.samples))
        {
            return Err(JobError::Task(format!(
                "stripe {k} counted {} simulations, not {}",
                c.n, self.samples
            )));
        }
        let stripes: Vec<StripeResult> = self
            .stripes
            .iter()
            .zip(per_stripe)
            .map(|(&im, c)| {
                // Over the samples decided (all of them without a vertical
                // motion); none decided: no probability (null).
                let decided = c.decided();
                let (lo, hi) = if decided > 0 {
                    wilson(c.overturned, decided, Z95)
                } else {
                    (f64::NAN, f64::NAN)
                };
                StripeResult {
                    im,
                    n: c.n,
                    overturned: c.overturned,
                    p: if decided > 0 {
                        c.overturned as f64 / decided as f64
                    } else {
                        f64::NAN
                    },
                    interval_95: [lo, hi],
                    mode_1: c.mode_1,
                    mode_2: c.mode_2,
                    lift_off: self.has_vertical().then_some(c.lift_off),
                    undecided: (c.undecided > 0).then_some(c.undecided),
                }
            })
            .collect();
        // Monotone in rising intensity (stripes with a probability).
        let mut order: Vec<&StripeResult> = stripes.iter().filter(|s| s.p.is_finite()).collect();
        order.sort_by(|a, b| a.im.total_cmp(&b.im));
        let falls_at: Vec<f64> = order
            .windows(2)
            .filter(|w| w[1].p < w[0].p)
            .map(|w| w[1].im)
            .collect();
        let counts: Vec<Stripe> = stripes
            .iter()
            .filter(|s| s.decided() > 0)
            .map(|s| Stripe {
                im: s.im,
                n: s.decided(),
                k: s.overturned,
            })
            .collect();
        let lognormal = fit_lognormal(&counts).map(|(theta, beta)| self.band(theta, beta, &counts));
        let simulations: u64 = per_stripe.iter().map(|c| c.n).sum();
        // One task: its wall time; several: the tasks' compute time summed
        // (wherever they ran) plus the assembly's.
        let wall = started.elapsed().as_secs_f64() + tasks.as_ref().map_or(0.0, |t| t.compute_s);
        Ok(FragilityResult {
            kind: tag::Fragility,
            im: self.im,
            stripes,
            interval_method: "wilson".into(),
            monotone: falls_at.is_empty(),
            falls_at,
            lognormal,
            numerics: FragilityNumerics {
                method: self.solver.method.name().to_string(),
                simulations,
                simulations_per_second: simulations as f64 / wall.max(1e-9),
                wall_time_s: wall,
                bootstrap: BOOTSTRAP,
                tasks: tasks.map_or(1, |t| t.count),
            },
            spec: self.clone(),
            warnings: Vec::new(),
            engine: None,
        })
    }

    /// The fit with its parametric bootstrap: each replicate redraws every
    /// stripe's count from Binomial(n, p̂) (p̂ the fitted curve there) with
    /// its own seeded stream, and is refitted.
    fn band(&self, theta: f64, beta: f64, counts: &[Stripe]) -> LognormalFit {
        let fitted = |x: f64, t: f64, b: f64| normal::cdf((x / t).ln() / b);
        let fits: Vec<(f64, f64)> = (0..BOOTSTRAP)
            .into_par_iter()
            .filter_map(|r| {
                let mut rng = stream(self.seed ^ 0xB007_57A9, usize::MAX, r);
                let redrawn: Vec<Stripe> = counts
                    .iter()
                    .map(|s| {
                        let p = fitted(s.im, theta, beta);
                        let k = if s.n <= 2_000 {
                            (0..s.n).filter(|_| uniform(&mut rng) < p).count() as u64
                        } else {
                            let z = normal::quantile(uniform(&mut rng));
                            let mean = s.n as f64 * p;
                            (mean + z * (mean * (1.0 - p)).sqrt())
                                .round()
                                .clamp(0.0, s.n as f64) as u64
                        };
                        Stripe { k, ..*s }
                    })
                    .collect();
                fit_lognormal(&redrawn)
            })
            .collect();
        let quantiles = |mut v: Vec<f64>| -> [f64; 2] {
            v.sort_by(f64::total_cmp);
            if v.is_empty() {
                return [f64::NAN, f64::NAN];
            }
            let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
            [at(0.025), at(0.975)]
        };
        let (lo, hi) = counts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), s| {
            (a.min(s.im), b.max(s.im))
        });
        let (lo, hi) = (
            lo.min(theta * (-2.5 * beta).exp()),
            hi.max(theta * (2.5 * beta).exp()),
        );
        let curve = (0..=60)
            .map(|i| {
                let x = lo * (hi / lo).powf(f64::from(i) / 60.0);
                let [a, b] = quantiles(fits.iter().map(|&(t, b)| fitted(x, t, b)).collect());
                CurvePoint {
                    im: x,
                    p: fitted(x, theta, beta),
                    lo: if a.is_finite() { a } else { 0.0 },
                    hi: if b.is_finite() { b } else { 1.0 },
                }
            })
            .collect();
        LognormalFit {
            median: theta,
            beta,
            median_interval_95: quantiles(fits.iter().map(|f| f.0).collect()),
            beta_interval_95: quantiles(fits.iter().map(|f| f.1).collect()),
            log_likelihood: log_likelihood(theta, beta, counts),
            curve,
        }
    }
}
