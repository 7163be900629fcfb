//! The `time_history` job: one block, one ground motion (a pulse or a sampled
//! record), one response.

pub mod figure;
pub mod motion;
pub mod table;

mod result;
mod run;
mod spec;
pub use result::*;
pub use spec::*;

pub use crate::jobs::warning::WarningDoc;

/// The `time_history` kind: one simulation of a block under a pulse or a
/// record.
pub struct TimeHistory;

impl crate::kinds::kind::Kind for TimeHistory {
    const NAME: &'static str = crate::jobs::names::tag::TimeHistory::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Time history";
    type Spec = TimeHistorySpec;
    type Job = TimeHistoryJob;
    type Result = TimeHistoryResult;
    type Part = crate::jobs::kind::NoPart;
    type Range = crate::jobs::kind::NoPart;

    fn run(
        job: &TimeHistoryJob,
        _part: Option<crate::jobs::kind::NoPart>,
        control: &crate::spectrum::Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        crate::kinds::kind::run_one::<Self>(control, || Ok(job.run()?))
    }
    fn table(
        result: &TimeHistoryResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &TimeHistoryResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        figure::svg(result, window).map_err(crate::plot::FigureError::Result)
    }

    fn size(
        job: &TimeHistoryJob,
        _part: Option<crate::jobs::kind::NoPart>,
    ) -> crate::jobs::kind::Size {
        use crate::jobs::cost;
        let cpu_s = match (&job.ground_motion, &job.pulse) {
            (Some(g), _) => cost::record_simulation_s(&g.acc),
            (None, Some(p)) => {
                cost::pulse_simulation_s(&p.shape, job.formulation, job.solver.method)
            }
            (None, None) => 0.0,
        };
        // On a Coulomb floor: pure rocking first, then the modes, whose
        // events cost more per step.
        let cpu_s = if job.contact.is_some() {
            4.0 * cpu_s
        } else {
            cpu_s
        };
        crate::jobs::kind::Size {
            series_points: job.outputs.series,
            record_work: job
                .ground_motion
                .as_ref()
                .map_or(0.0, |g| g.acc.len() as f64),
            ..crate::jobs::kind::Size::one(cpu_s)
        }
    }

