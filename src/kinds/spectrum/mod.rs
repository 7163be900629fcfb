//! The `spectrum` job: overturning spectra (paper Figs. 6, 10, 11).

pub mod figure;
pub mod table;

mod concatenate;

mod result;
mod run;
mod spec;
pub use result::*;
pub use spec::*;

use crate::spectrum::Control;

/// The `spectrum` kind: the overturning spectrum of a block under a pulse
/// family.
pub struct Spectrum;

impl crate::kinds::kind::Kind for Spectrum {
    const NAME: &'static str = crate::jobs::names::tag::Spectrum::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Overturning spectrum";
    type Spec = SpectrumSpec;
    type Job = SpectrumJob;
    type Result = SpectrumResult;
    type Part = SpectrumResult;
    type Range = crate::jobs::kind::NoPart;

    fn run(
        job: &SpectrumJob,
        _part: Option<crate::jobs::kind::NoPart>,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        Ok(crate::kinds::kind::Output::Whole(job.run(control)?))
    }
    fn table(
        result: &SpectrumResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &SpectrumResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    fn size(
        job: &SpectrumJob,
        _part: Option<crate::jobs::kind::NoPart>,
    ) -> crate::jobs::kind::Size {
        use crate::jobs::cost;
        let scan = (job.a_max_alpha_g / job.scan_step_alpha_g).ceil();
        let line = cost::pulse_line_simulations(scan, job.scan_step_alpha_g, job.tolerance);
        // A residual-slide line adds its amplitudes, each a whole history.
        let per_frequency = line + f64::from(job.residual_slide_steps.unwrap_or(0));
        let n = job.omega_ratio.len() as f64;
        let on_floor = n * per_frequency;
        // The pure-rocking spectrum beside it scans the same grid again, at
        // pure rocking's cost, after the other (the lanes stay).
        let beside = job.pure_rocking().map_or(0.0, |_| n * line);
        let per_simulation = cost::contact_factor(job.contact.as_ref());
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: (n * scan).min(usize::MAX as f64) as usize,
            work: on_floor + beside,
            record_work: 0.0,
            cpu_s: (on_floor * per_simulation + beside * cost::contact_factor(None))
                * cost::pulse_simulation_s(&job.pulse.shape(), job.formulation, job.solver.method),
            lanes: n * (scan / 48.0).ceil(),
        }
    }

    fn grid_field(_job: &SpectrumJob) -> &'static str {
        "/omega_ratio"
    }

    fn warnings(job: &SpectrumJob) -> Vec<crate::jobs::warning::WarningDoc> {
        crate::jobs::plausible::size_warning(&job.block, "/block")
            .into_iter()
            .collect()
    }

    /// One task per chunk of frequencies of about
    /// [`crate::jobs::split::TASK_CPU_S`].
    fn split(
        job: &SpectrumJob,
        size: &crate::jobs::kind::Size,
    ) -> Vec<crate::kinds::kind::Task<Self>> {
        use crate::kinds::kind::Task;
        let n = job.omega_ratio.len();
        if n <= 1 {
            return vec![Task::whole(job.clone())];
        }
        let per = crate::jobs::split::per_task(n, size.cpu_s / n as f64);
        job.omega_ratio
            .chunks(per)
            .map(|chunk| {
                Task::whole(SpectrumJob {
                    omega_ratio: chunk.to_vec(),
                    ..job.clone()
                })
            })
            .collect()
    }

    fn assemble(
        job: &SpectrumJob,
        parts: Vec<SpectrumResult>,
    ) -> Result<SpectrumResult, crate::jobs::JobError> {
        Ok(concatenate::concatenate(job, parts))
    }
}

#[cfg(test)]
mod tests {
    use serde_json::{Value, json};

    use crate::kinds::Job;
    use crate::kinds::key::cache_key;
    use crate::spectrum::Control;

