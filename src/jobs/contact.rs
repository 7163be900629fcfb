//! The contact between block and floor (`"contact"`): pure rocking
//! (`"no_sliding"`, the default: the pivot never slips, and `block.mu` only
//! warns where the friction it needs exceeds μ), or Coulomb friction
//! (`"coulomb"`, μ and optionally μ_k ≤ μ): the block sticks, slides, rocks,
//! slide-rocks or leaves the floor ([`crate::dynamics::coulomb`]).
//!
//! Under `coulomb` a history is first run as pure rocking, following the
//! friction it needs: where that never exceeds μ (eq. 7 at every start of
//! rocking included), never lifts the block off, and μ ≥ tan α (a block with
//! less slides before it could rock), pure rocking *is* the Coulomb answer,
//! to the bit. Otherwise the mode driver answers.

use serde::{Deserialize, Serialize};

use super::spec::SpecError;
use crate::dynamics::Formulation;
pub use crate::dynamics::floor::{AnsweredBy, CoulombHistory, run_coulomb};
use crate::dynamics::sliding::Friction;

/// The contact model as users write it.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// "no_sliding" (default: pure rocking) | "coulomb".
    #[schema(value_type = Option<ContactModelName>)]
    pub model: Option<String>,
    /// Coulomb only: the static friction coefficient μ (> 0).
    #[schema(exclusive_minimum = 0.0, maximum = 100.0)]
    pub mu: Option<f64>,
    /// Coulomb only: the kinetic coefficient, 0 < μ_k ≤ μ (default μ).
    #[schema(exclusive_minimum = 0.0, maximum = 100.0)]
    pub mu_kinetic: Option<f64>,
}

/// The contact model's names.
#[derive(utoipa::ToSchema)]
#[schema(as = ContactModelName)]
#[allow(dead_code)]
pub enum ContactModelName {
    /// Pure rocking.
    #[schema(rename = "no_sliding")]
    NoSliding,
    /// Coulomb friction.
    #[schema(rename = "coulomb")]
    Coulomb,
}

/// Coulomb friction, validated (absent: pure rocking).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ContactNorm {
    /// "coulomb".
    pub model: String,
    /// μ.
    pub mu: f64,
    /// μ_k.
    pub mu_kinetic: f64,
}

impl ContactNorm {
    /// The friction law.
    pub fn friction(&self) -> Friction {
        Friction {
            static_coefficient: self.mu,
            kinetic_coefficient: self.mu_kinetic,
        }
    }
}

/// Largest friction coefficient accepted.
pub const MAX_MU: f64 = 100.0;

/// Validates `contact` at `base`; `None` for pure rocking. Coulomb friction
/// takes the nonlinear equations and a Runge–Kutta solver.
pub fn validate_contact(
    spec: Option<&ContactSpec>,
    formulation: Formulation,
    base: &str,
) -> Result<Option<ContactNorm>, SpecError> {
    let Some(spec) = spec else {
        return Ok(None);
    };
    let model = spec.model.as_deref().unwrap_or("no_sliding");
    match model {
        "no_sliding" => {
            if spec.mu.is_some() || spec.mu_kinetic.is_some() {
                let field = if spec.mu.is_some() {
                    "mu"
                } else {
                    "mu_kinetic"
                };
                return Err(SpecError::at(
                    format!("{base}/{field}"),
                    "goes with \"model\": \"coulomb\"; under pure rocking (no_sliding) block.mu sets the friction the sliding warning compares with",
                ));
            }
            Ok(None)
        }
        "coulomb" => {
            let Some(mu) = spec.mu else {
                return Err(SpecError::at(
                    format!("{base}/mu"),
                    "missing field: the coulomb model needs the friction coefficient mu",
                ));
            };
            if !(mu.is_finite() && mu > 0.0 && mu <= MAX_MU) {
                return Err(SpecError::at(
                    format!("{base}/mu"),
                    format!("must be > 0 and at most {MAX_MU}"),
                ));
            }
            let mu_kinetic = spec.mu_kinetic.unwrap_or(mu);
            if !(mu_kinetic.is_finite() && mu_kinetic > 0.0 && mu_kinetic <= mu) {
                return Err(SpecError::at(
                    format!("{base}/mu_kinetic"),
                    "must satisfy 0 < mu_kinetic <= mu",
                ));
            }
            if formulation != Formulation::Nonlinear {
                return Err(SpecError::at(
                    "/formulation",
                    "the coulomb contact model follows the nonlinear equations (a sliding pivot has no linearised form here): use \"nonlinear\" (the default)",
                ));
            }
            Ok(Some(ContactNorm {
                model: "coulomb".to_string(),
                mu,
                mu_kinetic,
            }))
        }
        _ => Err(SpecError::at(
            format!("{base}/model"),
            format!(
                "unknown contact model {model:?}: \"no_sliding\" (pure rocking, the default) or \"coulomb\""
            ),
        )),
    }
}

