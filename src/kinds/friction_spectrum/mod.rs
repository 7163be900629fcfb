//! The `friction_spectrum` job: the friction pure rocking needs (paper Fig. 9).

pub mod figure;
pub mod table;

mod result;
mod run;
mod spec;
pub use result::*;
pub use spec::*;

use crate::spectrum::Control;

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
    type Range = crate::jobs::kind::NoPart;

    fn run(
        job: &FrictionJob,
        _part: Option<crate::jobs::kind::NoPart>,
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

    fn size(
        job: &FrictionJob,
        _part: Option<crate::jobs::kind::NoPart>,
    ) -> crate::jobs::kind::Size {
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
