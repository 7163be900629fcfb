//! Overturning spectra (paper Figs. 6, 10, 11): for each ω_p/p, the whole
//! overturning set in a_p/(αg) from the rocking threshold up to a maximum.

use std::time::Instant;

use rayon::prelude::*;

use crate::dynamics::sliding::Friction;
use crate::dynamics::{Block, Formulation, Problem, Pulse, PulsePair, PulseShape, Solver};

use super::closed_form::{eq21_minimum, linear_one_sine_mode2_boundary};
use super::control::Control;
pub use super::scan::Found;
use super::scan::{
    Direction, Line, ModeChange, Model, Scalable, ScanError, ScanStats, Transition, lift_off_level,
};
use super::verify::{self, Mixed};

/// What to compute.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumRequest {
    /// The block.
    pub block: Block,
    /// Pulse family.
    pub shape: PulseShape,
    /// Equation of motion.
    pub formulation: Formulation,
    /// Solver.
    pub solver: Solver,
    /// The frequencies ω_p/p.
    pub omega_ratios: Vec<f64>,
    /// Highest amplitude examined, a_p/(αg).
    pub a_max: f64,
    /// Bracket width of every transition, in αg.
    pub tolerance: f64,
    /// Scan step, in αg: every band or safe interval wider than this is found.
    pub scan_step: f64,
    /// The principal view drops bands and safe intervals narrower than this
    /// fraction of their amplitude.
    pub principal_relative_width: f64,
    /// A vertical ground acceleration ü_v = r ü_g (positive up), in phase.
    pub vertical_ratio: Option<f64>,
    /// Coulomb friction at the floor; `None`: pure rocking.
    pub friction: Option<Friction>,
}

/// The derived quantities of one frequency.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Derived {
    /// Lowest overturning amplitude, a_p/(αg).
    pub min_overturn: Option<f64>,
    /// Its mode.
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] in αg (hi = a_max if open).
    pub safe_intervals: Vec<(f64, f64)>,
    /// Every amplitude above this overturns (up to a_max), outside any
    /// mixed zone.
    pub overturns_above: Option<f64>,
    /// The mixed zone in which `min_overturn` lies, if it does.
    pub min_overturn_zone: Option<Mixed>,
    /// The lowest amplitude from which overturning is certain (no mixed
    /// zone) over a band at least the principal relative width wide.
    pub min_certain_overturn: Option<f64>,
}

/// One frequency of a spectrum.
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyLine {
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Rocking threshold in αg (1 linear, tan α/α nonlinear).
    pub threshold: f64,
    /// Every survive ↔ overturn transition, in order (fine structure).
    pub transitions: Vec<Transition>,
    /// Changes of overturning mode inside overturning regions.
    pub mode_changes: Vec<ModeChange>,
    /// Derived from the fine structure.
    pub derived: Derived,
    /// Transitions without bands or safe intervals narrower than the principal width.
    pub principal_transitions: Vec<Transition>,
    /// Derived from the principal view.
    pub principal: Derived,
    /// Eq. 21's approximation of the minimum, αg (cycloidal pulses only).
    pub eq21: Option<f64>,
    /// Closed-form linear one-sine mode-2 boundary (corrected eq. 47), αg.
    pub mode2_closed_form: Option<f64>,
    /// Under a vertical motion: from this level (αg) on the ground falls
    /// away faster than gravity (g + ü_v ≤ 0) and the block leaves it; the
    /// line is scanned up to just below it, and claims nothing above.
    pub lift_off_above: Option<f64>,
    /// Where the outcome alternates finer than the scan resolves, αg.
    pub mixed: Vec<Mixed>,
}

/// A whole spectrum.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    /// One entry per frequency, in request order.
    pub lines: Vec<FrequencyLine>,
    /// Cost.
    pub stats: ScanStats,
    /// Wall time, s.
    pub wall_time: f64,
}

/// Rocking threshold in units of αg.
pub fn threshold_alpha_g(formulation: Formulation, block: &Block) -> f64 {
    threshold_alpha_g_of(formulation, block.slenderness(), block.gravity())
}