    fn spectrum(axes: Value) -> Result<Job, crate::jobs::spec::SpecError> {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.0, "eta": 0.9},
                              "pulse": {"type": "one_sine"}, "formulation": "linear"});
        for (k, v) in axes.as_object().expect("object") {
            spec[k] = v.clone();
        }
        Job::from_value(&spec)
    }

    #[test]
    fn frequencies_and_amplitudes_in_any_unit_make_the_same_job() {
        let tau = std::f64::consts::TAU;
        let reference =
            spectrum(json!({"omega_ratio": [1.0, 3.0], "a_max_alpha_g": 8.0})).expect("valid");
        for axes in [
            json!({"omega_p": [2.0, 6.0], "a_max_g": 2.0}),
            json!({"frequency_hz": [2.0 / tau, 6.0 / tau], "a_max": 8.0 * 0.25 * 9.81}),
            json!({"omega_ratio": {"from": 1, "to": 3, "steps": 2}, "a_max_alpha_g": 8}),
        ] {
            let job = spectrum(axes.clone()).expect("valid");
            assert_eq!(cache_key(&job), cache_key(&reference), "{axes}");
        }
    }

    #[test]
    fn a_frequency_axis_is_given_once_and_named_when_wrong() {
        let e = spectrum(json!({"omega_ratio": [1.0], "frequency_hz": [0.5]})).expect_err("twice");
        assert_eq!(e.pointer, "/frequency_hz");
        let e = spectrum(json!({"a_max_alpha_g": 5, "a_max_g": 1})).expect_err("no frequencies");
        assert_eq!(e.pointer, "/omega_ratio");
        let e = spectrum(json!({"omega_p": [2.0], "a_max_alpha_g": 5, "a_max_g": 1}))
            .expect_err("two maxima");
        assert_eq!(e.pointer, "/a_max_g");
        // 1e5 rad/s on a block of p = 2 is ω_p/p = 5e4, above the accepted range.
        let e = spectrum(json!({"omega_p": [1e5]})).expect_err("out of range");
        assert_eq!(e.pointer, "/omega_p");
        assert!(e.message.contains("p = 2 rad/s"), "{}", e.message);
    }

    fn coulomb(mu: Option<f64>, alpha: f64, shape: &str, ratios: Value, a_max: f64) -> Value {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": alpha, "p": 2.14},
                              "pulse": {"type": shape}, "omega_ratio": ratios,
                              "a_max_alpha_g": a_max, "tolerance": 1e-3, "scan_step_alpha_g": 0.05});
        if let Some(mu) = mu {
            spec["contact"] = json!({"model": "coulomb", "mu": mu});
        }
        let job = Job::from_value(&spec).expect("valid");
        job.run(&Control::new()).expect("runs")
    }

    #[test]
    fn a_coulomb_spectrum_follows_the_floor() {
        // μ = 10 is never reached below these minima: the same lowest
        // overturning amplitude as pure rocking.
        let (pure, rough) = (
            coulomb(None, 0.25, "one_sine", json!([2.0, 4.0]), 6.0),
            coulomb(Some(10.0), 0.25, "one_sine", json!([2.0, 4.0]), 6.0),
        );
        for k in 0..2 {
            let (a, b) = (
                &pure["spectrum"][k]["min_overturn_alpha_g"],
                &rough["spectrum"][k]["min_overturn_alpha_g"],
            );
            assert!(a.as_f64().is_some() && a == b, "{a} vs {b}");
        }
        assert_eq!(rough["spec"]["contact"]["mu"], 10.0);
        // Below tan α the block only slides: nothing overturns.
        let smooth = coulomb(Some(0.2), 0.25, "one_sine", json!([2.0, 4.0]), 6.0);
        for line in smooth["spectrum"].as_array().expect("lines") {
            assert!(line["min_overturn_alpha_g"].is_null(), "{line}");
            assert!(line["transitions"].as_array().expect("list").is_empty());
        }
        // The residual slide on a grid of amplitudes: none below μg (nothing
        // moves), the block's slip growing with the pulse above, as the
        // history on that floor says.
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": [3.0], "a_max_alpha_g": 4.0,
            "contact": {"model": "coulomb", "mu": 0.2}, "residual_slide": {"steps": 8}});
        let doc = Job::from_value(&spec)
            .expect("valid")
            .run(&Control::new())
            .expect("runs");
        let line = doc["spectrum"][0]["residual_slide"]
            .as_array()
            .expect("asked");
        assert_eq!(line.len(), 8);
        let at = |k: usize| line[k]["residual_slide_m"].as_f64().expect("m");
        assert_eq!(line[0]["a_alpha_g"], 0.5);
        assert_eq!(at(0), 0.0, "0.5 αg = 0.125 g < μ g");
        assert!(line.iter().all(|p| p["outcome"] == "stands"));
        let th = Job::from_value(&json!({"kind": "time_history",
            "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0},
            "contact": {"model": "coulomb", "mu": 0.2}}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        assert_eq!(at(7), th["residual_slide_m"].as_f64().expect("m"));
        assert!(at(7).abs() > at(3).abs() && at(3).abs() > 0.0);
        // Only on a floor the block can slide on.
        spec.as_object_mut().expect("object").remove("contact");
        let e = Job::from_value(&spec).expect_err("no floor");
        assert_eq!(e.pointer, "/residual_slide");
        // A squat block under strong one-cosine pulses leaves the floor
        // (the normal force reaches 0): its flights are followed, so the
        // line claims the whole range, and where its history flies the
        // line says what that history says.
        let contact = json!({"model": "coulomb", "mu": 0.6, "mu_kinetic": 0.5});
        let squat = Job::from_value(&json!({"kind": "spectrum",
            "block": {"alpha": 0.4, "p": 2.14}, "pulse": {"type": "one_cosine"},
            "omega_ratio": [2.0], "a_max_alpha_g": 10.0, "tolerance": 1e-3,
            "scan_step_alpha_g": 0.05, "contact": contact}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        let line = &squat["spectrum"][0];
        assert!(line["lift_off_above_alpha_g"].is_null(), "{line}");
        let th = Job::from_value(&json!({"kind": "time_history",
            "block": {"alpha": 0.4, "p": 2.14},
            "pulse": {"type": "one_cosine", "omega_ratio": 2.0, "a_p_alpha_g": 8.0},
            "contact": contact}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        assert!(th["flights"].as_u64().expect("counted") >= 1, "{th}");
        assert!(th["time_in_flight_s"].as_f64().expect("s") > 0.1, "{th}");
        let overturns_at_8 = line["transitions"]
            .as_array()
            .expect("list")
            .iter()
            .rfind(|t| t["a_alpha_g"].as_f64().expect("at") < 8.0)
            .is_some_and(|t| t["direction"] == "up");
        assert!(overturns_at_8 && th["overturned"] == true, "{line}");
    }

    /// The locomotive's one-sine spectrum on a coarse grid (tolerance
    /// 1e-3 αg, step 0.05 αg) at `ratios` up to `a_max` αg, on a Coulomb
    /// floor of `mu` when given, with `extra` fields.
    fn locomotive(mu: Option<f64>, ratios: Value, a_max: f64, extra: Value) -> Value {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
                              "pulse": {"type": "one_sine"}, "omega_ratio": ratios,
                              "a_max_alpha_g": a_max, "tolerance": 1e-3, "scan_step_alpha_g": 0.05});
        if let Some(mu) = mu {
            spec["contact"] = json!({"model": "coulomb", "mu": mu});
        }
        for (k, v) in extra.as_object().expect("object") {
            spec[k] = v.clone();
        }
        spec
    }

    fn run(spec: &Value) -> Value {
        Job::from_value(spec)
            .expect("valid")
            .run(&Control::new())
            .expect("runs")
    }

    #[test]
    fn the_spectrum_beside_a_floor_never_reached_is_the_pure_rocking_spectrum() {
        let beside = json!({"no_sliding_beside": true});
        let rough = run(&locomotive(Some(10.0), json!([2.0, 4.0]), 6.0, beside));
        let alone = run(&locomotive(Some(10.0), json!([2.0, 4.0]), 6.0, json!({})));
        let pure = run(&locomotive(None, json!([2.0, 4.0]), 6.0, json!({})));
        // Bit for bit what the same spec without contact computes; the
        // spectrum on the floor unchanged by asking.
        assert_eq!(rough["no_sliding"], pure["spectrum"]);
        assert_eq!(rough["spectrum"], alone["spectrum"]);
        assert_eq!(rough["spec"]["no_sliding_beside"], true);
        // Its cost counted: the simulations of both spectra.
        let simulations = |doc: &Value| doc["numerics"]["simulations"].as_u64().expect("count");
        assert_eq!(
            simulations(&rough),
            simulations(&alone) + simulations(&pure)
        );
        // Not asked: no field, neither in the result nor in its spec.
        assert!(alone.get("no_sliding").is_none());
        assert!(alone["spec"].get("no_sliding_beside").is_none());
    }

    #[test]
    fn the_spectrum_beside_mu_0_3_is_pure_rocking_and_differs_from_the_floor() {
        // The locomotive (README): on μ = 0.3 the same lowest overturning
        // as pure rocking at ω_p/p = 3, none up to 6 αg at ω_p/p = 6
        // (pure rocking: 4.737 αg).
        let beside = json!({"no_sliding_beside": true});
        let doc = run(&locomotive(Some(0.3), json!([3.0, 6.0]), 6.0, beside));
        let pure = run(&locomotive(None, json!([3.0, 6.0]), 6.0, json!({})));
        assert_eq!(doc["no_sliding"], pure["spectrum"]);
        assert_ne!(doc["no_sliding"], doc["spectrum"]);
        let min = |lines: &Value, k: usize| lines[k]["min_overturn_alpha_g"].as_f64();
        let (sliding, rocking) = (&doc["spectrum"], &doc["no_sliding"]);
        assert_eq!(min(sliding, 0), min(rocking, 0));
        assert!(min(rocking, 1).is_some_and(|a| (a - 4.737).abs() < 0.01));
        assert_eq!(min(sliding, 1), None);
    }

    #[test]
    fn the_spectrum_beside_needs_a_coulomb_floor_and_not_asking_keeps_the_key() {
        let ratios = json!([2.0]);
        let e = Job::from_value(&locomotive(
            None,
            ratios.clone(),
            4.0,
            json!({"no_sliding_beside": true}),
        ))
        .expect_err("pure rocking is already the no-sliding spectrum");
        assert_eq!(e.pointer, "/no_sliding_beside");
        let e = Job::from_value(&locomotive(
            None,
            ratios.clone(),
            4.0,
            json!({"contact": {"model": "no_sliding"}, "no_sliding_beside": true}),
        ))
        .expect_err("pure rocking by name");
        assert_eq!(e.pointer, "/no_sliding_beside");
        // false (or null) is the default: the job and its key unchanged.
        for mu in [None, Some(0.3)] {
            let plain =
                Job::from_value(&locomotive(mu, ratios.clone(), 4.0, json!({}))).expect("valid");
            for off in [json!(false), Value::Null] {
                let job = Job::from_value(&locomotive(
                    mu,
                    ratios.clone(),
                    4.0,
                    json!({"no_sliding_beside": off}),
                ))
                .expect("valid");
                assert_eq!(job, plain);
                assert_eq!(cache_key(&job), cache_key(&plain));
                assert!(!crate::kinds::key::canonical_spec(&job).contains("no_sliding_beside"));
            }
        }
        // Asked for: another job, another key; its normalised spec
        // validates to itself.
        let asked = locomotive(Some(0.3), ratios, 4.0, json!({"no_sliding_beside": true}));
        let job = Job::from_value(&asked).expect("valid");
        let plain =
            Job::from_value(&locomotive(Some(0.3), json!([2.0]), 4.0, json!({}))).expect("valid");
        assert_ne!(cache_key(&job), cache_key(&plain));
        let again =
            Job::from_value(&serde_json::to_value(&job).expect("serialises")).expect("valid");
        assert_eq!(again, job);
        // Its cost: the floor's scans and pure rocking's, at 1×.
        let (with, without) = (job.size(), plain.size());
        assert!(with.work > without.work && with.cpu_s > without.cpu_s);
        let pure = Job::from_value(&locomotive(None, json!([2.0]), 4.0, json!({}))).expect("valid");
        let size = pure.size();
        assert!((with.cpu_s - without.cpu_s - size.cpu_s).abs() < 1e-12 * with.cpu_s);
        assert_eq!(with.work - without.work, size.work);
        // What runs beside it is that job: the spec without `contact`.
        let (Job::Spectrum(asked), Job::Spectrum(pure)) = (&job, &pure) else {
            panic!("spectra");
        };
        assert_eq!(asked.pure_rocking().as_ref(), Some(pure.as_ref()));
    }

    #[test]
    fn every_frequency_echoes_its_dimensional_values() {
        let job = spectrum(json!({"frequency_hz": [0.5], "a_max_g": 2.0})).expect("valid");
        let doc = job.run(&Control::new()).expect("runs");
        let line = &doc["spectrum"][0];
        let ratio = line["omega_ratio"].as_f64().expect("ratio");
        assert!(
            (ratio - std::f64::consts::PI / 2.0).abs() < 1e-12,
            "{ratio}"
        );
        assert!((line["omega_p"].as_f64().expect("omega_p") - std::f64::consts::PI).abs() < 1e-12);
        assert!((line["frequency_hz"].as_f64().expect("hz") - 0.5).abs() < 1e-12);
        let min = line["min_overturn_alpha_g"]
            .as_f64()
            .expect("overturns below 8 αg");
        let g = line["min_overturn_g"].as_f64().expect("in g");
        let si = line["min_overturn_m_s2"].as_f64().expect("in m/s²");
        assert!((g - 0.25 * min).abs() < 1e-12 && (si - 0.25 * 9.81 * min).abs() < 1e-9);
        // Every transition and the rocking threshold in g as well as αg.
        let transitions = line["transitions"].as_array().expect("transitions");
        assert!(!transitions.is_empty());
        for t in transitions {
            let (a, a_g) = (t["a_alpha_g"].as_f64(), t["a_g"].as_f64());
            let (a, a_g) = (a.expect("αg"), a_g.expect("g"));
            assert!((a_g - 0.25 * a).abs() < 1e-12, "{a} αg, {a_g} g");
        }
        let threshold = line["threshold_alpha_g"].as_f64().expect("αg");
        assert!((line["threshold_g"].as_f64().expect("g") - 0.25 * threshold).abs() < 1e-12);
    }
}
