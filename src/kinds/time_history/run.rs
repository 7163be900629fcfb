//! How a time history job is computed.

use super::result::{GroundPeaksDoc, ImpactDoc, SeriesDoc, TimeHistoryResult};
use super::spec::TimeHistoryJob;
use crate::dynamics::PulsePair;
use crate::dynamics::response::{Limit, Response, Warning};
use crate::dynamics::sliding::Kinematics;
use crate::dynamics::{Formulation, Options, Problem, SimError, simulate};
use crate::jobs::contact::{ContactDoc, run_coulomb};
use crate::jobs::names::tag;
use crate::jobs::numerics::NumericsDoc;
use crate::jobs::vertical::VerticalPulseNorm;
use crate::jobs::warning::WarningDoc;
impl TimeHistoryJob {
    /// Runs the job.
    pub fn run(&self) -> Result<TimeHistoryResult, SimError> {
        let block = self.block.block()?;
        let formulation = self.formulation;
        let options = Options {
            solver: self.solver.solver(),
            reactions: self.outputs.reactions,
            peak: true,
            series_points: (self.outputs.series > 0).then_some(self.outputs.series),
            series_at: None,
            record_impacts: self.outputs.impacts,
            stop_at_decision: false,
            stop_at_sliding: false,
            max_free_impacts: self.outputs.max_free_impacts,
            horizon: self.outputs.duration,
            initial_state: None,
            // A record mostly lasts past an overturning: the fall under it
            // is left out as the fall after a pulse's end is.
            fall_under_forcing: self.ground_motion.is_some(),
        };
        let mut pga_v = None;
        let (r, peaks) = match (&self.pulse, &self.ground_motion) {
            (Some(p), _) => {
                let pulse = crate::dynamics::Pulse::new(p.shape, p.a_p, p.omega_p)
                    .map_err(|_| SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_pulse(&pulse);
                if let Some(v) = &self.vertical {
                    let pair = match *v {
                        VerticalPulseNorm::Ratio(r) => PulsePair::proportional(pulse, r),
                        VerticalPulseNorm::Pulse { pulse: q, delay_s } => {
                            crate::dynamics::Pulse::new(q.shape, q.a_p, q.omega_p)
                                .ok()
                                .map(|v| PulsePair::new(pulse, v, delay_s))
                        }
                        VerticalPulseNorm::Scaled(v) => v.pair(pulse).ok(),
                    }
                    .ok_or(SimError::Tolerance)?;
                    pga_v = Some(pair.vertical.amplitude.abs());
                    let problem = Problem {
                        block,
                        pulse: pair,
                        formulation,
                    };
                    (self.respond(&problem, &options)?, peaks)
                } else {
                    let problem = Problem {
                        block,
                        pulse,
                        formulation,
                    };
                    (self.respond(&problem, &options)?, peaks)
                }
            }
            (None, Some(g)) if g.vertical.is_some() => {
                let pair = g.pair().and_then(Result::ok).ok_or(SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_record(&pair.horizontal);
                pga_v = Some(
                    pair.vertical
                        .samples()
                        .iter()
                        .fold(0.0f64, |m, a| m.max(a.abs())),
                );
                let problem = Problem {
                    block,
                    pulse: pair,
                    formulation,
                };
                (self.respond(&problem, &options)?, peaks)
            }
            (None, Some(g)) => {
                let record = g.record().map_err(|_| SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_record(&record);
                let problem = Problem {
                    block,
                    pulse: record,
                    formulation,
                };
                (self.respond(&problem, &options)?, peaks)
            }
            (None, None) => return Err(SimError::Tolerance),
        };
        let g = self.block.g;
        let (r, contact) = r;
        let mut doc = self.document(r, GroundPeaksDoc::new(&peaks, g).with_vertical(pga_v, g));
        if let Some(c) = contact {
            self.add_contact(&mut doc, c);
        }
        Ok(doc)
    }

    /// `doc` with what the Coulomb floor `c` adds: the contact model, who
    /// answered, the modes and slides, the flights, the slip and mode series;
    /// and, under a record that never reaches the rocking threshold, the
    /// `never_rocks` warning, which says whether the block slid (known only
    /// from the history, where pure rocking warns from the spec alone).
    fn add_contact(&self, doc: &mut TimeHistoryResult, c: ContactDoc) {
        doc.contact_model = Some(c.contact_model);
        doc.answered_by = Some(c.answered_by);
        doc.initial_mode = c.initial_mode;
        doc.modes = Some(c.modes);
        doc.peak_slide_m = Some(c.peak_slide_m);
        doc.residual_slide_m = Some(c.residual_slide_m);
        doc.time_sliding_s = Some(c.time_sliding_s);
        doc.flights = Some(c.flights);
        doc.time_in_flight_s = Some(c.time_in_flight_s);
        if let (Some(series), Some((slide, mode))) = (doc.series.as_mut(), c.series) {
            series.slide_m = Some(slide);
            series.mode = Some(mode);
        }
        if let Some(m) = self.ground_motion.as_ref().filter(|m| m.vertical.is_none()) {
            doc.warnings
                .extend(crate::jobs::plausible::never_rocks_warning(
                    m,
                    &self.block,
                    self.formulation == Formulation::Linear,
                    Some((c.peak_slide_m, c.residual_slide_m)),
                ));
        }
    }

    /// One history: pure rocking, or on the Coulomb floor of the spec.
    fn respond<G: Kinematics>(
        &self,
        problem: &Problem<G>,
        options: &Options,
    ) -> Result<(Response, Option<ContactDoc>), SimError> {
        match &self.contact {
            None => Ok((simulate(problem, options)?, None)),
            Some(c) => {
                let started = std::time::Instant::now();
                let h = run_coulomb(problem, options, c.friction())?;
                let doc = ContactDoc::new(&h);
                let mut r = h.response;
                r.numerics.wall_time = started.elapsed().as_secs_f64();
                Ok((r, Some(doc)))
            }
        }
    }

    /// The result document of response `r`.
    fn document(&self, r: Response, ground_peaks: GroundPeaksDoc) -> TimeHistoryResult {
        TimeHistoryResult {
            kind: tag::TimeHistory,
            ground_peaks,
            rocked: r.rocked,
            rocking_start: r.rocking_start,
            rocking_starts: r.rocking_starts,
            overturned: r.overturned,
            mode: r.mode.map(|m| m.number()),
            impact_count: r.impact_count,
            chatter_impacts_summed: r.summed_impacts,
            impacts: self.outputs.impacts.then(|| {
                r.impacts
                    .iter()
                    .map(|i| ImpactDoc {
                        t: i.time,
                        theta_dot_before: i.velocity_before,
                        theta_dot_after: i.velocity_after,
                    })
                    .collect()
            }),
            overturn_time: r.overturn_time,
            rest_time: r.rest_time,
            decided_at: r.decided_at,
            end_time: r.end_time,
            peak_theta_over_alpha: r.peak_theta_over_alpha,
            peak_friction_demand: r.friction.and_then(|f| f.peak),
            peak_friction_demand_time: r.friction.and_then(|f| f.peak_time),
            lift_off: r
                .friction
                .map(|f| f.first_lift_off.is_some() || r.lift_off.is_some())
                .or(r.lift_off.map(|_| true)),
            lift_off_time: match (r.friction.and_then(|f| f.first_lift_off), r.lift_off) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
            friction_demand_followed_until: r
                .friction
                .and_then(|f| f.followed_until)
                .filter(|_| r.overturned),
            initiation_friction_demand: r.friction.and_then(|f| f.initiation),
            warnings: r.warnings.iter().map(WarningDoc::from).collect(),
            series: r.series.map(|s| SeriesDoc {
                t: s.t,
                theta: s.theta,
                theta_dot: s.theta_dot,
                ground_acceleration: s.ground_acceleration,
                ground_vertical_acceleration: s.vertical_acceleration,
                fx_over_fz: s.reaction_ratio,
                slide_m: None,
                mode: None,
            }),
            numerics: NumericsDoc::from(&r.numerics),
            overturn_direction: r.overturn_side,
            contact_model: None,
            answered_by: None,
            initial_mode: None,
            modes: None,
            peak_slide_m: None,
            residual_slide_m: None,
            time_sliding_s: None,
            flights: None,
            time_in_flight_s: None,
            spec: self.clone(),
            engine: None,
        }
    }
}

impl WarningDoc {
    fn from(w: &Warning) -> Self {
        let (kind, t, message) = match *w {
            Warning::Sliding(t) => (
                "sliding",
                Some(t),
                format!("|f_x/f_z| exceeds mu at t = {t:.6} s: pure rocking is violated (the block would slide); contact {{\"model\": \"coulomb\", \"mu\": mu}} follows the block as it slides"),
            ),
            Warning::LiftOff(t) => (
                "lift_off",
                Some(t),
                format!("f_z <= 0 at t = {t:.6} s: the block would lift off the base; no friction coefficient sustains pure rocking (peak_friction_demand is null: unbounded)"),
            ),
            Warning::GroundFallsAway(t) => (
                "lift_off",
                Some(t),
                format!("g + vertical ground acceleration <= 0 at t = {t:.6} s: the ground falls away faster than gravity pulls the block, which leaves the base; the simulation ends there, without a verdict on overturning (overturned is false, mode null)"),
            ),
            Warning::DemandExcludesFall(t) => (
                "demand_excludes_fall",
                Some(t),
                format!("the friction demand is followed up to t = {t:.6} s, the pulse end: the block was then bound to overturn, and its fall is not counted"),
            ),
            Warning::DemandExcludesForcedFall(t) => (
                "demand_excludes_fall",
                Some(t),
                format!("the friction demand is followed up to t = {t:.6} s: from then on the block, the ground still moving, was bound to overturn (the free motion from every state overturns) and overturned; its fall is not counted"),
            ),
            Warning::FreeRockingTruncated(n) => (
                "free_rocking_truncated",
                None,
                format!("free rocking after the ground motion followed for {n} impacts only (outputs.max_free_impacts); overturned is then the outcome decided in closed form from there where the free motion is pure rocking (overturn_time and rest_time null), else the outcome up to there"),
            ),
            Warning::ImpactListTruncated(n) => (
                "impact_list_truncated",
                None,
                format!("impact list truncated to {n} entries; impact_count is complete"),
            ),
            Warning::LimitReached(limit, t) => (
                "limit_reached",
                Some(t),
                format!(
                    "the history reached its bound on {} at t = {t:.6} s and ends there: {}; its outcome past it is not followed (overturned: false means not overturned by then)",
                    match limit {
                        Limit::Impacts(_) => "impacts",
                        Limit::Steps(_) => "integration steps",
                        Limit::FreeTime(_) => "free motion",
                    },
                    match limit {
                        Limit::Impacts(n) => format!("{n} impacts followed one by one, none of them ending in rest"),
                        Limit::Steps(n) => format!("{n} integration steps"),
                        Limit::FreeTime(s) => format!("the motion after the ground motion followed for {s:.6} s without rest or overturning"),
                    }
                ),
            ),
            Warning::NearSeparatrix => (
                "near_separatrix",
                None,
                "the state at the pulse end lies within integration tolerance of the separatrix; the outcome is the exact free-vibration decision".to_string(),
            ),
        };
        WarningDoc {
            kind: kind.to_string(),
            t,
            message,
        }
    }
}
