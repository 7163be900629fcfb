//! The `forensic` job: which pulses are consistent with what was seen.
//!
//! The paper closes on its warning: a block that toppled, or survived, does not
//! give the peak ground acceleration directly — overturning sets have safe
//! regions inside them, and the nonlinear answer differs from the linear one.
//! Here every observation (a block that overturned or stood) is turned into
//! its set of consistent amplitudes at each pulse frequency, from the
//! overturning spectrum of that block (scan plus bisection of every
//! transition, so the sets are intervals located to `tolerance_g`, not grid
//! samples); the sets of all observations are intersected.

pub mod figure;
pub mod figure_record;
pub mod table;
pub mod table_record;

pub mod mixed;
pub mod record;
pub mod scan;

use serde::{Deserialize, Serialize};

use super::record_spectrum::RecordDoc;
use super::record_spectrum::{ScaleRangeNorm, ScaleRangeSpec, pga};
use super::spectrum::{PulseFamily, ScanCost, validate_family};
use crate::dynamics::Formulation;
use crate::jobs::names::{EngineDoc, Excitation, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, OMEGA_RATIO_RANGE, PulseSpec,
    SolverNorm, SolverSpec, SpecError, at_most_one, in_one_unit, parse_formulation, validate_block,
};
use crate::spectrum::Control;
use crate::spectrum::scan::{Direction, ScanError, ScanStats, Transition};

/// Most observations in one query.
pub const MAX_OBSERVATIONS: usize = 32;
/// Most pulse frequencies in one query.
pub const MAX_FREQUENCIES: usize = 2_000;
/// Default scan step, g.
pub const DEFAULT_SCAN_STEP_G: f64 = 0.01;
/// Default bracket width of every interval end, g.
pub const DEFAULT_TOLERANCE_G: f64 = 1e-4;

/// An object that was seen standing or overturned after the shaking.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ObservationSpec {
    /// What it is ("locomotive").
    pub name: Option<String>,
    /// The block (α and p, or b and h).
    pub block: Option<BlockSpec>,
    /// Half-width b, m (shorthand for `block.b`).
    #[schema(exclusive_minimum = 0.0)]
    pub b: Option<f64>,
    /// Half-height h, m (shorthand for `block.h`).
    #[schema(exclusive_minimum = 0.0)]
    pub h: Option<f64>,
    /// Whether it overturned.
    #[schema(required = true, value_type = bool)]
    pub overturned: Option<bool>,
    /// How far its base was found from where it stood, m, as `[lo, hi]`:
    /// the size of the residual slide of a block seen standing, on a
    /// Coulomb floor (`contact`). The amplitudes consistent with it are
    /// those at which the block stands with |residual slide| in `[lo, hi]`.
    #[schema(min_items = 2, max_items = 2)]
    pub slid_m: Option<Vec<f64>>,
}

/// An amplitude range in g.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct AmplitudeRange {
    /// Lowest amplitude (g for `a_p_g`, m/s² for `a_p`).
    #[schema(minimum = 0.0)]
    pub from: f64,
    /// Highest amplitude, above `from`.
    #[schema(exclusive_minimum = 0.0)]
    pub to: f64,
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ForensicSpec {
    /// "forensic".
    #[schema(value_type = crate::jobs::names::tag::Forensic)]
    pub kind: String,
    /// The pulse family (`type`, `n`, …); frequency and amplitude vary.
    /// Give this or `ground_motion`.
    #[schema(value_type = Option<crate::jobs::schema::PulseFamilyInput>)]
    pub pulse: Option<PulseSpec>,
    /// A recorded motion (`dt`, `acc`, `unit`) whose scale is the unknown:
    /// give this or `pulse`, and the scale axis as `scale` or `pga_g`.
    pub ground_motion: Option<GroundMotionSpec>,
    /// Scale factors examined (with `ground_motion`): `{"from", "to"}`.
    pub scale: Option<ScaleRangeSpec>,
    /// The scaled record's PGA examined, g (with `ground_motion`; or give `scale`).
    pub pga_g: Option<ScaleRangeSpec>,
    /// Bracket width of every interval end in scale units (with
    /// `ground_motion`; or give `tolerance_g`, in g of PGA).
    #[schema(exclusive_minimum = 0.0)]
    pub tolerance: Option<f64>,
    /// Scan step in scale units (with `ground_motion`; or give `scan_step_g`).
    #[schema(exclusive_minimum = 0.0)]
    pub scan_step: Option<f64>,
    /// What was seen (1 to 32 observations).
    #[schema(required = true, value_type = Vec<ObservationSpec>, min_items = 1, max_items = 32)]
    pub observations: Option<Vec<ObservationSpec>>,
    /// Pulse frequencies f_p = ω_p/2π, Hz (or give `omega_p`, or `omega_ratio`).
    pub frequency_hz: Option<RangeSpec>,
    /// Pulse circular frequencies ω_p, rad/s.
    pub omega_p: Option<RangeSpec>,
    /// ω_p/p: only when every observation's block has the same p.
    pub omega_ratio: Option<RangeSpec>,
    /// Amplitudes examined, g (or give `a_p`).
    pub a_p_g: Option<AmplitudeRange>,
    /// Amplitudes examined, m/s² (`from` and `to` in m/s²).
    pub a_p: Option<AmplitudeRange>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// Scan step, g (the tolerance to 1, default 0.01): every interval wider than this is found.
    #[schema(minimum = 1e-9, maximum = 1.0)]
    pub scan_step_g: Option<f64>,
    /// Bracket width of every interval end, g (1e-9 to 0.1, default 1e-4).
    #[schema(minimum = 1e-9, maximum = 0.1)]
    pub tolerance_g: Option<f64>,
    /// Solver.
    pub solver: Option<SolverSpec>,
    /// The vertical ground acceleration (positive up) as a share of the
    /// horizontal one at every amplitude or scale: `{"ratio": r}`, ü_v = r·ü_g;
    /// a pulse query also takes a pulse of its own scaled with each pulse
    /// (`type`, `amplitude_ratio`, `frequency_ratio` | `omega_p` |
    /// `frequency_hz`, `delay_s`), as spectra do (a record query also takes the record's own vertical samples as
    /// `ground_motion.vertical`, scaled with it; not both).
    pub vertical: Option<crate::jobs::vertical::VerticalPulseSpec>,
    /// The contact with the floor, the same for every observation:
    /// `{"model": "no_sliding"}` (pure rocking, the default) or
    /// `{"model": "coulomb", "mu", "mu_kinetic"?}`.
    pub contact: Option<crate::jobs::contact::ContactSpec>,
}

/// An observation, validated.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct Observation {
    /// Its name.
    pub name: String,
    /// Whether it overturned.
    pub overturned: bool,
    /// Its block.
    pub block: BlockNorm,
    /// The size of its residual slide, m, `[lo, hi]`, when seen.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slid_m: Option<[f64; 2]>,
}