    fn grid_field(_job: &TimeHistoryJob) -> &'static str {
        "/omega_ratio"
    }

    fn warnings(job: &TimeHistoryJob) -> Vec<WarningDoc> {
        use crate::jobs::plausible::{
            coarse_dt_warning, never_rocks_warning, record_warnings, size_warning,
        };
        let mut found: Vec<WarningDoc> = size_warning(&job.block, "/block").into_iter().collect();
        if let Some(m) = &job.ground_motion {
            found.extend(record_warnings(m, "/ground_motion"));
            found.extend(coarse_dt_warning(m.dt, job.block.p, "/ground_motion"));
            // (A vertical acceleration moves the threshold: the PGA alone
            // does not tell. On a Coulomb floor the result says whether the
            // block slid: `TimeHistoryJob::run` warns there.)
            if m.vertical.is_none() && job.contact.is_none() {
                found.extend(never_rocks_warning(
                    m,
                    &job.block,
                    job.formulation == crate::dynamics::Formulation::Linear,
                    None,
                ));
            }
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Forcing, Options, Problem, simulate};
    use crate::jobs::kind::Validate;
    use serde_json::json;

    /// The result of the time-history spec `doc`.
    fn run(doc: serde_json::Value) -> TimeHistoryResult {
        serde_json::from_value::<TimeHistorySpec>(doc)
            .expect("a spec")
            .validate()
            .expect("a valid spec")
            .run()
            .expect("a result")
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-9)
    }

    fn pulse_spec(vertical: Option<serde_json::Value>) -> serde_json::Value {
        let mut doc = json!({"kind": "time_history",
            "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
            "pulse": {"type": "one_sine", "omega_ratio": 4.0, "a_p_alpha_g": 3.0},
            "outputs": {"series": 300, "duration": 4.0}});
        if let Some(v) = vertical {
            doc["vertical"] = v;
        }
        doc
    }

    #[test]
    fn the_series_carries_the_vertical_acceleration_only_with_a_vertical_motion() {
        let plain = run(pulse_spec(None));
        let s = plain.series.as_ref().expect("a series");
        assert_eq!(s.ground_vertical_acceleration, None);
        let text = serde_json::to_string(&plain).expect("json");
        assert!(!text.contains("ground_vertical_acceleration"));

        // ü_v = r·ü_g at every sample.
        let r = -0.4;
        let ratio = run(pulse_spec(Some(json!({"ratio": r}))));
        let s = ratio.series.as_ref().expect("a series");
        let v = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        assert_eq!(v.len(), s.t.len());
        assert!(v.iter().any(|a| *a != 0.0));
        for (k, (&av, &ag)) in v.iter().zip(&s.ground_acceleration).enumerate() {
            assert!(close(av, r * ag), "sample {k}: {av} vs {}", r * ag);
        }
        let text = serde_json::to_string(&ratio).expect("json");
        let back: TimeHistoryResult = serde_json::from_str(&text).expect("reads back");
        assert_eq!(back.series, ratio.series);
    }

    #[test]
    fn a_delayed_vertical_pulse_is_sampled_where_it_acts() {
        let delay = 0.5;
        let result = run(pulse_spec(Some(json!({"type": "one_sine",
            "omega_p": 12.0, "a_p_g": 0.3, "delay_s": delay}))));
        let s = result.series.as_ref().expect("a series");
        let v = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        let pulse = crate::dynamics::Pulse::new(
            crate::dynamics::PulseShape::OneSine,
            0.3 * result.spec.block.g,
            12.0,
        )
        .expect("a pulse");
        let mut acting = 0;
        for (&t, &a) in s.t.iter().zip(v) {
            if t < delay || t > delay + pulse.duration {
                assert_eq!(a, 0.0, "still at t = {t}");
            } else {
                acting += 1;
                assert!(close(a, pulse.acceleration(t - delay)), "t = {t}: {a}");
            }
        }
        assert!(acting > 10, "{acting} samples while it acts");
    }

    #[test]
    fn a_vertical_record_is_sampled_from_its_samples() {
        let dt = 0.01;
        let h: Vec<f64> = (0..400)
            .map(|k| 3.0 * (f64::from(k) * dt * 9.0).sin())
            .collect();
        let v: Vec<f64> = (0..250)
            .map(|k| -2.0 * (f64::from(k) * dt * 5.0).cos())
            .collect();
        let result = run(json!({"kind": "time_history",
            "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
            "ground_motion": {"dt": dt, "acc": h, "unit": "m/s2",
                              "vertical": {"acc": v, "unit": "m/s2"}},
            "outputs": {"series": 333}}));
        let s = result.series.as_ref().expect("a series");
        let sampled = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        let record = crate::dynamics::Record::new(v.into(), dt).expect("a record");
        for (&t, &a) in s.t.iter().zip(sampled) {
            // Padded with zeros past its end.
            let expected = if t <= 249.0 * dt {
                record.acceleration(t)
            } else {
                0.0
            };
            assert!((a - expected).abs() <= 1e-12, "t = {t}: {a} vs {expected}");
        }
    }

    /// The ridge station record of `specs/records` (3000 samples, dt =
    /// 0.01 s, in g) scaled by `scale`, under a slender block (α = 0.25,
    /// p = 2 rad/s).
    fn ridge_spec(scale: f64) -> serde_json::Value {
        let acc: Vec<f64> = include_str!("../../../specs/records/ridge_station_090.at2")
            .lines()
            .skip(4)
            .flat_map(str::split_whitespace)
            .map(|a| scale * a.parse::<f64>().expect("a sample"))
            .collect();
        assert_eq!(acc.len(), 3000);
        json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.0},
            "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc}})
    }

    /// Under a record, as after a pulse's end, the fall of a block bound to
    /// overturn is not counted in the friction demand: from the first step
    /// of the last unbroken stretch where the free motion overturns
    /// (`separatrix::decide`) to the overturning. Counted, it gave 103.4 at
    /// t = 6.72 s, 0.06 s before the block overturns (2.7 × the record);
    /// and at 1.5 × a lift-off at 7.258 s, 0.06 s before, nulled the peak.
    #[test]
    fn under_a_record_the_friction_demand_leaves_out_the_fall() {
        // (scale, followed until, peak and its time; counted with the fall:
        // the peak and its time, or the lift-off).
        let cases = [
            (2.7, 4.8, (0.343_621_4, 3.183_149), (Some(103.420_2), 6.72)),
            (1.5, 4.36, (0.307_209_2, 4.351_792), (None, 7.258_121)),
        ];
        for (scale, until, (peak, at), (counted, counted_at)) in cases {
            let job = serde_json::from_value::<TimeHistorySpec>(ridge_spec(scale))
                .expect("a spec")
                .validate()
                .expect("a valid spec");
            let r = job.run().expect("a result");
            let to = r.overturn_time.expect("overturns");
            assert!(r.overturned && r.mode == Some(1), "{scale}");
            let followed = r.friction_demand_followed_until.expect("the fall left out");
            assert!((followed - until).abs() < 1e-9, "{scale}: {followed}");
            let found = r.peak_friction_demand.expect("bounded");
            let found_at = r.peak_friction_demand_time.expect("a time");
            assert!((found - peak).abs() < 1e-6, "{scale}: {found}");
            assert!((found_at - at).abs() < 1e-5, "{scale}: {found_at}");
            assert_eq!((r.lift_off, r.lift_off_time), (Some(false), None));
            let fall: Vec<&WarningDoc> = r
                .warnings
                .iter()
                .filter(|w| w.kind == "demand_excludes_fall")
                .collect();
            assert_eq!(fall.len(), 1, "{scale}: {:?}", r.warnings);
            assert_eq!(fall[0].t, Some(followed));
            assert!(
                !fall[0].message.contains("pulse end"),
                "{}",
                fall[0].message
            );
            // The same history with the fall counted.
            let problem = Problem {
                block: job.block.block().expect("a block"),
                pulse: job
                    .ground_motion
                    .as_ref()
                    .and_then(|g| g.record().ok())
                    .expect("a record"),
                formulation: job.formulation,
            };
            let all = simulate(&problem, &Options::history(job.solver.solver())).expect("runs");
            assert_eq!(all.overturn_time, Some(to));
            let f = all.friction.expect("followed");
            assert_eq!(f.followed_until, None);
            match counted {
                Some(d) => {
                    assert!((f.peak.expect("bounded") - d).abs() < 1e-3, "{f:?}");
                    assert!((f.peak_time.expect("a time") - counted_at).abs() < 1e-5);
                }
                None => {
                    assert_eq!(f.peak, None);
                    assert!((f.first_lift_off.expect("lifts off") - counted_at).abs() < 1e-5);
                }
            }
        }
    }
}
