//! The `survival` job: the probability that a rock of known (or uncertain)
//! age still stands under a hazard model. With a lognormal fragility (median
//! θ, dispersion β) and a tabulated hazard curve λ(x), the annual toppling
//! rate is λ_t = ∫ P(topple | x) |dλ(x)| in closed form
//! ([`HazardCurve::toppling_rate`]); topplings are a Poisson process, so a
//! rock of age T stands with P_s = exp(−λ_t T) ([`Age::survival`]).

pub mod figure;
pub mod table;

mod result;
mod run;
mod spec;
pub use result::*;
pub use spec::*;

/// The `survival` kind: the probability that rocks of known age still
/// stand under a hazard model (closed forms).
pub struct Survival;

impl crate::kinds::kind::Kind for Survival {
    const NAME: &'static str = crate::jobs::names::tag::Survival::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Survival";
    type Spec = SurvivalSpec;
    type Job = SurvivalJob;
    type Result = SurvivalResult;
    type Part = crate::jobs::kind::NoPart;
    type Range = crate::jobs::kind::NoPart;

    fn run(
        job: &SurvivalJob,
        _part: Option<crate::jobs::kind::NoPart>,
        control: &crate::spectrum::Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        crate::kinds::kind::run_one::<Self>(control, || Ok(job.run()))
    }

    fn table(
        result: &SurvivalResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &SurvivalResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    /// Closed forms and a quadrature: under a millisecond.
    fn size(
        _job: &SurvivalJob,
        _part: Option<crate::jobs::kind::NoPart>,
    ) -> crate::jobs::kind::Size {
        crate::jobs::kind::Size::one(1e-4)
    }

    fn grid_field(_job: &SurvivalJob) -> &'static str {
        "/omega_ratio"
    }
}