/// A validated forensic query; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicJob {
    /// "forensic".
    pub kind: tag::Forensic,
    /// Pulse family (pulse queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseFamily>,
    /// The record, m/s² (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_motion: Option<GroundMotionNorm>,
    /// Observations.
    pub observations: Vec<Observation>,
    /// Frequencies, Hz (pulse queries).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frequency_hz: Vec<f64>,
    /// Amplitudes examined, g (pulse queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_p_g: Option<AmplitudeRange>,
    /// The scaled record's PGA examined, g (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pga_g: Option<AmplitudeRange>,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// Scan step, g.
    pub scan_step_g: f64,
    /// Bracket width, g.
    pub tolerance_g: f64,
    /// Solver.
    pub solver: SolverNorm,
    /// ü_v = r·ü_g (positive up), when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<crate::jobs::vertical::VerticalPulseNorm>,
    /// Coulomb friction at the floor, when given (absent: pure rocking).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<crate::jobs::contact::ContactNorm>,
    /// A task's lines and levels (absent: the whole query).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub part: Option<crate::jobs::scan_parts::Part>,
}

fn in_range(v: f64, lo: f64, hi: f64, pointer: &str, what: &str) -> Result<f64, SpecError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(SpecError::at(
            pointer,
            format!("{what} must lie in [{lo:e}, {hi}] (got {v})"),
        ))
    }
}

impl Observation {
    /// What was seen, as figures and tables word it: "overturned",
    /// "survived", or "survived, slid 0.02–0.3 m".
    pub fn seen(&self) -> String {
        match (self.overturned, self.slid_m) {
            (true, _) => "overturned".into(),
            (false, None) => "survived".into(),
            (false, Some([lo, hi])) if lo == hi => format!("survived, slid {lo} m"),
            (false, Some([lo, hi])) => format!("survived, slid {lo}–{hi} m"),
        }
    }
}

impl ObservationSpec {
    fn validate(&self, at: &str, index: usize) -> Result<Observation, SpecError> {
        let overturned = self.overturned.ok_or_else(|| {
            SpecError::at(
                format!("{at}/overturned"),
                "missing field: true if it overturned, false if it stood",
            )
        })?;
        let block = match (&self.block, self.b, self.h) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(SpecError::at(
                    format!("{at}/block"),
                    "give the block, or b and h beside it, not both",
                ));
            }
            (Some(spec), None, None) => validate_block(spec, &format!("{at}/block"))?,
            (None, b, h) if b.is_some() || h.is_some() => {
                let spec = BlockSpec {
                    b,
                    h,
                    ..BlockSpec::default()
                };
                validate_block(&spec, at)?
            }
            (None, _, _) => {
                return Err(SpecError::at(
                    format!("{at}/block"),
                    "missing field: the block ({\"alpha\", \"p\"} or {\"b\", \"h\"})",
                ));
            }
        };
        let slid_m = self
            .slid_m
            .as_deref()
            .map(|s| slide_band(s, overturned, &format!("{at}/slid_m")))
            .transpose()?;
        Ok(Observation {
            slid_m,
            name: self
                .name
                .clone()
                .filter(|n| !n.trim().is_empty())
                .unwrap_or_else(|| format!("observation {}", index + 1)),
            overturned,
            block,
        })
    }
}

impl crate::jobs::kind::Validate for ForensicSpec {
    type Job = ForensicJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<ForensicJob, SpecError> {
        match (&self.pulse, &self.ground_motion) {
            (Some(_), Some(_)) => Err(SpecError::at(
                "/ground_motion",
                "give a pulse family or a ground_motion, not both",
            )),
            (None, Some(gm)) => self.validate_record(gm),
            (pulse, None) => self.validate_pulse(pulse.as_ref()),
        }
        .and_then(|job| {
            // A slide is seen only on a floor that lets the block slide.
            match job.observations.iter().position(|o| o.slid_m.is_some()) {
                Some(i) if job.contact.is_none() => Err(SpecError::at(
                    format!("/observations/{i}/slid_m"),
                    "needs \"contact\": {\"model\": \"coulomb\", \"mu\": …}: in pure rocking (the default) the block never slides",
                )),
                _ => Ok(job),
            }
        })
    }
}

impl ForensicSpec {
    fn observations(&self) -> Result<Vec<Observation>, SpecError> {
        let specs = self.observations.as_ref().ok_or_else(|| {
            SpecError::at(
                "/observations",
                "missing field: a list of {\"name\", \"block\", \"overturned\"}",
            )
        })?;
        if specs.is_empty() || specs.len() > MAX_OBSERVATIONS {
            return Err(SpecError::at(
                "/observations",
                format!("give between 1 and {MAX_OBSERVATIONS} observations"),
            ));
        }
        specs
            .iter()
            .enumerate()
            .map(|(i, o)| o.validate(&format!("/observations/{i}"), i))
            .collect()
    }