/// `threshold` (α g) under a vertical motion ü_v = r ü_g (`ratio`): rocking
/// can start on the side where the vertical lightens the block, once
/// |ü_g| (1 + |r| k) > k g (k = tan α, or α linear); unchanged without one.
pub fn threshold_under_ratio(
    threshold: f64,
    formulation: Formulation,
    slenderness: f64,
    ratio: Option<f64>,
) -> f64 {
    match ratio {
        Some(r) => threshold / (1.0 + r.abs() * formulation.rocking_threshold_of(slenderness, 1.0)),
        None => threshold,
    }
}

/// `threshold` (α g, of a record's PGA) under a record's own vertical
/// samples, both scaled by one factor c: the ground motion is linear between
/// samples, so c ü_g s − k c ü_v (side s = ±1, k = tan α, or α linear) peaks
/// at a sample, and rocking can start once c max_j (|h_j| − k v_j) > k g
/// (the shorter record padded with zeros). In levels of the horizontal PGA:
/// `threshold` · PGA / max_j (|h_j| − k v_j); infinite when no sample can
/// rock at any scale. Exact, as [`threshold_under_ratio`] is for a ratio.
pub fn threshold_under_samples(
    threshold: f64,
    formulation: Formulation,
    slenderness: f64,
    horizontal: &[f64],
    vertical: &[f64],
) -> f64 {
    let k = formulation.rocking_threshold_of(slenderness, 1.0);
    let n = horizontal.len().max(vertical.len());
    let at = |x: &[f64], j: usize| x.get(j).copied().unwrap_or(0.0);
    let demand = (0..n)
        .map(|j| at(horizontal, j).abs() - k * at(vertical, j))
        .fold(f64::NEG_INFINITY, f64::max);
    let pga = horizontal.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    if demand > 0.0 {
        threshold * pga / demand
    } else {
        f64::INFINITY
    }
}

/// Rocking threshold in units of αg of any block of slenderness α under
/// gravity g, whatever its size.
pub fn threshold_alpha_g_of(formulation: Formulation, slenderness: f64, gravity: f64) -> f64 {
    formulation.rocking_threshold_of(slenderness, gravity) / (gravity * slenderness)
}

/// Grid points of one frequency: threshold, threshold + h, …, a_max.
fn grid_len(threshold: f64, a_max: f64, h: f64) -> usize {
    if a_max <= threshold {
        return 1;
    }
    ((a_max - threshold) / h).ceil() as usize + 1
}

fn grid_point(threshold: f64, a_max: f64, h: f64, k: usize, len: usize) -> f64 {
    if k + 1 >= len {
        a_max.max(threshold)
    } else {
        threshold + h * k as f64
    }
}

/// What one chunk of one line found.
type ChunkResult = (usize, Found, ScanStats);

/// Largest number of scan chunks per line (bounds memory and task count).
const MAX_CHUNKS: usize = 256;
/// Scan points per chunk when the grid is small.
const CHUNK_POINTS: usize = 48;

/// The length (in levels) of the chunks of a line of `points` levels: a
/// line is scanned and verified chunk by chunk, each from a multiple of it
/// to the next; a range of levels cut at such multiples is scanned as the
/// whole line is.
pub fn chunk_points(points: usize) -> usize {
    CHUNK_POINTS.max(points.div_ceil(MAX_CHUNKS))
}

/// How each line of a spectrum is scanned, in levels of peak ground
/// acceleration (α g).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanGrid {
    /// First level examined (the rocking threshold, or above it).
    pub from: f64,
    /// Highest level examined.
    pub to: f64,
    /// Scan step: every band or safe interval wider than this is found.
    pub step: f64,
    /// Bracket width of every transition.
    pub tolerance: f64,
    /// The principal view drops bands and safe intervals narrower than this
    /// fraction of their level.
    pub principal_relative_width: f64,
}

