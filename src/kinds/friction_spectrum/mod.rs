//! The `friction_spectrum` job: the friction pure rocking needs (paper Fig. 9).

pub mod figure;
pub mod table;

use serde::{Deserialize, Serialize};

use super::spectrum::{PulseFamily, SpectrumNumerics, validate_family};
use crate::dynamics::{Formulation, SimError};
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, OMEGA_RATIO_RANGE, PulseSpec, SolverNorm, SolverSpec, SpecError,
    in_one_unit, parse_formulation,
};
use crate::spectrum::Control;
use crate::spectrum::friction::{FrictionRequest, friction_spectrum};
use crate::spectrum::scan::ScanError;

/// Most amplitudes in one friction spectrum.
pub const MAX_AMPLITUDES: usize = 100_000;

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = FrictionSpectrumSpec)]
pub struct FrictionSpec {
    /// "friction_spectrum".
    #[schema(value_type = crate::jobs::names::tag::FrictionSpectrum)]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse family (`type`, `n`).
    #[schema(required = true, value_type = crate::jobs::schema::PulseFamilyInput)]
    pub pulse: Option<PulseSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// ω_p/p (one value, 1e-3 to 1e4; or give `omega_p` or `frequency_hz`).
    #[schema(minimum = 1e-3, maximum = 1e4)]
    pub omega_ratio: Option<f64>,
    /// ω_p, rad/s.
    #[schema(exclusive_minimum = 0.0)]
    pub omega_p: Option<f64>,
    /// f_p = ω_p/2π, Hz.
    #[schema(exclusive_minimum = 0.0)]
    pub frequency_hz: Option<f64>,
    /// Amplitudes a_p/(αg) (or give `a_p` or `a_p_g`).
    pub a_alpha_g: Option<RangeSpec>,
    /// Amplitudes, m/s².
    pub a_p: Option<RangeSpec>,
    /// Amplitudes, g.
    pub a_p_g: Option<RangeSpec>,
    /// Solver.
    pub solver: Option<SolverSpec>,
    /// The vertical ground acceleration (positive up), scaled with each
    /// pulse: `{"ratio": r}` (ü_v = r·ü_g), or a pulse of its own (`type`,
    /// `amplitude_ratio` a_v/a_p, `frequency_ratio` ω_v/ω_p or an absolute
    /// `omega_p`/`frequency_hz`, optional `delay_s`).
    pub vertical: Option<crate::jobs::vertical::VerticalPulseSpec>,
}

/// A validated friction-spectrum job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[schema(as = FrictionSpectrumJob)]
pub struct FrictionJob {
    /// "friction_spectrum".
    pub kind: tag::FrictionSpectrum,
    /// Block.
    pub block: BlockNorm,
    /// Pulse family.
    pub pulse: PulseFamily,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Amplitudes, αg.
    pub a_alpha_g: Vec<f64>,
    /// Solver.
    pub solver: SolverNorm,
    /// The vertical motion (positive up), when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<crate::jobs::vertical::VerticalPulseNorm>,
}

impl crate::jobs::kind::Validate for FrictionSpec {
    type Job = FrictionJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<FrictionJob, SpecError> {
        let block = crate::jobs::spec::the_block(self.block.as_ref())?;
        let pulse = validate_family(self.pulse.as_ref(), "/pulse")?;
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
        // The frequency and the amplitudes in any unit, normalised to ω_p/p and αg.
        let p = block.p;
        let unit_g = block.alpha * block.g;
        let (value, name, to_ratio) = in_one_unit(
            &[
                (self.omega_ratio, "omega_ratio", 1.0),
                (self.omega_p, "omega_p", 1.0 / p),
                (self.frequency_hz, "frequency_hz", std::f64::consts::TAU / p),
            ],
            "frequency",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/omega_ratio",
                "missing field: one frequency as omega_ratio (ω_p/p), omega_p (rad/s) or frequency_hz",
            )
        })?;
        let omega_ratio = value * to_ratio;
        if !(omega_ratio.is_finite()
            && (OMEGA_RATIO_RANGE.0..=OMEGA_RATIO_RANGE.1).contains(&omega_ratio))
        {
            return Err(SpecError::at(
                format!("/{name}"),
                format!(
                    "must give ω_p/p in [{}, {}] for this block (p = {p} rad/s; got ω_p/p = {omega_ratio})",
                    OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
                ),
            ));
        }
        let (range, name, to_alpha_g) = in_one_unit(
            &[
                (self.a_alpha_g.as_ref(), "a_alpha_g", 1.0),
                (self.a_p.as_ref(), "a_p", 1.0 / unit_g),
                (self.a_p_g.as_ref(), "a_p_g", block.g / unit_g),
            ],
            "amplitude axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/a_alpha_g",
                "missing field: the amplitudes as a_alpha_g (αg), a_p (m/s²) or a_p_g: {\"from\", \"to\", \"steps\"} or a list",
            )
        })?;
        let pointer = format!("/{name}");
        let a_alpha_g: Vec<f64> = range
            .values(&pointer, 0.0, f64::MAX, MAX_AMPLITUDES)?
            .into_iter()
            .map(|a| a * to_alpha_g)
            .collect();
        if let Some(bad) = a_alpha_g.iter().find(|a| !(1e-6..=1e6).contains(*a)) {
            return Err(SpecError::at(
                pointer,
                format!("every amplitude must give a_p/(αg) in [1e-6, 1e6]; one gives {bad}"),
            ));
        }
        Ok(FrictionJob {
            kind: tag::FrictionSpectrum,
            block,
            pulse,
            formulation,
            omega_ratio,
            a_alpha_g,
            solver,
            vertical,
        })
    }
}