    fn validate_pulse(&self, pulse: Option<&PulseSpec>) -> Result<ForensicJob, SpecError> {
        if pulse.is_none() {
            return Err(SpecError::at(
                "/pulse",
                "missing field: a pulse family {\"type\": …} whose frequency and amplitude are the unknowns, or a ground_motion {\"dt\", \"acc\", \"unit\"} whose scale is",
            ));
        }
        let pulse = validate_family(pulse, "/pulse")?;
        self.reject_record_axes()?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let vertical =
            crate::jobs::vertical::validate_scaled_vertical(self.vertical.as_ref(), "/vertical")?;
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            pulse.shape().is_sinusoidal(),
            vertical.is_some(),
            "/solver",
        )?;
        let observations = self.observations()?;
        let frequency_hz = self.pulse_frequencies(&observations)?;
        let AmplitudeRange { from, to } = self.pulse_amplitudes(&observations)?;
        let (tolerance_g, scan_step_g) = amplitude_grid(
            &observations,
            to,
            (self.tolerance_g, "/tolerance_g", 1.0),
            (self.scan_step_g, "/scan_step_g", 1.0),
            "/a_p_g/to",
        )?;
        Ok(ForensicJob {
            kind: tag::Forensic,
            pulse: Some(pulse),
            ground_motion: None,
            observations,
            frequency_hz,
            a_p_g: Some(AmplitudeRange { from, to }),
            pga_g: None,
            formulation,
            scan_step_g,
            tolerance_g,
            solver,
            vertical,
            contact: crate::jobs::contact::validate_contact(
                self.contact.as_ref(),
                formulation,
                "/contact",
            )?,
            part: None,
        })
    }

    /// A pulse query gives none of a record query's fields (scale, pga_g,
    /// tolerance, scan_step): the first given is the error.
    fn reject_record_axes(&self) -> Result<(), SpecError> {
        first_given_refused(
            &[
                (self.scale.is_some(), "scale"),
                (self.pga_g.is_some(), "pga_g"),
                (self.tolerance.is_some(), "tolerance"),
                (self.scan_step.is_some(), "scan_step"),
            ],
            "scales a ground_motion: a pulse query's axes are the frequency (frequency_hz, omega_p, omega_ratio) and the amplitude (a_p_g, a_p), with tolerance_g and scan_step_g",
        )
    }

    /// The pulse frequencies, Hz, given in Hz, rad/s, or as ω_p/p where every
    /// block shares p: each in [1e-3, 1e3] Hz and, for every block, within
    /// `OMEGA_RATIO_RANGE` of its p.
    fn pulse_frequencies(&self, observations: &[Observation]) -> Result<Vec<f64>, SpecError> {
        // Frequencies in Hz, rad/s, or ω_p/p where every block shares p.
        let tau = std::f64::consts::TAU;
        let ps: Vec<f64> = observations.iter().map(|o| o.block.p).collect();
        let same_p = ps.iter().all(|p| (p / ps[0] - 1.0).abs() < 1e-12);
        let (range, which) = at_most_one(
            "",
            &[
                (self.frequency_hz.as_ref(), "frequency_hz"),
                (self.omega_p.as_ref(), "omega_p"),
                (self.omega_ratio.as_ref(), "omega_ratio"),
            ],
            "frequency axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/frequency_hz",
                "missing field: the pulse frequencies as frequency_hz, omega_p (rad/s) or omega_ratio: {\"from\", \"to\", \"steps\"} or a list",
            )
        })?;
        let name = ["frequency_hz", "omega_p", "omega_ratio"][which];
        if name == "omega_ratio" && !same_p {
            return Err(SpecError::at(
                "/omega_ratio",
                format!(
                    "ω_p/p names one frequency per block only when every block has the same p; these have p = {ps:?} rad/s: give frequency_hz or omega_p"
                ),
            ));
        }
        let to_hz = match name {
            "omega_p" => 1.0 / tau,
            "omega_ratio" => ps[0] / tau,
            _ => 1.0,
        };
        let pointer = format!("/{name}");
        let frequency_hz: Vec<f64> = range
            .values(&pointer, 0.0, f64::MAX, MAX_FREQUENCIES)?
            .into_iter()
            .map(|v| v * to_hz)
            .collect();
        if let Some(bad) = frequency_hz.iter().find(|f| !(1e-3..=1e3).contains(*f)) {
            return Err(SpecError::at(
                &pointer,
                format!("every frequency must lie in [1e-3, 1e3] Hz; one is {bad} Hz"),
            ));
        }
        check_omega_ratios(observations, &frequency_hz, &pointer)?;
        Ok(frequency_hz)
    }

    /// The pulse amplitudes, g, given in g or in m/s² where every block
    /// shares g: from in [0, 100], to in [1e-3, 100], to above from.
    fn pulse_amplitudes(&self, observations: &[Observation]) -> Result<AmplitudeRange, SpecError> {
        // Amplitudes in g, or in m/s² where every block shares g.
        let range = match (self.a_p_g, self.a_p) {
            (Some(r), None) => r,
            (None, Some(r)) => {
                let g = common_g(observations).ok_or_else(|| {
                    SpecError::at(
                        "/a_p",
                        "a_p in m/s² converts to g only when every block has the same g: give a_p_g",
                    )
                })?;
                AmplitudeRange {
                    from: r.from / g,
                    to: r.to / g,
                }
            }
            (Some(_), Some(_)) => {
                return Err(SpecError::at(
                    "/a_p",
                    "give exactly one amplitude range (a_p_g, a_p), not several",
                ));
            }
            (None, None) => {
                return Err(SpecError::at(
                    "/a_p_g",
                    "missing field: {\"from\", \"to\"} in g (or a_p in m/s²)",
                ));
            }
        };
        let from = in_range(
            range.from,
            0.0,
            100.0,
            "/a_p_g/from",
            "the lowest amplitude",
        )?;
        let to = in_range(range.to, 1e-3, 100.0, "/a_p_g/to", "the highest amplitude")?;
        if to <= from {
            return Err(SpecError::at("/a_p_g", "to must exceed from"));
        }
        Ok(AmplitudeRange { from, to })
    }

    fn validate_record(&self, gm: &GroundMotionSpec) -> Result<ForensicJob, SpecError> {
        self.reject_pulse_axes()?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let observations = self.observations()?;
        let g = common_g(&observations).ok_or_else(|| {
            SpecError::at(
                "/observations",
                "a record's PGA in g is one number only when every block has the same g",
            )
        })?;
        // The most slender block bounds the samples most tightly.
        let weakest = observations
            .iter()
            .map(|o| &o.block)
            .min_by(|a, b| a.alpha.total_cmp(&b.alpha))
            .ok_or_else(|| SpecError::at("/observations", "give at least one observation"))?;
        let (ground_motion, vertical) = crate::jobs::vertical::validate_scaled_record(
            self.vertical.as_ref(),
            gm,
            weakest,
            "/ground_motion",
        )?;
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            true,
            vertical.is_some() || ground_motion.vertical.is_some(),
            "/solver",
        )?;
        let peak_g = pga(&ground_motion.acc) / g;
        if peak_g == 0.0 {
            return Err(SpecError::at(
                "/ground_motion/acc",
                "the record has no motion (every sample is 0)",
            ));
        }
        let (pga_g, s_name) = self.scaled_pga_g(peak_g)?;
        let (tolerance_g, scan_step_g) = amplitude_grid(
            &observations,
            pga_g.to,
            at_most_one_unit(
                (self.tolerance_g, "/tolerance_g", 1.0),
                (self.tolerance, "/tolerance", peak_g),
            )?,
            at_most_one_unit(
                (self.scan_step_g, "/scan_step_g", 1.0),
                (self.scan_step, "/scan_step", peak_g),
            )?,
            &format!("/{s_name}/to"),
        )?;
        Ok(ForensicJob {
            kind: tag::Forensic,
            pulse: None,
            ground_motion: Some(ground_motion),
            observations,
            frequency_hz: Vec::new(),
            a_p_g: None,
            pga_g: Some(pga_g),
            formulation,
            scan_step_g,
            tolerance_g,
            solver,
            vertical,
            contact: crate::jobs::contact::validate_contact(
                self.contact.as_ref(),
                formulation,
                "/contact",
            )?,
            part: None,
        })
    }

    /// A record query gives none of a pulse query's axes (frequency_hz,
    /// omega_p, omega_ratio, a_p_g, a_p): the first given is the error.
    fn reject_pulse_axes(&self) -> Result<(), SpecError> {
        first_given_refused(
            &[
                (self.frequency_hz.is_some(), "frequency_hz"),
                (self.omega_p.is_some(), "omega_p"),
                (self.omega_ratio.is_some(), "omega_ratio"),
                (self.a_p_g.is_some(), "a_p_g"),
                (self.a_p.is_some(), "a_p"),
            ],
            "a record query's only unknown is the record's scale: give it as scale {\"from\", \"to\"} or as the scaled PGA pga_g {\"from\", \"to\"}",
        )
    }

    /// The record's scaled PGA range, g, given as scale factors or as pga_g
    /// (the record's own PGA is `peak_g`), with the name of the field that
    /// gave it; its top in [1e-3, 100] g.
    fn scaled_pga_g(&self, peak_g: f64) -> Result<(AmplitudeRange, &'static str), SpecError> {
        let (range, s_name, to_g) = in_one_unit(
            &[
                (self.scale.as_ref(), "scale", peak_g),
                (self.pga_g.as_ref(), "pga_g", 1.0),
            ],
            "scale axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/scale",
                "missing field: the scale factors as scale {\"from\", \"to\"} or the scaled PGA as pga_g {\"from\", \"to\"}",
            )
        })?;
        let (from, to) = range.ends(s_name)?;
        let (from_g, to_g) = (from * to_g, to * to_g);
        if !(1e-3..=100.0).contains(&to_g) {
            return Err(SpecError::at(
                format!("/{s_name}/to"),
                format!(
                    "the scaled PGA must lie in [1e-3, 100] g (the record's PGA is {peak_g:.6} g; got {to_g} g)"
                ),
            ));
        }
        Ok((
            AmplitudeRange {
                from: from_g,
                to: to_g,
            },
            s_name,
        ))
    }
}