/// The overturning set of one line.
#[derive(Clone, Debug, PartialEq)]
pub struct LineScan {
    /// Every survive ↔ overturn transition, in order (fine structure).
    pub transitions: Vec<Transition>,
    /// Changes of overturning mode inside overturning regions.
    pub mode_changes: Vec<ModeChange>,
    /// Derived from the fine structure.
    pub derived: Derived,
    /// Transitions without bands or safe intervals narrower than the principal width.
    pub principal_transitions: Vec<Transition>,
    /// Derived from the principal view.
    pub principal: Derived,
    /// With a slide band: where the block's standing with its residual slide
    /// inside the band begins and ends, in order.
    pub slide_band: Vec<Transition>,
    /// Where the outcome alternates finer than the scan resolves
    /// ([`super::verify`]): no band or safe interval is claimed there.
    pub mixed: Vec<Mixed>,
}

/// Scans every problem (its ground motion scaled per level) over `grid`, in
/// parallel over lines and chunks of levels; results in the order of `problems`.
pub fn scan_lines<G: Scalable + Sync>(
    problems: &[Problem<G>],
    model: Model,
    grid: &ScanGrid,
    control: &Control,
) -> Result<(Vec<LineScan>, ScanStats), ScanError> {
    let len = grid.points();
    let (found, stats) = scan_range(problems, model, grid, [0, len - 1], control)?;
    let lines = found.into_iter().map(|found| grid.line(found)).collect();
    Ok((lines, stats))
}

impl ScanGrid {
    /// Levels of one line: `from`, `from + step`, …, `to`.
    pub fn points(&self) -> usize {
        grid_len(self.from, self.to, self.step)
    }

    /// The `k`th level of a line.
    pub fn level(&self, k: usize) -> f64 {
        grid_point(self.from, self.to, self.step, k, self.points())
    }

    /// The overturning set of a line from everything its scans found (in
    /// any order): the transitions in order, and what they imply outside
    /// its mixed zones (zones of neighbouring ranges closer than a step
    /// made one).
    pub fn line(&self, found: Found) -> LineScan {
        let Found {
            mut transitions,
            mut mode_changes,
            mixed,
        } = found;
        transitions.sort_by(|a, b| a.at.total_cmp(&b.at));
        mode_changes.sort_by(|a, b| a.at.total_cmp(&b.at));
        let to = self.to;
        let mixed = Mixed::merged(mixed, self.step);
        let slide_band = transitions
            .iter()
            .filter(|t| t.is_slide() && t.bracket.1 <= to)
            .copied()
            .collect();
        transitions.retain(|t| !t.is_slide() && t.bracket.1 <= to);
        mode_changes.retain(|m| m.bracket.1 <= to);
        let rel = self.principal_relative_width;
        let derived = derive_outside(&transitions, &mixed, to, rel);
        let principal_transitions = principal(&transitions, to, rel);
        let principal = derive_principal(&principal_transitions, &mixed, to, rel);
        LineScan {
            transitions,
            mode_changes,
            derived,
            principal_transitions,
            principal,
            slide_band,
            mixed,
        }
    }
}

/// Scans the levels `k0..=k1` of every problem's line over `grid`, in
/// parallel over lines and chunks of levels; what each line's range holds,
/// in the order of `problems`. Neighbouring ranges share their boundary
/// level, so that every pair of neighbouring levels is refined by exactly one
/// of them: the ranges of a line, scanned apart, find what one scan finds.
pub fn scan_range<G: Scalable + Sync>(
    problems: &[Problem<G>],
    model: Model,
    grid: &ScanGrid,
    [first, last]: [usize; 2],
    control: &Control,
) -> Result<(Vec<Found>, ScanStats), ScanError> {
    let last = last.min(grid.points() - 1);
    let first = first.min(last);
    let len = last - first + 1;
    // Chunks at fixed levels of the whole grid (multiples of its chunk
    // length), so that a range cut at such a level is scanned and verified
    // in the very chunks the whole line is: parts assemble to the whole.
    let size = chunk_points(grid.points());
    let starts: Vec<usize> = (first / size * size..last.max(first + 1))
        .step_by(size)
        .map(|k| k.max(first))
        .collect();
    control.add_total((problems.len() * len) as u64);
    let tasks: Vec<(usize, usize)> = (0..problems.len())
        .flat_map(|f| starts.iter().map(move |&k0| (f, k0)))
        .collect();
    let results: Vec<Result<ChunkResult, ScanError>> = tasks
        .par_iter()
        .map(|&(f, k0)| {
            let line = Line {
                problem: problems[f].clone(),
                model,
                control,
            };
            let k1 = ((k0 / size + 1) * size).min(last);
            let mut stats = ScanStats::default();
            // Chunks share their boundary point so that no pair is skipped.
            let levels = (k0..=k1).map(|k| grid.level(k));
            let found = line.scan(levels, grid.step, grid.tolerance, &mut stats)?;
            Ok((f, found, stats))
        })
        .collect();
    let mut per_line: Vec<Found> = vec![Found::default(); problems.len()];
    let mut stats = ScanStats::default();
    for r in results {
        let (f, found, s) = r?;
        per_line[f].extend(found);
        stats.absorb(&s);
    }
    Ok((per_line, stats))
}

