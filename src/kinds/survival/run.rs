//! How a survival job is computed.

use super::result::{
    AgeDistributionResult, AgeResult, JointResult, RockResult, SurvivalNumerics, SurvivalResult,
};
use super::spec::{AgeNorm, SurvivalJob, TARGET};
use crate::jobs::names::tag;
use crate::probability::hazard::HazardCurve;
use crate::probability::survival::{Age, rate_scale};
impl SurvivalJob {
    /// Computes the rates and probabilities.
    pub fn run(&self) -> SurvivalResult {
        let started = std::time::Instant::now();
        // Validated: the curve is one.
        let curve = HazardCurve::new(&self.hazard.points);
        let mut joint_rocks = Vec::new();
        let rocks: Vec<RockResult> = self
            .rocks
            .iter()
            .map(|r| {
                let t = curve
                    .as_ref()
                    .map(|c| c.toppling_rate(r.fragility.median, r.fragility.beta))
                    .unwrap_or(crate::probability::hazard::TopplingRate {
                        rate: 0.0,
                        extrapolated_share: 0.0,
                    });
                let (ages, distribution) = match &r.age_years {
                    AgeNorm::Known(list) => {
                        let ages = list
                            .iter()
                            .map(|&years| {
                                let age = Age::Known(years);
                                AgeResult {
                                    age_years: years,
                                    survival_probability: age.survival(t.rate),
                                    rate_scale_at_5_percent: rate_scale(&[(t.rate, age)], TARGET),
                                }
                            })
                            .collect();
                        if let [years] = list[..] {
                            joint_rocks.push((t.rate, Age::Known(years)));
                        }
                        (ages, None)
                    }
                    AgeNorm::Uncertain(d) => {
                        let dist = d.distribution();
                        let age = Age::Uncertain(dist);
                        joint_rocks.push((t.rate, age));
                        (
                            Vec::new(),
                            Some(AgeDistributionResult {
                                median_age_years: dist.median(),
                                survival_probability: age.survival(t.rate),
                                rate_scale_at_5_percent: rate_scale(&[(t.rate, age)], TARGET),
                            }),
                        )
                    }
                };
                RockResult {
                    name: r.name.clone(),
                    fragility: r.fragility,
                    annual_toppling_rate: t.rate,
                    mean_years_between_topplings: Some(1.0 / t.rate).filter(|y| y.is_finite()),
                    extrapolated_share: t.extrapolated_share,
                    ages,
                    age_distribution: distribution,
                }
            })
            .collect();
        let single = (rocks.len() == 1).then(|| rocks[0].clone());
        let joint = (rocks.len() > 1).then(|| JointResult {
            survival_probability: joint_rocks.iter().map(|(l, a)| a.survival(*l)).product(),
            rate_scale_at_5_percent: rate_scale(&joint_rocks, TARGET),
        });
        SurvivalResult {
            kind: tag::Survival,
            im: self.hazard.im,
            annual_toppling_rate: single.as_ref().map(|r| r.annual_toppling_rate),
            ages: single
                .as_ref()
                .filter(|r| r.age_distribution.is_none())
                .map(|r| r.ages.clone()),
            age_distribution: single.and_then(|r| r.age_distribution),
            rocks,
            joint,
            numerics: SurvivalNumerics {
                method:
                    "closed form: λ_t = E[λ(X)], X lognormal, on the log-log interpolated curve"
                        .into(),
                wall_time_s: started.elapsed().as_secs_f64(),
            },
            spec: self.clone(),
            warnings: Vec::new(),
            engine: None,
        }
    }
}