/// Every frequency of `frequency_hz` (the field at `pointer`) is, for every
/// observation's block, within `OMEGA_RATIO_RANGE` of its p.
fn check_omega_ratios(
    observations: &[Observation],
    frequency_hz: &[f64],
    pointer: &str,
) -> Result<(), SpecError> {
    for (i, o) in observations.iter().enumerate() {
        for &f in frequency_hz {
            let ratio = 2.0 * std::f64::consts::PI * f / o.block.p;
            if !(OMEGA_RATIO_RANGE.0..=OMEGA_RATIO_RANGE.1).contains(&ratio) {
                return Err(SpecError::at(
                    pointer,
                    format!(
                        "{f} Hz is ω_p/p = {ratio:.3e} for observation {i} ({}), outside [{}, {}]",
                        o.name, OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The first of `fields` (given, name) that is given, refused with
/// `message` at its pointer.
fn first_given_refused(fields: &[(bool, &str)], message: &str) -> Result<(), SpecError> {
    match fields.iter().find(|(given, _)| *given) {
        Some((_, name)) => Err(SpecError::at(format!("/{name}"), message)),
        None => Ok(()),
    }
}

/// The gravity every block shares, if they do.
fn common_g(observations: &[Observation]) -> Option<f64> {
    let g = observations.first()?.block.g;
    observations.iter().all(|o| o.block.g == g).then_some(g)
}

/// A value given in g or in scale units (at most one): `(value, pointer, g per unit)`.
type InUnit = (Option<f64>, &'static str, f64);

fn at_most_one_unit(in_g: InUnit, in_scale: InUnit) -> Result<InUnit, SpecError> {
    match (in_g.0, in_scale.0) {
        (Some(_), Some(_)) => Err(SpecError::at(
            in_scale.1,
            format!("give {} or {}, not both", in_g.1, in_scale.1),
        )),
        (None, Some(_)) => Ok(in_scale),
        _ => Ok(in_g),
    }
}

/// The bracket width and scan step in g (`(value, pointer, g per unit)`,
/// defaults 1e-4 g and 0.01 g), checked against the highest amplitude `to` g
/// of every observation's block.
fn amplitude_grid(
    observations: &[Observation],
    to: f64,
    tolerance: InUnit,
    scan_step: InUnit,
    to_pointer: &str,
) -> Result<(f64, f64), SpecError> {
    let tolerance_g = in_range(
        tolerance.0.map_or(DEFAULT_TOLERANCE_G, |v| v * tolerance.2),
        1e-9,
        0.1,
        tolerance.1,
        "the tolerance (g)",
    )?;
    let scan_step_g = in_range(
        scan_step.0.map_or(DEFAULT_SCAN_STEP_G, |v| v * scan_step.2),
        tolerance_g,
        1.0,
        scan_step.1,
        "the scan step (g, at least the tolerance)",
    )?;
    if to / scan_step_g > super::spectrum::MAX_SCAN_POINTS {
        return Err(SpecError::at(
            scan_step.1,
            "the highest amplitude over the scan step must not exceed 1e6",
        ));
    }
    for o in observations {
        if to / o.block.alpha > 1e4 {
            return Err(SpecError::at(
                to_pointer,
                format!(
                    "must not exceed 1e4 α g for {} ({} g)",
                    o.name,
                    1e4 * o.block.alpha
                ),
            ));
        }
    }
    Ok((tolerance_g, scan_step_g))
}

/// Largest residual slide an observation may give, m.
pub const MAX_SLID_M: f64 = 1e3;

/// A seen slide `[lo, hi]`, m, of an observation (`overturned` or not) at `at`.
fn slide_band(s: &[f64], overturned: bool, at: &str) -> Result<[f64; 2], SpecError> {
    let &[lo, hi] = s else {
        return Err(SpecError::at(
            at,
            format!("give [lo, hi], m: two sizes, not {}", s.len()),
        ));
    };
    if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi && hi <= MAX_SLID_M) {
        return Err(SpecError::at(
            at,
            format!("must satisfy 0 <= lo <= hi <= {MAX_SLID_M} m (got [{lo}, {hi}])"),
        ));
    }
    if overturned {
        return Err(SpecError::at(
            at,
            "is seen on a block that stands: an overturned block's slide before it fell is not told apart from its fall",
        ));
    }
    Ok([lo, hi])
}

/// Intervals [lo, hi] of amplitude, g, sorted and disjoint.
pub type Intervals = Vec<[f64; 2]>;

/// What one line (an observation's block at one frequency, or under the
/// record) decides, g.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LineSet {
    /// Amplitudes at which the block overturns.
    pub overturning: Intervals,
    /// The line decides amplitudes up to here (the range asked, or on a
    /// Coulomb floor the block's leaving the floor).
    pub decided_to: f64,
    /// On a Coulomb floor: the lowest amplitude found at which the block
    /// leaves the floor.
    pub lift_off_g: Option<f64>,
    /// For an observation with `slid_m`: the amplitudes at which the block
    /// stands with its residual slide's size in the band.
    pub slide_band: Option<Intervals>,
    /// Where the outcome alternates finer than the scan resolves, g: no
    /// amplitude inside is claimed consistent or not.
    pub mixed: Vec<crate::spectrum::verify::Mixed>,
}

impl LineSet {
    /// The amplitudes consistent with a block seen `overturned` (or
    /// standing), from `from`.
    pub fn consistent(&self, overturned: bool, from: f64) -> Intervals {
        let all = if let Some(band) = &self.slide_band {
            clip(band, from, self.decided_to)
        } else if overturned {
            self.overturning.clone()
        } else {
            complement(&self.overturning, from, self.decided_to)
        };
        crate::spectrum::verify::outside(&all, &self.mixed)
    }

    /// Where the block certainly overturns: outside the mixed zones.
    pub fn certain_overturning(&self) -> Intervals {
        crate::spectrum::verify::outside(&self.overturning, &self.mixed)
    }
}

/// Where a line with `transitions` (of a block of slenderness `alpha`) overturns, in g, within
/// `[from, to]`.
pub fn overturning_set(transitions: &[Transition], alpha: f64, from: f64, to: f64) -> Intervals {
    let mut out = Vec::new();
    let mut open: Option<f64> = None;
    for t in transitions {
        let at = t.at * alpha;
        match t.direction {
            Direction::Up => open = Some(at),
            Direction::Down => {
                if let Some(lo) = open.take() {
                    out.push([lo, at]);
                }
            }
            Direction::SlideIn | Direction::SlideOut => {}
        }
    }
    if let Some(lo) = open {
        out.push([lo, to]);
    }
    clip(&out, from, to)
}

/// Where a line's block (of slenderness `alpha`) stands with its residual
/// slide in the band, in g within `[from, to]`, from the band's edges
/// (`transitions`, in order) and whether the line's first level is inside
/// it (`inside`; the block has not moved there, nor anywhere below).
pub fn slide_band_set(
    transitions: &[Transition],
    inside: bool,
    alpha: f64,
    from: f64,
    to: f64,
) -> Intervals {
    let mut out = Vec::new();
    let mut open = inside.then_some(from);
    for t in transitions {
        let at = t.at * alpha;
        match t.direction {
            Direction::SlideIn => open = Some(at),
            Direction::SlideOut => {
                if let Some(lo) = open.take() {
                    out.push([lo, at]);
                }
            }
            _ => {}
        }
    }
    if let Some(lo) = open {
        out.push([lo, to]);
    }
    clip(&out, from, to)
}

fn clip(set: &[[f64; 2]], from: f64, to: f64) -> Intervals {
    set.iter()
        .map(|&[a, b]| [a.max(from), b.min(to)])
        .filter(|[a, b]| b > a)
        .collect()
}

/// `[from, to]` without `set`.
pub fn complement(set: &[[f64; 2]], from: f64, to: f64) -> Intervals {
    let mut out = Vec::new();
    let mut lo = from;
    for &[a, b] in set {
        if a > lo {
            out.push([lo, a]);
        }
        lo = lo.max(b);
    }
    if to > lo {
        out.push([lo, to]);
    }
    out
}

/// The amplitudes in both sets.
pub fn intersect(x: &[[f64; 2]], y: &[[f64; 2]]) -> Intervals {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < x.len() && j < y.len() {
        let lo = x[i][0].max(y[j][0]);
        let hi = x[i][1].min(y[j][1]);
        if hi > lo {
            out.push([lo, hi]);
        }
        if x[i][1] < y[j][1] {
            i += 1;
        } else {
            j += 1;
        }
    }
    out
}

/// One observation's consistent amplitudes at one frequency.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ObservationSet {
    /// The observation.
    pub name: String,
    /// Amplitudes certainly consistent with it, g: every one verified
    /// inside ([`crate::spectrum::verify`]).
    pub consistent_g: Vec<[f64; 2]>,
    /// Where its outcome alternates finer than the scan resolves, g, with
    /// the fraction of probed amplitudes at which its block did what was
    /// seen.
    #[serde(default)]
    pub mixed_g: Vec<mixed::MixedDoc>,
    /// On a Coulomb floor: from this amplitude (g, the lowest found within
    /// the tolerance) its block leaves the floor; nothing above is claimed
    /// consistent with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_g: Option<f64>,
}

/// One pulse frequency of the answer.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicFrequency {
    /// f_p, Hz.
    pub frequency_hz: f64,
    /// ω_p, rad/s.
    pub omega_p: f64,
    /// Amplitudes certainly consistent with every observation, g.
    pub consistent_g: Vec<[f64; 2]>,
    /// Where every observation is consistent or mixed and one at least
    /// mixed, g (the fraction: the product of theirs).
    #[serde(default)]
    pub mixed_g: Vec<mixed::MixedDoc>,
    /// Each observation's consistent amplitudes, g.
    pub per_observation: Vec<ObservationSet>,
}

/// The range of pulses consistent with everything seen.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct Bounds {
    /// Lowest consistent amplitude at any frequency, g.
    #[schema(required = true)]
    pub min_g: Option<f64>,
    /// Highest consistent amplitude at any frequency, g.
    #[schema(required = true)]
    pub max_g: Option<f64>,
    /// Lowest and highest frequency with a consistent amplitude, Hz (null
    /// for a record query).
    #[schema(required = true)]
    pub frequency_hz: Option<[f64; 2]>,
    /// Lowest consistent scale factor (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_scale: Option<f64>,
    /// Highest consistent scale factor (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_scale: Option<f64>,
}

/// One observation's consistent scales of a record query.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordObservationSet {
    /// The observation.
    pub name: String,
    /// Whether it overturned.
    pub overturned: bool,
    /// Scale factors certainly consistent with it: every interval verified
    /// inside ([`crate::spectrum::verify`]).
    pub consistent_scale: Vec<[f64; 2]>,
    /// The same, as the scaled record's PGA, g.
    pub consistent_pga_g: Vec<[f64; 2]>,
    /// Where its outcome alternates finer than the scan resolves (scale
    /// factors), with the fraction of probed scales at which its block did
    /// what was seen.
    #[serde(default)]
    pub mixed_scale: Vec<mixed::MixedDoc>,
    /// The same, as the scaled record's PGA, g.
    #[serde(default)]
    pub mixed_pga_g: Vec<mixed::MixedDoc>,
    /// Scale factors at which its block certainly overturns (within the
    /// range examined, outside the mixed zones).
    pub overturning_scale: Vec<[f64; 2]>,
    /// Scale factor at which its block starts to rock (PGA = g tan α, or g α linear).
    pub threshold_scale: f64,
    /// On a Coulomb floor: from this scale factor (the lowest found within
    /// the tolerance) its block leaves the floor; nothing above is claimed
    /// consistent with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
}

/// Cost and accuracy.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicNumerics {
    /// Solver, cost and worst error estimate (all observations).
    #[serde(flatten)]
    pub cost: ScanCost,
    /// Every interval end is bracketed within this, g.
    pub tolerance_g: f64,
    /// Scan step, g.
    pub scan_step_g: f64,
    /// Wall time, s (of a query computed in several tasks: their total
    /// compute time).
    pub wall_time_s: f64,
    /// Tasks the query was computed in (absent: one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tasks: Option<usize>,
}

/// The result document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicResult {
    /// "forensic".
    pub kind: tag::Forensic,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// "pulse": the unknowns are the pulse's frequency and amplitude
    /// (`pulse`, `frequencies`); "ground_motion": the unknown is the record's
    /// scale (`record`, `scale`, `consistent_scale`, `per_observation`).
    #[schema(value_type = crate::jobs::schema::ForensicExcitation)]
    pub excitation: Excitation,
    /// Pulse family (pulse queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseFamily>,
    /// The record's PGA, PGV, PGD and sampling, unscaled (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub record: Option<RecordDoc>,
    /// Amplitudes examined, g (a record query: the scaled PGA).
    pub a_p_g: AmplitudeRange,
    /// Scale factors examined (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<ScaleRangeNorm>,
    /// The observations.
    pub observations: Vec<Observation>,
    /// One entry per frequency (empty for a record query).
    pub frequencies: Vec<ForensicFrequency>,
    /// Scale factors consistent with every observation (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consistent_scale: Option<Vec<[f64; 2]>>,
    /// The same, as the scaled record's PGA, g (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consistent_pga_g: Option<Vec<[f64; 2]>>,
    /// Where every observation is consistent or mixed, and one at least
    /// mixed: scale factors, with the product of their fractions (record
    /// queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixed_scale: Option<Vec<mixed::MixedDoc>>,
    /// The same, as the scaled record's PGA, g (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixed_pga_g: Option<Vec<mixed::MixedDoc>>,
    /// Each observation's consistent scales (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_observation: Option<Vec<RecordObservationSet>>,
    /// Overall bounds.
    pub bounds: Bounds,
    /// Under a vertical motion: from this amplitude (g; a pulse's peak, or
    /// the scaled record's PGA) the ground falls away faster than gravity
    /// (g + ü_v ≤ 0) and the block leaves it. The query is answered up to
    /// just below it (`a_p_g`/`pga_g` end there) and claims nothing above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_g: Option<f64>,
    /// Numerics.
    pub numerics: ForensicNumerics,
    /// The normalised spec.
    pub spec: ForensicJob,
    /// Notes on the inputs (`implausible_size`: a block smaller than 1 cm or
    /// larger than 100 m; `implausible_slide`: a seen slide past 1 m); absent
    /// when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(ForensicResult);

impl ForensicJob {
    /// The amplitudes examined, g: a pulse's peak, or the scaled record's
    /// PGA; under a vertical motion, up to just below the amplitude where the
    /// ground falls away faster than gravity ([`ForensicJob::lift_off_g`]).
    pub fn range_g(&self) -> AmplitudeRange {
        let range = self
            .a_p_g
            .or(self.pga_g)
            .unwrap_or(AmplitudeRange { from: 0.0, to: 0.0 });
        match self.lift_off_g() {
            Some((lo, _)) => AmplitudeRange {
                from: range.from,
                to: range.to.min(lo).max(range.from),
            },
            None => range,
        }
    }

    /// ü_v/ü_g, when the query has a vertical motion given as a ratio.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// The vertical motion scaled with the ground motion (a ratio, or a
    /// record's own samples), when the query has one.
    pub fn scaled_vertical(&self) -> Option<crate::jobs::vertical::ScaledVertical<'_>> {
        crate::jobs::vertical::ScaledVertical::of(
            self.vertical.as_ref(),
            self.ground_motion.as_ref(),
        )
    }

    /// Under a vertical motion ü_v = r ü_g: the amplitude (g; a pulse's
    /// peak, or the scaled record's PGA) from which the ground falls away
    /// faster than gravity somewhere (g + ü_v ≤ 0) and the block leaves it,
    /// bracketed `(lo, hi)`; `None` when it does not within the range asked
    /// (or without a vertical motion). The same for every block: it is the
    /// ground's.
    pub fn lift_off_g(&self) -> Option<(f64, f64)> {
        use crate::dynamics::{Block, Pulse};
        // On a Coulomb floor the block's flights are followed.
        if self.contact.is_some() {
            return None;
        }
        use crate::spectrum::scan::lift_off_level;
        let vertical = self.scaled_vertical()?;
        let asked = self.a_p_g.or(self.pga_g)?;
        // Any block of slenderness 1 under the observations' g: levels in g.
        let g = self.observations.first()?.block.g;
        let unit = Block::new(1.0, 1.0, None, None, Some(g)).ok()?;
        let (lo, hi) = match (&self.ground_motion, &self.pulse) {
            (Some(gm), _) => vertical.record_lift_off(&gm.record().ok()?, &unit, asked.to)?,
            (None, Some(family)) => {
                // (The same at every frequency: the vertical motion's
                // extremes scale with the amplitude, whatever its length.)
                let pulse = Pulse::new(family.shape(), g, 1.0).ok()?;
                let pair = vertical.pulse_pair(pulse)?.ok()?;
                lift_off_level(&pair, &unit, asked.to)?
            }
            (None, None) => return None,
        };
        Some((lo, hi))
    }

    /// The scale factors examined by a record query: `pga_g` over the
    /// record's PGA (in the g every block shares); `None` for a pulse query.
    pub fn scale(&self) -> Option<ScaleRangeNorm> {
        let gm = self.ground_motion.as_ref()?;
        self.pga_g?;
        // (Under a vertical motion, up to just below the lift-off.)
        let range = self.range_g();
        let peak_g = pga(&gm.acc) / common_g(&self.observations)?;
        Some(ScaleRangeNorm {
            from: range.from / peak_g,
            to: range.to / peak_g,
        })
    }

    /// The result of a pulse query from each observation's overturning set
    /// at each frequency (`sets[observation][frequency]`, g): the sets
    /// consistent with what was seen, intersected at each frequency.
    fn pulse_result(
        &self,
        sets: &[Vec<LineSet>],
        stats: &ScanStats,
    ) -> Result<ForensicResult, ScanError> {
        let pulse = self
            .pulse
            .ok_or(ScanError::Simulation(crate::dynamics::SimError::Tolerance))?;
        let frequencies = self.frequency_sets(sets);
        let bounds = Self::pulse_bounds(&frequencies);
        Ok(ForensicResult {
            warnings: Vec::new(),
            kind: tag::Forensic,
            formulation: self.formulation,
            excitation: Excitation::Pulse,
            pulse: Some(pulse),
            record: None,
            a_p_g: self.range_g(),
            scale: None,
            observations: self.observations.clone(),
            frequencies,
            consistent_scale: None,
            consistent_pga_g: None,
            mixed_scale: None,
            mixed_pga_g: None,
            per_observation: None,
            bounds,
            lift_off_above_g: self.lift_off_g().map(|(_, hi)| hi),
            numerics: ForensicNumerics {
                cost: ScanCost::new(&self.solver, stats),
                tolerance_g: self.tolerance_g,
                scan_step_g: self.scan_step_g,
                wall_time_s: 0.0,
                tasks: None,
            },
            spec: self.clone(),
            engine: None,
        })
    }

    /// Per frequency, the amplitudes, g, consistent with every observation,
    /// and each observation's own, with their mixed zones
    /// (`sets[observation][frequency]`).
    fn frequency_sets(&self, sets: &[Vec<LineSet>]) -> Vec<ForensicFrequency> {
        let two_pi = 2.0 * std::f64::consts::PI;
        let AmplitudeRange { from, to } = self.range_g();
        // Each observation's certain intervals and mixed zones, per frequency.
        let (consistent, zones): (Vec<Vec<Intervals>>, Vec<Vec<Vec<mixed::MixedDoc>>>) = self
            .observations
            .iter()
            .zip(sets)
            .map(|(o, per_frequency)| {
                per_frequency
                    .iter()
                    .map(|line| {
                        (
                            line.consistent(o.overturned, from),
                            mixed::observation_zones(line, o, from),
                        )
                    })
                    .unzip()
            })
            .unzip();
        self.frequency_hz
            .iter()
            .enumerate()
            .map(|(k, &f)| {
                let mut all: Intervals = vec![[from, to]];
                let per_observation = self
                    .observations
                    .iter()
                    .zip(&consistent)
                    .zip(&zones)
                    .zip(sets)
                    .map(|(((o, s), z), lines)| {
                        all = intersect(&all, &s[k]);
                        ObservationSet {
                            name: o.name.clone(),
                            consistent_g: s[k].clone(),
                            mixed_g: z[k].clone(),
                            lift_off_above_g: lines.get(k).and_then(|l| l.lift_off_g),
                        }
                    })
                    .collect();
                let here: Vec<Intervals> = consistent.iter().map(|v| v[k].clone()).collect();
                let here_zones: Vec<Vec<mixed::MixedDoc>> =
                    zones.iter().map(|v| v[k].clone()).collect();
                ForensicFrequency {
                    frequency_hz: f,
                    omega_p: two_pi * f,
                    consistent_g: all,
                    mixed_g: mixed::combined(&here, &here_zones),
                    per_observation,
                }
            })
            .collect()
    }

    /// The bounds of the consistent amplitudes, g, over the frequencies, and
    /// the frequencies, Hz, where some are.
    fn pulse_bounds(frequencies: &[ForensicFrequency]) -> Bounds {
        let mut bounds = Bounds {
            min_g: None,
            max_g: None,
            frequency_hz: None,
            min_scale: None,
            max_scale: None,
        };
        for f in frequencies {
            if let (Some(first), Some(last)) = (f.consistent_g.first(), f.consistent_g.last()) {
                bounds.min_g = Some(bounds.min_g.map_or(first[0], |m| m.min(first[0])));
                bounds.max_g = Some(bounds.max_g.map_or(last[1], |m| m.max(last[1])));
                bounds.frequency_hz = Some(match bounds.frequency_hz {
                    None => [f.frequency_hz, f.frequency_hz],
                    Some([lo, hi]) => [lo.min(f.frequency_hz), hi.max(f.frequency_hz)],
                });
            }
        }
        bounds
    }
}