/// One amplitude of a friction spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FrictionPointDoc {
    /// a_p/(αg).
    pub a_alpha_g: f64,
    /// a_p, g.
    #[serde(default)]
    #[schema(required = true)]
    pub a_p_g: f64,
    /// max |f_x/f_z| over the rocking history: the minimum μ for pure rocking;
    /// null when the block lifts off (`lift_off`): the demand is unbounded.
    #[schema(required = true)]
    pub peak_friction_demand: Option<f64>,
    /// The same over tan α (the axis of Fig. 9); null with it.
    #[schema(required = true)]
    pub peak_over_tan_alpha: Option<f64>,
    /// f_x/f_z when rocking starts (eq. 7; eq. 51 for one-cosine).
    #[schema(required = true)]
    pub initiation_friction_demand: Option<f64>,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Overturning mode.
    #[schema(required = true)]
    pub mode: Option<u8>,
    /// Whether f_z reached 0: the block would lift off, no μ sustains pure
    /// rocking.
    #[serde(default)]
    #[schema(required = true)]
    pub lift_off: bool,
    /// First time f_z ≤ 0, s.
    #[schema(required = true)]
    pub lift_off_time: Option<f64>,
    /// The demand was followed up to this time (the pulse end) only: the block
    /// was then bound to overturn, and its fall is not counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_demand_followed_until: Option<f64>,
}

/// The result document of a friction-spectrum job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[schema(as = FrictionSpectrumResult)]
pub struct FrictionResult {
    /// "friction_spectrum".
    pub kind: tag::FrictionSpectrum,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// ω_p, rad/s.
    pub omega_p: f64,
    /// f_p, Hz.
    pub frequency_hz: f64,
    /// One entry per amplitude.
    pub points: Vec<FrictionPointDoc>,
    /// Cost and accuracy.
    pub numerics: SpectrumNumerics,
    /// The normalised spec.
    pub spec: FrictionJob,
    /// Notes on the inputs (`implausible_size`: a block smaller than 1 cm or
    /// larger than 100 m); absent when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(FrictionResult);

impl FrictionJob {
    /// Runs the job under `control`.
    pub fn run(&self, control: &Control) -> Result<FrictionResult, ScanError> {
        let block = self.block.block().map_err(SimError::from)?;
        let req = FrictionRequest {
            block,
            shape: self.pulse.shape(),
            formulation: self.formulation,
            solver: self.solver.solver(),
            omega_ratio: self.omega_ratio,
            levels: self.a_alpha_g.clone(),
            vertical: crate::jobs::vertical::ScaledVertical::of(self.vertical.as_ref(), None)
                .and_then(|v| v.of_pulses()),
        };
        let s = friction_spectrum(&req, control)?;
        let tan = block.slenderness().tan();
        Ok(FrictionResult {
            warnings: Vec::new(),
            kind: tag::FrictionSpectrum,
            omega_ratio: self.omega_ratio,
            omega_p: self.omega_ratio * self.block.p,
            frequency_hz: self.omega_ratio * self.block.p / std::f64::consts::TAU,
            points: s
                .points
                .iter()
                .map(|p| FrictionPointDoc {
                    a_alpha_g: p.level,
                    a_p_g: p.level * block.slenderness(),
                    peak_friction_demand: p.peak_demand,
                    peak_over_tan_alpha: p.peak_demand.map(|d| d / tan),
                    initiation_friction_demand: p.initiation_demand,
                    overturned: p.overturned,
                    mode: p.mode,
                    lift_off: p.lift_off.is_some(),
                    lift_off_time: p.lift_off,
                    friction_demand_followed_until: p.followed_until,
                })
                .collect(),
            numerics: SpectrumNumerics::new(&self.solver, &s.stats, 0.0, 0.0, s.wall_time),
            spec: self.clone(),
            engine: None,
        })
    }
}

/// The `friction_spectrum` kind: the friction pure rocking needs, over a
/// pulse's amplitudes.
pub struct FrictionSpectrum;

/// A friction simulation costs this many of an overturning scan's: it
/// follows the reactions through the whole response (measured: about
/// 350 µs of CPU for a one-sine, whose scan simulation the cost table puts
/// at 60 µs).
const FRICTION_COST: f64 = 6.0;

impl crate::kinds::kind::Kind for FrictionSpectrum {
    const NAME: &'static str = crate::jobs::names::tag::FrictionSpectrum::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Friction spectrum";
    type Spec = FrictionSpec;
    type Job = FrictionJob;
    type Result = FrictionResult;
    type Part = crate::jobs::kind::NoPart;