/// One stretch of a mode in a result.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ModeDoc {
    /// "stick" | "slide" | "rock" | "slide_rock" | "flight".
    pub mode: String,
    /// Start, s.
    pub from: f64,
    /// End, s.
    pub to: f64,
    /// Slide and slide-rock: the way the base slips relative to the ground
    /// (+1 towards +x, the way positive ü_g points; −1 the other way).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<f64>,
    /// The base's slip on the floor at the start and at the end, m.
    pub slide_from_m: f64,
    /// See `slide_from_m`.
    pub slide_to_m: f64,
}

/// A Coulomb history's own fields in a result.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ContactDoc {
    /// "coulomb".
    pub contact_model: String,
    /// "pure_rocking" when the friction pure rocking needs never exceeded μ
    /// (the answer is pure rocking's, to the bit), "modes" otherwise.
    pub answered_by: String,
    /// The mode the block first left rest in (null: it never moved).
    #[schema(required = true)]
    pub initial_mode: Option<String>,
    /// The modes in time order (stretches of one mode merged; rocking
    /// stretches across impacts).
    pub modes: Vec<ModeDoc>,
    /// max |slip| of the base on the floor, m.
    pub peak_slide_m: f64,
    /// The base's slip at the end, m (+ towards +x).
    pub residual_slide_m: f64,
    /// Time spent sliding or slide-rocking, s.
    pub time_sliding_s: f64,
    /// Times the block left the floor (each flight ends in a landing,
    /// counted among the impacts, or in overturning in the air).
    pub flights: u64,
    /// Time spent in the air, s.
    pub time_in_flight_s: f64,
    /// The slip and the mode at each time of the series, when one was asked for.
    #[serde(skip)]
    #[schema(ignore)]
    pub series: Option<(Vec<f64>, Vec<String>)>,
}