/// The `forensic` kind: the pulses, or the scales of a record, consistent
/// with blocks seen overturned or standing.
pub struct Forensic;

impl crate::kinds::kind::Kind for Forensic {
    const NAME: &'static str = crate::jobs::names::tag::Forensic::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Forensic query";
    type Spec = ForensicSpec;
    type Job = ForensicJob;
    type Result = ForensicResult;
    type Part = crate::jobs::scan_parts::PartDoc;

    fn parse(value: &serde_json::Value) -> Result<ForensicJob, SpecError> {
        // Serde would also read a block from an array, by position.
        if let Some(list) = value.get("observations").and_then(|v| v.as_array()) {
            for (i, o) in list.iter().enumerate() {
                if let Some(b) = o.get("block")
                    && !(b.is_object() || b.is_null())
                {
                    return Err(SpecError::at(
                        format!("/observations/{i}/block"),
                        "must be a JSON object",
                    ));
                }
            }
        }
        use crate::jobs::kind::Validate;
        crate::jobs::spec::from_value::<ForensicSpec>(value, "")?.validate()
    }

    fn run(
        job: &ForensicJob,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        use crate::kinds::kind::Output;
        Ok(match job.part {
            // A task's transitions, assembled by the service.
            Some(p) => Output::Part(job.run_part(p, control)?),
            None => Output::Whole(job.run(control)?),
        })
    }