    fn run(
        job: &FrictionJob,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        Ok(crate::kinds::kind::Output::Whole(job.run(control)?))
    }
    fn table(
        result: &FrictionResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &FrictionResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    fn size(job: &FrictionJob) -> crate::jobs::kind::Size {
        let n = job.a_alpha_g.len() as f64;
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: job.a_alpha_g.len(),
            work: n,
            record_work: 0.0,
            cpu_s: n
                * FRICTION_COST
                * crate::jobs::cost::pulse_simulation_s(
                    &job.pulse.shape(),
                    job.formulation,
                    job.solver.method,
                ),
            lanes: n,
        }
    }

    fn grid_field(_job: &FrictionJob) -> &'static str {
        "/a_alpha_g"
    }

    fn warnings(job: &FrictionJob) -> Vec<crate::jobs::warning::WarningDoc> {
        crate::jobs::plausible::size_warning(&job.block, "/block")
            .into_iter()
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use serde_json::{Value, json};

    use crate::kinds::Job;
    use crate::spectrum::Control;

    fn run(spec: Value) -> Value {
        let job = Job::from_value(&spec).expect("valid spec");
        job.run(&Control::new()).expect("runs")
    }

    /// Eq. 51 (λ = 1), written out as printed.
    fn eq51(alpha: f64, level: f64) -> f64 {
        let (g, t, s, c) = (9.81, alpha.tan(), alpha.sin(), alpha.cos());
        let a_p = level * alpha * g;
        let x = a_p / (g * t) - 1.0;
        t * (a_p / (g * s) - 0.75 * c * x) / (t / s + 0.75 * t * s * x)
    }

    #[test]
    fn one_cosine_spectrum_is_eq_51_and_reaches_two_alpha_at_six_alpha_g() {
        // Fig. 9 (bottom): α = 0.25, ω_p/p = 4; 0.5096 ≈ 2α at 6 αg.
        let doc = run(json!({"kind": "friction_spectrum",
            "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
            "pulse": {"type": "one_cosine"}, "omega_ratio": 4.0,
            "a_alpha_g": [2.0, 4.0, 6.0]}));
        for p in doc["points"].as_array().expect("points") {
            let level = p["a_alpha_g"].as_f64().expect("level");
            let peak = p["peak_friction_demand"].as_f64().expect("bounded");
            assert!((peak / eq51(0.25, level) - 1.0).abs() < 5e-3, "{p}");
            assert!(peak < 0.7 * level * 0.25, "at-rest a_p/g counted: {p}");
            assert_eq!(p["lift_off"], json!(false));
        }
        let six = &doc["points"][2];
        let peak = six["peak_friction_demand"].as_f64().expect("bounded");
        assert!((peak - 0.5096).abs() <= 0.005 * 0.5096, "{six}");
        let over_tan = six["peak_over_tan_alpha"].as_f64().expect("bounded");
        assert!((over_tan - peak / 0.25f64.tan()).abs() < 1e-12);
    }

    #[test]
    fn the_frequency_and_amplitudes_in_any_unit_make_the_same_job() {
        let base = |axes: Value| {
            let mut spec = json!({"kind": "friction_spectrum",
                "block": {"alpha": 0.25, "p": 2.0, "eta": 0.9}, "pulse": {"type": "one_sine"}});
            for (k, v) in axes.as_object().expect("object") {
                spec[k] = v.clone();
            }
            Job::from_value(&spec)
        };
        let key = |axes: Value| crate::kinds::key::cache_key(&base(axes).expect("valid"));
        let reference = key(json!({"omega_ratio": 3.0, "a_alpha_g": [2.0, 4.0]}));
        let tau = std::f64::consts::TAU;
        assert_eq!(key(json!({"omega_p": 6.0, "a_p_g": [0.5, 1.0]})), reference);
        assert_eq!(
            key(json!({"frequency_hz": 6.0 / tau, "a_p": [0.5 * 9.81, 9.81]})),
            reference
        );
        let e = base(json!({"omega_ratio": 3.0, "omega_p": 6.0, "a_alpha_g": [2.0]}))
            .expect_err("twice");
        assert_eq!(e.pointer, "/omega_p");
        let e = base(json!({"omega_ratio": 3.0, "a_p_g": [-1.0]})).expect_err("negative");
        assert!(e.pointer.starts_with("/a_p_g"), "{}", e.pointer);
        let doc = base(json!({"omega_p": 6.0, "a_p_g": [0.5]}))
            .expect("valid")
            .run(&Control::new())
            .expect("runs");
        assert!((doc["omega_p"].as_f64().expect("omega_p") - 6.0).abs() < 1e-12);
        assert!((doc["points"][0]["a_p_g"].as_f64().expect("a_p_g") - 0.5).abs() < 1e-12);
        assert!((doc["points"][0]["a_alpha_g"].as_f64().expect("αg") - 2.0).abs() < 1e-12);
    }
}