impl ContactDoc {
    /// The document of `h`.
    pub fn new(h: &CoulombHistory) -> Self {
        let c = &h.contact;
        ContactDoc {
            contact_model: "coulomb".to_string(),
            answered_by: match h.answered_by {
                AnsweredBy::PureRocking => "pure_rocking",
                AnsweredBy::Modes => "modes",
            }
            .to_string(),
            initial_mode: c.initial_mode.map(|m| m.name().to_string()),
            modes: c
                .modes
                .iter()
                .map(|m| ModeDoc {
                    mode: m.mode.name().to_string(),
                    from: m.from,
                    to: m.to,
                    direction: m.direction,
                    slide_from_m: m.slip.0,
                    slide_to_m: m.slip.1,
                })
                .collect(),
            peak_slide_m: c.peak_slide,
            residual_slide_m: c.residual_slide,
            time_sliding_s: c.time_sliding,
            flights: c.flights,
            time_in_flight_s: c.time_in_flight,
            series: c.series.as_ref().map(|s| {
                (
                    s.slide.clone(),
                    s.mode.iter().map(|m| m.name().to_string()).collect(),
                )
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::jobs::kind::Validate;
    use crate::kinds::time_history::{TimeHistoryResult, TimeHistorySpec};
    use serde_json::{Value, json};

    fn spec(pulse: Value, contact: Option<Value>) -> Value {
        let mut doc = json!({"kind": "time_history",
            "block": {"alpha": 0.25, "p": 2.14}, "pulse": pulse});
        if let Some(c) = contact {
            doc["contact"] = c;
        }
        doc
    }

    fn run(doc: Value) -> TimeHistoryResult {
        serde_json::from_value::<TimeHistorySpec>(doc)
            .expect("a spec")
            .validate()
            .expect("a valid spec")
            .run()
            .expect("a result")
    }

    fn refused(doc: Value) -> String {
        serde_json::from_value::<TimeHistorySpec>(doc)
            .expect("a spec")
            .validate()
            .expect_err("refused")
            .pointer
    }

    #[test]
    fn a_mu_pure_rocking_never_reaches_gives_pure_rockings_answer_to_the_bit() {
        let mut answered = 0;
        for (shape, level, ratio) in [
            ("one_sine", 1.5, 3.0),
            ("one_sine", 3.0, 6.0),
            ("one_cosine", 2.0, 4.0),
            ("ricker", 2.5, 2.0),
            ("cn", 4.0, 5.0),
        ] {
            let mut pulse = json!({"type": shape, "a_p_alpha_g": level, "omega_ratio": ratio});
            if shape == "cn" {
                pulse["n"] = json!(3);
            }
            let pure = run(spec(pulse.clone(), None));
            let c = run(spec(pulse, Some(json!({"model": "coulomb", "mu": 10.0}))));
            if c.answered_by.as_deref() == Some("pure_rocking") {
                answered += 1;
                assert_eq!(
                    (c.overturned, c.mode, c.impact_count, &c.impacts),
                    (pure.overturned, pure.mode, pure.impact_count, &pure.impacts),
                    "{shape} {level}"
                );
                assert_eq!(
                    (c.overturn_time, c.rest_time),
                    (pure.overturn_time, pure.rest_time)
                );
                assert_eq!(c.peak_theta_over_alpha, pure.peak_theta_over_alpha);
                assert_eq!(c.peak_slide_m, Some(0.0));
                assert_eq!(c.overturn_direction, pure.overturn_direction);
                let modes = c.modes.as_ref().expect("modes");
                assert!(modes.iter().all(|m| m.mode == "stick" || m.mode == "rock"));
            } else {
                // Pure rocking needed more than μ = 10 somewhere (falling over,
                // where f_z vanishes), or its fall was not followed: the modes
                // answer, with the same outcome.
                assert_eq!(c.overturned, pure.overturned, "{shape} {level}");
                assert!(
                    pure.friction_demand_followed_until.is_some()
                        || pure.lift_off == Some(true)
                        || pure.rocking_starts > 1
                        || pure.peak_friction_demand.is_none_or(|d| d > 10.0),
                    "{shape} {level}: {:?} {:?} {}",
                    pure.friction_demand_followed_until,
                    pure.peak_friction_demand,
                    pure.rocking_starts
                );
            }
        }
        assert!(answered >= 3, "{answered}");
    }

    #[test]
    fn a_block_on_less_friction_than_tan_alpha_slides_and_stands() {
        let pulse = json!({"type": "one_sine", "a_p_alpha_g": 4.0, "omega_ratio": 3.0});
        let pure = run(spec(pulse.clone(), None));
        assert!(pure.overturned);
        let c = run(spec(pulse, Some(json!({"model": "coulomb", "mu": 0.2}))));
        assert_eq!(c.answered_by.as_deref(), Some("modes"));
        assert_eq!(c.initial_mode.as_deref(), Some("slide"));
        assert!(!c.overturned && c.mode.is_none() && !c.rocked);
        assert!((c.residual_slide_m.expect("slid").abs() - 0.45).abs() < 0.005);
        assert_eq!(c.overturn_direction, None);
        // Pure rocking overturns it the other way.
        assert_eq!(pure.overturn_direction, Some(-1.0));
        assert!(c.numerics.rhs_evaluations == 0 && c.numerics.wall_time_s > 0.0);
    }

    #[test]
    fn a_series_on_a_coulomb_floor_follows_the_modes_and_the_slip() {
        // The locomotive on μ = 0.3 at 4 αg: stick, rock, slide-rock, one
        // impact, overturning; and on μ = 0.2: a flat slide to rest.
        for (mu, overturns) in [(0.3, true), (0.2, false)] {
            let mut doc = spec(
                json!({"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0}),
                Some(json!({"model": "coulomb", "mu": mu})),
            );
            doc["outputs"] = json!({"series": 2001});
            let r = run(doc);
            assert_eq!(r.overturned, overturns);
            let s = r.series.as_ref().expect("a series");
            let (slide, mode) = (
                s.slide_m.as_ref().expect("slip"),
                s.mode.as_ref().expect("modes"),
            );
            let modes = r.modes.as_ref().expect("modes");
            assert!(s.t.len() >= 2000, "{}", s.t.len());
            for (k, &t) in s.t.iter().enumerate() {
                // Each sample in the stretch that holds it (the ends shared).
                let inside = modes
                    .iter()
                    .filter(|m| m.from <= t && t <= m.to)
                    .any(|m| m.mode == mode[k]);
                assert!(inside, "μ {mu}: t = {t}, {} not in {modes:?}", mode[k]);
                if mode[k] == "stick" || mode[k] == "slide" {
                    assert_eq!(s.theta[k], 0.0);
                }
            }
            // The slip at the stretch ends, as the modes list it.
            for m in modes {
                for (at, want) in [(m.from, m.slide_from_m), (m.to, m.slide_to_m)] {
                    if let Some(k) = s.t.iter().position(|&t| (t - at).abs() < 1e-12) {
                        assert!(
                            (slide[k] - want).abs() < 1e-9,
                            "{at}: {} vs {want}",
                            slide[k]
                        );
                    }
                }
            }
            let peak = slide.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let want = r.peak_slide_m.expect("peak");
            assert!(
                peak <= want + 1e-12 && peak > 0.95 * want,
                "{peak} vs {want}"
            );
            if !overturns {
                let last = *slide.last().expect("samples");
                assert_eq!(last, r.residual_slide_m.expect("residual"));
            } else {
                let theta = s.theta.last().expect("samples").abs();
                assert!(theta > 1.0, "falling at the end: {theta}");
            }
        }
    }

    #[test]
    fn the_contact_field_is_checked_field_by_field() {
        let pulse = json!({"type": "one_sine", "a_p_alpha_g": 2.0, "omega_ratio": 3.0});
        let cases = [
            (json!({"model": "sticky"}), "/contact/model"),
            (json!({"model": "coulomb"}), "/contact/mu"),
            (json!({"model": "coulomb", "mu": -0.1}), "/contact/mu"),
            (
                json!({"model": "coulomb", "mu": 0.3, "mu_kinetic": 0.4}),
                "/contact/mu_kinetic",
            ),
            (json!({"model": "no_sliding", "mu": 0.3}), "/contact/mu"),
        ];
        for (c, at) in cases {
            assert_eq!(refused(spec(pulse.clone(), Some(c))), at);
        }
        let mut linear = spec(pulse.clone(), Some(json!({"model": "coulomb", "mu": 0.3})));
        linear["formulation"] = json!("linear");
        assert_eq!(refused(linear), "/formulation");
        // Pure rocking by name is the job without a contact field.
        let named = serde_json::from_value::<TimeHistorySpec>(spec(
            pulse.clone(),
            Some(json!({"model": "no_sliding"})),
        ))
        .expect("a spec")
        .validate()
        .expect("valid");
        let plain = serde_json::from_value::<TimeHistorySpec>(spec(pulse, None))
            .expect("a spec")
            .validate()
            .expect("valid");
        assert_eq!(named, plain);
    }
}