    /// A query over a record's scales has a table and a figure of its
    /// own (scales and PGAs, not frequencies and amplitudes).
    fn table(
        result: &ForensicResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        match result.excitation {
            Excitation::GroundMotion => table_record::rows(result, table),
            Excitation::Pulse => table::rows(result, table),
        }
    }

    fn figure(
        result: &ForensicResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || match result.excitation {
            Excitation::GroundMotion => figure_record::svg(result),
            Excitation::Pulse => figure::svg(result),
        })
    }

    /// Scan points of every observation's lines, each bisected down to the
    /// tolerance ([`crate::jobs::cost`]), at the cost of a simulation of the pulse
    /// or the record.
    fn size(job: &ForensicJob) -> crate::jobs::kind::Size {
        job.scan_size()
            .unwrap_or_else(|_| crate::jobs::kind::Size::one(0.0))
    }

    fn grid_field(job: &ForensicJob) -> &'static str {
        if job.ground_motion.is_some() {
            "/scale"
        } else {
            "/frequency_hz"
        }
    }

    fn warnings(job: &ForensicJob) -> Vec<crate::jobs::warning::WarningDoc> {
        use crate::jobs::plausible::{
            coarse_dt_warning, record_warnings, size_warnings, slide_warning,
        };
        let mut found = size_warnings(
            job.observations
                .iter()
                .enumerate()
                .map(|(i, o)| (&o.block, format!("/observations/{i}/block"))),
        );
        found.extend(job.observations.iter().enumerate().filter_map(|(i, o)| {
            o.slid_m
                .and_then(|band| slide_warning(band, &format!("/observations/{i}/slid_m")))
        }));
        if let Some(m) = &job.ground_motion {
            found.extend(record_warnings(m, "/ground_motion"));
            if let Some(p) = job.observations.iter().map(|o| o.block.p).reduce(f64::max) {
                found.extend(coarse_dt_warning(m.dt, p, "/ground_motion"));
            }
        }
        found
    }

    /// Tasks of about [`crate::jobs::cost::TASK_CPU_S`]: an observation's lines
    /// grouped, or a line split along its levels ([`scan`]); each task
    /// names its part of the query, whose record is stored once.
    fn split(job: &ForensicJob, _size: &crate::jobs::kind::Size) -> Vec<ForensicJob> {
        crate::jobs::scan_parts::split(job)
    }

    fn task_payload(job: &ForensicJob) -> Option<String> {
        crate::jobs::scan_parts::task_payload(job)
    }

    fn part_of(
        whole: &ForensicJob,
        payload: &serde_json::Value,
    ) -> Option<Result<ForensicJob, crate::jobs::JobError>> {
        crate::jobs::scan_parts::part_of(whole, payload)
    }

    fn is_part(job: &ForensicJob) -> bool {
        job.part.is_some()
    }

    /// The parts' transitions gathered per line, and everything derived
    /// from them as one task would.
    fn assemble(
        job: &ForensicJob,
        parts: Vec<crate::jobs::scan_parts::PartDoc>,
    ) -> Result<ForensicResult, crate::jobs::JobError> {
        job.result_of(&parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_algebra() {
        let a = vec![[0.0, 1.0], [2.0, 3.0]];
        assert_eq!(
            complement(&a, -1.0, 4.0),
            vec![[-1.0, 0.0], [1.0, 2.0], [3.0, 4.0]]
        );
        assert_eq!(complement(&[], 0.0, 1.0), vec![[0.0, 1.0]]);
        assert_eq!(complement(&[[0.0, 1.0]], 0.0, 1.0), Vec::<[f64; 2]>::new());
        let b = vec![[0.5, 2.5]];
        assert_eq!(intersect(&a, &b), vec![[0.5, 1.0], [2.0, 2.5]]);
        assert_eq!(clip(&a, 0.5, 2.5), vec![[0.5, 1.0], [2.0, 2.5]]);
    }
}

#[cfg(test)]
mod unit_tests {
    use serde_json::{Value, json};

    use crate::kinds::Job;
    use crate::kinds::key::cache_key;

    fn query(observations: Value, axes: Value) -> Result<Job, crate::jobs::spec::SpecError> {
        let mut spec = json!({"kind": "forensic", "pulse": {"type": "one_sine"},
                              "observations": observations});
        for (k, v) in axes.as_object().expect("object") {
            spec[k] = v.clone();
        }
        Job::from_value(&spec)
    }

    fn twins() -> Value {
        json!([{"name": "a", "overturned": true, "block": {"alpha": 0.25, "p": 2.0}},
               {"name": "b", "overturned": false, "block": {"alpha": 0.3, "p": 2.0}}])
    }

    #[test]
    fn frequencies_and_amplitudes_in_any_unit_make_the_same_query() {
        let tau = std::f64::consts::TAU;
        let key = |axes: Value| cache_key(&query(twins(), axes).expect("valid"));
        let reference = key(json!({"frequency_hz": [1.0 / tau, 2.0 / tau],
                                   "a_p_g": {"from": 0.1, "to": 1.5}}));
        assert_eq!(
            key(json!({"omega_p": [1.0, 2.0], "a_p": {"from": 0.981, "to": 14.715}})),
            reference
        );
        // Both blocks have p = 2 rad/s: ω_p/p = 0.5 and 1 are 1 and 2 rad/s.
        assert_eq!(
            key(json!({"omega_ratio": [0.5, 1.0], "a_p_g": {"from": 0.1, "to": 1.5}})),
            reference
        );
    }

    #[test]
    fn on_a_floor_slicker_than_tan_alpha_no_pulse_overturns_a_block() {
        // μ = 0.2 < tan 0.25: the block slides and never rocks, so a block
        // seen overturned is consistent with no pulse, and one seen
        // standing with all of them; μ = 10 answers as pure rocking.
        let obs = |overturned: bool| json!([{"name": "a", "overturned": overturned, "block": {"alpha": 0.25, "p": 2.14}}]);
        let axes = |contact: Value| {
            json!({"frequency_hz": [0.5, 1.0], "a_p_g": {"from": 0.1, "to": 1.0},
                   "tolerance_g": 1e-3, "scan_step_g": 0.01, "contact": contact})
        };
        let run = |overturned: bool, contact: Value| {
            query(obs(overturned), axes(contact))
                .expect("valid")
                .run(&crate::spectrum::Control::new())
                .expect("runs")
        };
        let slick = json!({"model": "coulomb", "mu": 0.2});
        let down = run(true, slick.clone());
        let up = run(false, slick);
        for k in 0..2 {
            assert_eq!(down["frequencies"][k]["consistent_g"], json!([]), "{down}");
            assert_eq!(
                up["frequencies"][k]["consistent_g"],
                json!([[0.1, 1.0]]),
                "{up}"
            );
        }
        let pure = run(true, json!({"model": "no_sliding"}));
        let rough = run(true, json!({"model": "coulomb", "mu": 10.0}));
        assert_eq!(pure["frequencies"], rough["frequencies"]);
        assert!(
            !pure["frequencies"][1]["consistent_g"]
                .as_array()
                .expect("list")
                .is_empty()
        );
    }

    /// |residual slide|, m, of the locomotive's time history on `contact`
    /// under a one-sine pulse of `a_g` g at `f` Hz; `None` when it overturns.
    fn slid(contact: &Value, f: f64, a_g: f64) -> Option<f64> {
        let doc = json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "a_p_g": a_g, "omega_p": std::f64::consts::TAU * f},
            "contact": contact});
        let r = Job::from_value(&doc)
            .expect("valid")
            .run(&crate::spectrum::Control::new())
            .expect("runs");
        assert_ne!(r["lift_off"], json!(true), "{r}");
        (!r["overturned"].as_bool().expect("bool"))
            .then(|| r["residual_slide_m"].as_f64().expect("m").abs())
    }

    #[test]
    fn a_seen_slide_is_consistent_exactly_where_the_time_history_slides_that_far() {
        // The locomotive on μ = 0.2 only slides; on μ = 0.3 it slide-rocks
        // and overturns above some amplitude. At the middle of every
        // consistent interval and of every gap the time history's residual
        // slide is inside / outside [lo, hi] (or the block overturned); at
        // each end found, one tolerance either side differs.
        let tol = 1e-3;
        for (mu, band, from, to) in [(0.2, [0.02, 0.3], 0.1, 1.2), (0.3, [0.0, 0.05], 0.1, 1.2)] {
            let contact = json!({"model": "coulomb", "mu": mu});
            let obs = json!([{"name": "loco", "overturned": false, "slid_m": band,
                              "block": {"alpha": 0.25, "p": 2.14}}]);
            let frequencies = [0.5, 1.0];
            let r = query(
                obs,
                json!({"frequency_hz": frequencies, "a_p_g": {"from": from, "to": to},
                       "tolerance_g": tol, "scan_step_g": 0.02, "contact": contact}),
            )
            .expect("valid")
            .run(&crate::spectrum::Control::new())
            .expect("runs");
            let inside = |s: Option<f64>| s.is_some_and(|s| band[0] <= s && s <= band[1]);
            let mut edges = 0;
            for (k, &f) in frequencies.iter().enumerate() {
                let set: Vec<[f64; 2]> =
                    serde_json::from_value(r["frequencies"][k]["consistent_g"].clone())
                        .expect("intervals");
                assert!(!set.is_empty(), "μ {mu}, {f} Hz: {r}");
                let mut lo = from;
                for &[a, b] in &set {
                    if a > lo {
                        let gap = slid(&contact, f, 0.5 * (lo + a));
                        assert!(
                            !inside(gap),
                            "μ {mu}, {f} Hz: gap at {}: {gap:?}",
                            0.5 * (lo + a)
                        );
                    }
                    let mid = slid(&contact, f, 0.5 * (a + b));
                    assert!(inside(mid), "μ {mu}, {f} Hz: {a}..{b}: {mid:?}");
                    for (edge, opens) in [(a, true), (b, false)] {
                        if edge > from && edge < to {
                            let below = inside(slid(&contact, f, edge - tol));
                            let above = inside(slid(&contact, f, edge + tol));
                            assert_eq!(
                                (below, above),
                                (!opens, opens),
                                "μ {mu}, {f} Hz: edge {edge}"
                            );
                            edges += 1;
                        }
                    }
                    lo = b;
                }
                if to > lo {
                    let gap = slid(&contact, f, 0.5 * (lo + to));
                    assert!(!inside(gap), "μ {mu}, {f} Hz: gap above {lo}: {gap:?}");
                }
            }
            assert!(edges >= 2, "μ {mu}: {edges} edges in {r}");
        }
    }

    #[test]
    fn a_seen_slide_needs_a_coulomb_floor_a_standing_block_and_a_size_range() {
        let refused = |slid: Value, overturned: bool, contact: Option<Value>| {
            let obs = json!([{"name": "a", "overturned": overturned, "slid_m": slid,
                              "block": {"alpha": 0.25, "p": 2.14}}]);
            let mut axes = json!({"frequency_hz": [1.0], "a_p_g": {"from": 0.1, "to": 1.0}});
            if let Some(c) = contact {
                axes["contact"] = c;
            }
            let e = query(obs, axes).expect_err("refused");
            assert_eq!(e.pointer, "/observations/0/slid_m", "{}", e.message);
            e.message
        };
        let coulomb = Some(json!({"model": "coulomb", "mu": 0.3}));
        assert!(refused(json!([0.0, 0.1]), false, None).contains("coulomb"));
        assert!(refused(json!([0.0, 0.1]), true, coulomb.clone()).contains("stands"));
        for bad in [
            json!([0.2, 0.1]),
            json!([-0.1, 0.1]),
            json!([0.1]),
            json!([0.0, 1e9]),
        ] {
            assert!(refused(bad, false, coulomb.clone()).contains("lo"));
        }
    }

    #[test]
    fn omega_ratio_across_blocks_of_different_size_is_refused_with_the_reason() {
        let mixed = json!([{"name": "a", "overturned": true, "block": {"alpha": 0.25, "p": 2.0}},
                           {"name": "b", "overturned": false, "block": {"alpha": 0.3, "p": 1.5}}]);
        let e = query(
            mixed,
            json!({"omega_ratio": [1.0], "a_p_g": {"from": 0.1, "to": 1.0}}),
        )
        .expect_err("ambiguous");
        assert_eq!(e.pointer, "/omega_ratio");
        assert!(e.message.contains("same p"), "{}", e.message);
        let e = query(
            twins(),
            json!({"frequency_hz": [0.5], "omega_p": [3.0],
                                      "a_p_g": {"from": 0.1, "to": 1.0}}),
        )
        .expect_err("twice");
        assert_eq!(e.pointer, "/omega_p");
    }
}
