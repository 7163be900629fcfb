//! A survival result's table: a row per rock and age (an uncertain age: its
//! median, marked), then the joint probability of several rocks (rock
//! `all`); a rock's fragility and rates are on each of its rows.

use serde::Serialize;

use crate::jobs::names::Im;
use crate::kinds::survival::{RockResult, SurvivalResult};
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Named, Table, TableError};

/// A row per rock and age, then the joint row.
pub fn rows(r: &SurvivalResult, table: &mut Table) -> Result<(), TableError> {
    // The fragility's median, its column named after the intensity measure.
    let median = |value| Named {
        name: median_column(r.im),
        value,
    };
    for rock in &r.rocks {
        let known = rock.ages.iter().map(|a| Age {
            age_years: Some(Number(a.age_years)),
            age_uncertain: Some(false),
            survival_probability: Number(a.survival_probability),
            rate_scale_at_5_percent: a.rate_scale_at_5_percent.map(Number),
        });
        let uncertain = rock.age_distribution.iter().map(|d| Age {
            age_years: Some(Number(d.median_age_years)),
            age_uncertain: Some(true),
            survival_probability: Number(d.survival_probability),
            rate_scale_at_5_percent: d.rate_scale_at_5_percent.map(Number),
        });
        for age in known.chain(uncertain) {
            let fragility = Some(Number(rock.fragility.median));
            table.row((Head::of(rock), age, median(fragility), Rates::of(rock)))?;
        }
    }
    if let Some(j) = &r.joint {
        let all = Head {
            rock: Text("all"),
            annual_toppling_rate_per_yr: None,
        };
        let age = Age {
            age_years: None,
            age_uncertain: None,
            survival_probability: Number(j.survival_probability),
            rate_scale_at_5_percent: j.rate_scale_at_5_percent.map(Number),
        };
        table.row((all, age, median(None), Rates::default()))?;
    }
    Ok(())
}

/// The header of the fragility's median for intensity measure `im`:
/// `fragility_median_` and the measure's name.
fn median_column(im: Im) -> &'static str {
    match im {
        Im::PgaG => "fragility_median_pga_g",
        Im::PgvMS => "fragility_median_pgv_m_s",
    }
}

/// The rock a row is of.
#[derive(Serialize)]
struct Head<'a> {
    /// Its name; `all` for the rocks together.
    rock: Text<&'a str>,
    /// λ_t, topplings per year.
    annual_toppling_rate_per_yr: Option<Number>,
}

impl<'a> Head<'a> {
    fn of(rock: &'a RockResult) -> Head<'a> {
        Head {
            rock: Text(&rock.name),
            annual_toppling_rate_per_yr: Some(Number(rock.annual_toppling_rate)),
        }
    }
}

/// An age of the rock (or the rocks together), and its chances.
#[derive(Serialize)]
struct Age {
    /// The age, years (an uncertain age's median).
    age_years: Option<Number>,
    /// Whether the age is uncertain.
    age_uncertain: Option<bool>,
    /// P(still standing).
    survival_probability: Number,
    /// The factor on every hazard rate that brings it to 5 % (empty: it
    /// never topples).
    rate_scale_at_5_percent: Option<Number>,
}

/// The rock's fragility spread and rates (after its median).
#[derive(Default, Serialize)]
struct Rates {
    /// The fragility's log-standard deviation β.
    fragility_beta: Option<Number>,
    /// 1/λ_t, years (empty when it cannot topple).
    mean_years_between_topplings: Option<Number>,
    /// The share of λ_t from intensities beyond the tabulated hazard curve.
    extrapolated_share: Option<Number>,
}

impl Rates {
    fn of(rock: &RockResult) -> Rates {
        Rates {
            fragility_beta: Some(Number(rock.fragility.beta)),
            mean_years_between_topplings: rock.mean_years_between_topplings.map(Number),
            extrapolated_share: Some(Number(rock.extrapolated_share)),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{SURVIVAL, cell, csv_of, lines};
    use crate::kinds::JobResult;
    use crate::kinds::survival::{AgeDistributionResult, AgeResult, JointResult};
    use crate::plot::tests::typed;

    #[test]
    fn survival_rows_per_rock_and_age_then_the_joint() {
        let JobResult::Survival(mut r) = typed(SURVIVAL) else {
            panic!("a survival")
        };
        let csv = csv_of(&JobResult::Survival(r.clone()));
        let rock = &r.rocks[0];
        let age = &rock.ages[0];
        assert_eq!(
            lines(&csv),
            vec![
                "rock,annual_toppling_rate_per_yr,age_years,age_uncertain,survival_probability,rate_scale_at_5_percent,\
                 fragility_median_pga_g,fragility_beta,mean_years_between_topplings,extrapolated_share".to_string(),
                format!(
                    "{},{},1000.0,false,{},{},0.4,0.4,{},{}",
                    rock.name,
                    cell(&rock.annual_toppling_rate),
                    cell(&age.survival_probability),
                    cell(&age.rate_scale_at_5_percent.expect("it can topple")),
                    cell(&rock.mean_years_between_topplings.expect("it can topple")),
                    cell(&rock.extrapolated_share),
                ),
            ]
        );
        let mut grass = rock.clone();
        (grass.name, grass.annual_toppling_rate) = ("Grass Valley".into(), 1.5e-4);
        (grass.fragility.median, grass.fragility.beta) = (0.3, 0.5);
        grass.mean_years_between_topplings = Some(6666.7);
        grass.extrapolated_share = 0.01;
        grass.ages = vec![AgeResult {
            age_years: 1000.0,
            survival_probability: 0.86,
            rate_scale_at_5_percent: Some(20.0),
        }];
        grass.age_distribution = None;
        let mut b = rock.clone();
        (b.name, b.annual_toppling_rate, b.ages) = ("b".into(), 1e-4, vec![]);
        (b.fragility.median, b.fragility.beta) = (5.0, 0.0);
        (b.mean_years_between_topplings, b.extrapolated_share) = (None, 0.0);
        b.age_distribution = Some(AgeDistributionResult {
            median_age_years: 9000.0,
            survival_probability: 0.4,
            rate_scale_at_5_percent: None,
        });
        r.rocks = vec![grass, b];
        r.joint = Some(JointResult {
            survival_probability: 0.344,
            rate_scale_at_5_percent: Some(2.5),
        });
        let csv = csv_of(&JobResult::Survival(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "Grass Valley,0.00015,1000.0,false,0.86,20.0,0.3,0.5,6666.7,0.01",
                "b,0.0001,9000.0,true,0.4,,5.0,0.0,,0.0",
                "all,,,,0.344,2.5,,,,",
            ]
        );
    }
}