/// The frequency of a vertical pulse of its own beside a line's pulse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VerticalFrequency {
    /// ω_v, rad/s, whatever the line.
    Omega(f64),
    /// ω_v/ω_p of each line's pulse.
    Ratio(f64),
}

/// A vertical pulse of its own (positive up) beside each line's horizontal
/// pulse, scaled with it: a_v = `amplitude_ratio`·a_p (either sign), starting
/// `delay` s after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerticalPulse {
    /// Its family.
    pub shape: PulseShape,
    /// a_v/a_p.
    pub amplitude_ratio: f64,
    /// Its frequency.
    pub frequency: VerticalFrequency,
    /// Its start after the horizontal pulse's, s.
    pub delay: f64,
}

impl VerticalPulse {
    /// The pair of `horizontal` and this vertical pulse.
    pub fn pair(&self, horizontal: Pulse) -> Result<PulsePair, ScanError> {
        let omega = match self.frequency {
            VerticalFrequency::Omega(w) => w,
            VerticalFrequency::Ratio(x) => x * horizontal.circular_frequency,
        };
        let vertical = Pulse::new(
            self.shape,
            self.amplitude_ratio * horizontal.amplitude,
            omega,
        )
        .map_err(|_| ScanError::Simulation(crate::dynamics::SimError::Tolerance))?;
        Ok(PulsePair::new(horizontal, vertical, self.delay))
    }

    /// Where a scan under this vertical pulse starts: every pulse's peak
    /// |ü| is its amplitude, so s ü_g − k ü_v ≤ a_p (1 + k |a_v/a_p|) and no
    /// block rocks below [`threshold_under_ratio`] of |a_v/a_p|: a lower
    /// bound of the rocking threshold (reached when the peaks coincide with
    /// opposite signs, as under a ratio), not the threshold itself.
    pub fn scan_from(&self, threshold: f64, formulation: Formulation, slenderness: f64) -> f64 {
        threshold_under_ratio(
            threshold,
            formulation,
            slenderness,
            Some(self.amplitude_ratio),
        )
    }
}

/// The vertical motion beside each pulse of a scan, scaled with it: ü_v =
/// r ü_g, or a pulse of its own whose amplitude is a share of each a_p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PulseVertical {
    /// ü_v = r·ü_g, in phase.
    Ratio(f64),
    /// A pulse of its own.
    Pulse(VerticalPulse),
}

impl PulseVertical {
    /// `horizontal` with this vertical motion.
    pub fn pair(&self, horizontal: Pulse) -> Result<PulsePair, ScanError> {
        match *self {
            PulseVertical::Ratio(r) => PulsePair::proportional(horizontal, r)
                .ok_or(ScanError::Simulation(crate::dynamics::SimError::Tolerance)),
            PulseVertical::Pulse(v) => v.pair(horizontal),
        }
    }
}

/// The pulse of each line of `req` at 1 αg.
pub fn line_pulses(req: &SpectrumRequest) -> Result<Vec<Pulse>, ScanError> {
    req.omega_ratios
        .iter()
        .map(|&ratio| {
            Pulse::new(
                req.shape,
                req.block.slenderness() * req.block.gravity(),
                ratio * req.block.frequency_parameter(),
            )
            .map_err(|_| ScanError::Simulation(crate::dynamics::SimError::Tolerance))
        })
        .collect::<Result<Vec<_>, ScanError>>()
}

