//! A forensic job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::dynamics::Formulation;
use crate::jobs::names::tag;
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, OMEGA_RATIO_RANGE, PulseSpec,
    SolverNorm, SolverSpec, SpecError, at_most_one, in_one_unit, parse_formulation, validate_block,
};
use crate::kinds::record_spectrum::{ScaleRangeSpec, pga};
use crate::kinds::spectrum::{PulseFamily, validate_family};
use serde::{Deserialize, Serialize};
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
}

pub(super) fn in_range(
    v: f64,
    lo: f64,
    hi: f64,
    pointer: &str,
    what: &str,
) -> Result<f64, SpecError> {
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
pub(super) fn check_omega_ratios(
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
pub(super) fn first_given_refused(fields: &[(bool, &str)], message: &str) -> Result<(), SpecError> {
    match fields.iter().find(|(given, _)| *given) {
        Some((_, name)) => Err(SpecError::at(format!("/{name}"), message)),
        None => Ok(()),
    }
}

/// The gravity every block shares, if they do.
pub(super) fn common_g(observations: &[Observation]) -> Option<f64> {
    let g = observations.first()?.block.g;
    observations.iter().all(|o| o.block.g == g).then_some(g)
}

/// A value given in g or in scale units (at most one): `(value, pointer, g per unit)`.
pub(super) type InUnit = (Option<f64>, &'static str, f64);

pub(super) fn at_most_one_unit(in_g: InUnit, in_scale: InUnit) -> Result<InUnit, SpecError> {
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
pub(super) fn amplitude_grid(
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
    if to / scan_step_g > crate::kinds::spectrum::MAX_SCAN_POINTS {
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
pub(super) fn slide_band(s: &[f64], overturned: bool, at: &str) -> Result<[f64; 2], SpecError> {
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
