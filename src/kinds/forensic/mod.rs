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
pub mod sample;
pub mod scan;

mod result;
mod run;
mod sets;
mod spec;
pub use result::*;
pub use sets::*;
pub use spec::*;

use crate::jobs::names::Excitation;
use crate::jobs::spec::SpecError;
use crate::spectrum::Control;

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
    type Range = crate::jobs::scan_parts::Part;

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
        part: Option<crate::jobs::scan_parts::Part>,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        use crate::kinds::kind::Output;
        Ok(match part {
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
    fn size(
        job: &ForensicJob,
        part: Option<crate::jobs::scan_parts::Part>,
    ) -> crate::jobs::kind::Size {
        job.scan_size(part)
            .unwrap_or_else(|_| crate::jobs::kind::Size::one(0.0))
    }

    /// Under a record, each observation's line measured on a sample of
    /// its scan ([`ForensicJob::sampled_size`]).
    fn sampled_size(
        job: &ForensicJob,
        size: &crate::jobs::kind::Size,
    ) -> Option<crate::jobs::kind::Size> {
        job.sampled_size(size)
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
    fn split(
        job: &ForensicJob,
        size: &crate::jobs::kind::Size,
    ) -> Vec<crate::kinds::kind::Task<Self>> {
        crate::kinds::kind::Task::parts(job, job.cut(size))
    }

    fn fits(
        whole: &ForensicJob,
        part: &crate::jobs::scan_parts::Part,
    ) -> Result<(), crate::jobs::JobError> {
        whole.fits(part)
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