/// The spectrum of `req` under a vertical pulse of its own beside each
/// line's pulse (`req.vertical_ratio` is not used), scanned from
/// [`VerticalPulse::scan_from`] to just below the lift-off.
pub fn overturning_spectrum_under(
    req: &SpectrumRequest,
    vertical: &VerticalPulse,
    control: &Control,
) -> Result<Spectrum, ScanError> {
    let started = Instant::now();
    let pairs = line_pulses(req)?
        .into_iter()
        .map(|p| vertical.pair(p))
        .collect::<Result<Vec<_>, ScanError>>()?;
    let from = vertical.scan_from(
        threshold_alpha_g(req.formulation, &req.block),
        req.formulation,
        req.block.slenderness(),
    );
    let (lines, stats) = lines_of(req, pairs, from, control)?;
    Ok(Spectrum {
        lines,
        stats,
        wall_time: started.elapsed().as_secs_f64(),
    })
}

/// Computes the spectrum, in parallel over frequencies and amplitude chunks.
pub fn overturning_spectrum(
    req: &SpectrumRequest,
    control: &Control,
) -> Result<Spectrum, ScanError> {
    let started = Instant::now();
    let pulses = line_pulses(req)?;
    let threshold = threshold_alpha_g(req.formulation, &req.block);
    let (lines, stats) = match req.vertical_ratio {
        None => lines_of(req, pulses, threshold, control)?,
        Some(r) => {
            let pairs = pulses
                .into_iter()
                .map(|p| {
                    PulsePair::proportional(p, r)
                        .ok_or(ScanError::Simulation(crate::dynamics::SimError::Tolerance))
                })
                .collect::<Result<Vec<_>, ScanError>>()?;
            let from =
                threshold_under_ratio(threshold, req.formulation, req.block.slenderness(), Some(r));
            lines_of(req, pairs, from, control)?
        }
    };
    Ok(Spectrum {
        lines,
        stats,
        wall_time: started.elapsed().as_secs_f64(),
    })
}

/// The lines of a spectrum of `motions` (one per frequency of `req`, at 1 αg)
/// scanned from `threshold` αg; a vertical motion ends each line's scan below
/// the level where the block would leave the ground.
fn lines_of<G: Scalable + Sync>(
    req: &SpectrumRequest,
    motions: Vec<G>,
    threshold: f64,
    control: &Control,
) -> Result<(Vec<FrequencyLine>, ScanStats), ScanError> {
    // (The level is the same for every frequency: the vertical motion's
    // extremes scale with the amplitude, whatever the pulse's length.)
    // (On a Coulomb floor the block's flights are followed: no cap.)
    let lift = motions
        .first()
        .filter(|_| req.friction.is_none())
        .and_then(|m| lift_off_level(m, &req.block, req.a_max));
    let to = lift.map_or(req.a_max, |(lo, _)| lo.max(threshold));
    let problems: Vec<Problem<G>> = motions
        .into_iter()
        .map(|pulse| Problem {
            block: req.block,
            pulse,
            formulation: req.formulation,
        })
        .collect();
    let grid = ScanGrid {
        from: threshold,
        to,
        step: req.scan_step,
        tolerance: req.tolerance,
        principal_relative_width: req.principal_relative_width,
    };
    let (scans, stats) = scan_lines(
        &problems,
        Model {
            solver: req.solver,
            friction: req.friction,
            slide_band: None,
        },
        &grid,
        control,
    )?;
    let plain = !G::VERTICAL;
    let lines = req
        .omega_ratios
        .iter()
        .zip(scans)
        .map(|(&ratio, scan)| FrequencyLine {
            omega_ratio: ratio,
            threshold,
            transitions: scan.transitions,
            mode_changes: scan.mode_changes,
            derived: scan.derived,
            principal_transitions: scan.principal_transitions,
            principal: scan.principal,
            eq21: eq21_minimum(req.shape, ratio).filter(|_| plain),
            mode2_closed_form: if plain
                && req.shape == PulseShape::OneSine
                && req.formulation == Formulation::Linear
            {
                linear_one_sine_mode2_boundary(ratio)
            } else {
                None
            },
            lift_off_above: lift.map(|(_, hi)| hi),
            mixed: scan.mixed,
        })
        .collect();
    Ok((lines, stats))
}

/// [`derive`] outside the mixed zones `mixed`: the lowest overturning
/// found anywhere (in a band or a zone, and which), safe intervals without
/// the zones, the all-overturn level above every zone, and the lowest
/// certain overturning band at least `rel` of its level wide.
pub fn derive_outside(
    transitions: &[Transition],
    mixed: &[Mixed],
    a_max: f64,
    rel: f64,
) -> Derived {
    let mut d = clipped(derive(transitions, a_max), transitions, mixed, a_max, rel);
    let touches = |z: &Mixed, t: &Transition| t.bracket.1 >= z.from && t.bracket.0 <= z.to;
    let first_up = transitions.iter().find(|t| t.direction == Direction::Up);
    d.min_overturn_zone = first_up.and_then(|t| mixed.iter().find(|z| touches(z, t)).copied());
    if let Some((f, z)) = mixed
        .iter()
        .filter_map(|z| z.first_overturn.map(|f| (f, z)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        && d.min_overturn.is_none_or(|m| f < m)
    {
        d.min_overturn = Some(f);
        d.min_overturn_zone = Some(*z);
        if first_up.is_none() {
            d.min_overturn_mode = None;
        }
    }
    d
}

/// The principal view ([`principal`]'s transitions) outside the mixed
/// zones: its minimum the lowest of its bands that, without the zones, is
/// still at least `rel` of its level wide (its mode that band's).
pub fn derive_principal(
    transitions: &[Transition],
    mixed: &[Mixed],
    a_max: f64,
    rel: f64,
) -> Derived {
    let mut d = clipped(derive(transitions, a_max), transitions, mixed, a_max, rel);
    d.min_overturn = d.min_certain_overturn;
    d.min_overturn_mode = d.min_overturn.and_then(|m| {
        transitions
            .iter()
            .rfind(|t| t.direction == Direction::Up && t.at <= m)
            .map(|t| t.mode)
    });
    d
}

/// `d` without the zones `mixed`: its safe intervals cut, its all-overturn
/// level above every zone, and its lowest certain band at least `rel` wide.
fn clipped(
    mut d: Derived,
    transitions: &[Transition],
    mixed: &[Mixed],
    a_max: f64,
    rel: f64,
) -> Derived {
    let safe: Vec<[f64; 2]> = d.safe_intervals.iter().map(|&(a, b)| [a, b]).collect();
    d.safe_intervals = verify::outside(&safe, mixed)
        .into_iter()
        .map(|[a, b]| (a, b))
        .collect();
    if let Some(a) = d.overturns_above {
        let above = mixed
            .iter()
            .filter(|z| z.to >= a)
            .map(|z| z.to)
            .fold(f64::NEG_INFINITY, f64::max);
        if above.is_finite() {
            d.overturns_above = (above < a_max).then_some(above);
        }
    }
    d.min_certain_overturn = verify::outside(&bands(transitions, a_max), mixed)
        .into_iter()
        .find(|&[lo, hi]| hi > lo && hi - lo >= rel * 0.5 * (lo + hi))
        .map(|[lo, _]| lo);
    d
}

/// The overturning bands `[up, down]` of ordered transitions (the last
/// open to `a_max`).
pub fn bands(transitions: &[Transition], a_max: f64) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    let mut open: Option<f64> = None;
    for t in transitions {
        match t.direction {
            Direction::Up => open = Some(t.at),
            Direction::Down => {
                if let Some(lo) = open.take() {
                    out.push([lo, t.at]);
                }
            }
            Direction::SlideIn | Direction::SlideOut => {}
        }
    }
    if let Some(lo) = open {
        out.push([lo, a_max]);
    }
    out
}

/// Minimum, safe intervals and the all-overturn level from ordered transitions.
pub fn derive(transitions: &[Transition], a_max: f64) -> Derived {
    let first_up = transitions.iter().find(|t| t.direction == Direction::Up);
    let mut safe = Vec::new();
    let mut open: Option<f64> = None;
    for t in transitions {
        match t.direction {
            Direction::Down => open = Some(t.at),
            Direction::Up => {
                if let Some(lo) = open.take() {
                    safe.push((lo, t.at));
                }
            }
            Direction::SlideIn | Direction::SlideOut => {}
        }
    }
    if let Some(lo) = open {
        safe.push((lo, a_max));
    }
    let overturns_above = match transitions.last() {
        Some(t) if t.direction == Direction::Up => Some(t.at),
        _ => None,
    };
    Derived {
        min_overturn: first_up.map(|t| t.at),
        min_overturn_mode: first_up.map(|t| t.mode),
        safe_intervals: safe,
        overturns_above,
        min_overturn_zone: None,
        min_certain_overturn: None,
    }
}

/// Drops overturning bands, then safe intervals, narrower than `rel` times their
/// central amplitude; merged bands keep the mode of their lowest part.
pub fn principal(transitions: &[Transition], a_max: f64, rel: f64) -> Vec<Transition> {
    // Overturning bands as (up, down-or-None).
    let mut bands: Vec<(Transition, Option<Transition>)> = Vec::new();
    let mut pending: Option<Transition> = None;
    for t in transitions {
        match t.direction {
            Direction::Up => pending = Some(*t),
            Direction::Down => {
                if let Some(up) = pending.take() {
                    bands.push((up, Some(*t)));
                }
            }
            Direction::SlideIn | Direction::SlideOut => {}
        }
    }
    if let Some(up) = pending {
        bands.push((up, None));
    }
    let narrow = |lo: f64, hi: f64| hi - lo < rel * 0.5 * (lo + hi);
    bands.retain(|(up, down)| {
        let hi = down.map_or(a_max, |d| d.at);
        !narrow(up.at, hi) || down.is_none() && hi >= a_max
    });
    let mut merged: Vec<(Transition, Option<Transition>)> = Vec::new();
    for band in bands {
        if let Some(last) = merged.last_mut()
            && let Some(down) = last.1
            && narrow(down.at, band.0.at)
        {
            last.1 = band.1;
            continue;
        }
        merged.push(band);
    }
    merged
        .into_iter()
        .flat_map(|(up, down)| std::iter::once(up).chain(down))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(at: f64, direction: Direction, mode: u8) -> Transition {
        Transition {
            at,
            direction,
            mode,
            impacts: u64::from(mode == 1),
            bracket: (at - 1e-5, at + 1e-5),
        }
    }

    #[test]
    fn derived_quantities_of_a_mode_one_bay_and_a_safe_cape() {
        let tr = [
            t(3.0, Direction::Up, 1),
            t(6.3, Direction::Down, 1),
            t(7.2, Direction::Up, 2),
        ];
        let d = derive(&tr, 20.0);
        assert_eq!(d.min_overturn, Some(3.0));
        assert_eq!(d.min_overturn_mode, Some(1));
        assert_eq!(d.safe_intervals, vec![(6.3, 7.2)]);
        assert_eq!(d.overturns_above, Some(7.2));
    }

    #[test]
    fn principal_view_drops_a_comb_of_narrow_bands() {
        let tr = [
            t(1.046, Direction::Up, 1),
            t(1.0461, Direction::Down, 1),
            t(1.05, Direction::Up, 1),
            t(1.0501, Direction::Down, 1),
            t(2.0, Direction::Up, 1),
            t(5.0, Direction::Down, 1),
            t(5.001, Direction::Up, 2),
        ];
        let p = principal(&tr, 20.0, 0.01);
        let d = derive(&p, 20.0);
        assert_eq!(d.min_overturn, Some(2.0));
        // The 0.001-wide safe gap at 5.0 is merged away: all overturns above 2.
        assert!(d.safe_intervals.is_empty(), "{:?}", d.safe_intervals);
        assert_eq!(d.overturns_above, Some(2.0));
    }
}
