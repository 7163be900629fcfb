//! A history on a Coulomb floor, answered by the cheapest computation that
//! is exact for it: pure rocking where the friction it needs never exceeds
//! μ, the mode driver ([`super::coulomb`]) otherwise.
//!
//! Pure rocking runs first, following the friction it needs: where that
//! never exceeds μ (eq. 7 at every start of rocking included), never lifts
//! the block off, and μ ≥ tan α (a block with less slides before it could
//! rock), pure rocking *is* the Coulomb answer, to the bit.

use super::contact::Mode;
use super::coulomb::{Asks, ContactResponse, ContactSeries, Cut, ModeSpan, simulate_contact_with};
use super::response::{Impact, Numerics, Response, Warning};
use super::sliding::{Friction, Kinematics};
use super::{Block, Options, Problem, SimError, Solver, simulate};

/// Which computation answered a Coulomb history.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnsweredBy {
    /// Pure rocking held throughout (the friction it needs stayed within μ).
    PureRocking,
    /// The mode driver.
    Modes,
}

/// A history on a Coulomb floor: the response in the pure-rocking shape
/// (outcome, impacts, peaks, numerics) and the contact's own account.
pub struct CoulombHistory {
    /// Outcome, impacts, peaks, numerics.
    pub response: Response,
    /// Modes and sliding.
    pub contact: ContactResponse,
    /// Which computation answered.
    pub answered_by: AnsweredBy,
}

/// Runs `problem` on a Coulomb floor with `friction` (`options` as for pure
/// rocking; a Runge–Kutta solver).
pub fn run_coulomb<G: Kinematics>(
    problem: &Problem<G>,
    options: &Options,
    friction: Friction,
) -> Result<CoulombHistory, SimError> {
    let block = problem.block;
    let Solver::RungeKutta { method, rtol, atol } = options.solver else {
        return Err(SimError::ExactNeedsLinear);
    };
    if friction.static_coefficient >= block.slenderness().tan() {
        let followed = Block::new(
            block.slenderness(),
            block.frequency_parameter(),
            Some(block.restitution()),
            Some(friction.static_coefficient),
            Some(block.gravity()),
        )?;
        let pure = Problem {
            block: followed,
            ..problem.clone()
        };
        // Where only the outcome is asked, the free motion is decided at
        // the ground motion's end where it is pure rocking on this floor to
        // its end (`free_rocking::stays_pure`); otherwise the demand is
        // followed to its end, as in a whole history.
        let with_demand = Options {
            reactions: true,
            // A whole history follows the free motion as far as asked.
            max_free_impacts: if options.stop_at_decision {
                options
                    .max_free_impacts
                    .max(Options::history(options.solver).max_free_impacts)
            } else {
                options.max_free_impacts
            },
            // Where it is not the answer, the modes are run from the start.
            stop_at_sliding: true,
            ..options.clone()
        };
        let r = simulate(&pure, &with_demand)?;
        let held = r.lift_off.is_none()
            && r.friction.is_some_and(|f| {
                f.first_sliding.is_none()
                    && f.first_lift_off.is_none()
                    && f.followed_until.is_none()
            })
            && r.rocking_starts <= 1;
        if held {
            let contact = from_pure_rocking(&r);
            return Ok(CoulombHistory {
                response: r,
                contact,
                answered_by: AnsweredBy::PureRocking,
            });
        }
    }
    let run = |times| {
        let solver = (method, rtol, atol);
        let asks = Asks {
            peak: options.peak,
            stop_at_decision: options.stop_at_decision,
            // A scan's outcome follows the free motion to its end (or its
            // decision); a history as far as asked.
            max_free_impacts: (!options.stop_at_decision).then_some(options.max_free_impacts),
        };
        simulate_contact_with(&block, &problem.pulse, friction, solver, times, asks)
    };
    let c = match (&options.series_at, options.series_points) {
        (Some(times), _) => run(Some(times.clone()))?,
        (None, Some(n)) if n > 0 => {
            // The series spans the history, known after a first pass.
            let end = run(None)?.end_time;
            let last = (n - 1).max(1) as f64;
            run(Some((0..n).map(|k| end * k as f64 / last).collect()))?
        }
        _ => run(None)?,
    };
    Ok(CoulombHistory {
        response: to_response(&c, &problem.pulse, options, method.name(), rtol, atol),
        contact: c,
        answered_by: AnsweredBy::Modes,
    })
}

/// The contact account of a history pure rocking answers: at rest, then
/// rocking from its start to rest or overturning (one start at most).
fn from_pure_rocking(r: &Response) -> ContactResponse {
    let end = r.overturn_time.or(r.rest_time).unwrap_or(r.end_time);
    let mut modes = Vec::new();
    let span = |mode, from, to| ModeSpan {
        mode,
        from,
        to,
        direction: None,
        slip: (0.0, 0.0),
    };
    match r.rocking_start {
        Some(start) => {
            if start > 0.0 {
                modes.push(span(Mode::Stick, 0.0, start));
            }
            modes.push(span(Mode::Rock, start, end));
            if let Some(rest) = r.rest_time
                && r.end_time > rest
            {
                modes.push(span(Mode::Stick, rest, r.end_time));
            }
        }
        None => modes.push(span(Mode::Stick, 0.0, r.end_time)),
    }
    ContactResponse {
        initial_mode: r.rocking_start.map(|_| Mode::Rock),
        modes,
        overturned: r.overturned,
        overturn_time: r.overturn_time,
        overturn_side: r.overturn_side,
        overturn_mode: r.mode,
        impacts: Vec::new(),
        impact_count: r.impact_count,
        rocking_impacts: r.rocking_impacts,
        summed_impacts: r.summed_impacts,
        first_flight: None,
        flights: 0,
        time_in_flight: 0.0,
        rest_time: r.rest_time,
        end_time: r.end_time,
        peak_slide: 0.0,
        residual_slide: 0.0,
        time_sliding: 0.0,
        peak_theta_over_alpha: r.peak_theta_over_alpha,
        stats: Default::default(),
        events: r.numerics.events,
        cut: r.warnings.iter().find_map(|w| match *w {
            Warning::FreeRockingTruncated(n) => Some(Cut::FreeImpacts(n)),
            Warning::LimitReached(l, _) => Some(Cut::Limit(l)),
            _ => None,
        }),
        series: r.series.as_ref().map(|s| ContactSeries {
            t: s.t.clone(),
            theta: s.theta.clone(),
            theta_dot: s.theta_dot.clone(),
            slide: vec![0.0; s.t.len()],
            mode: s
                .t
                .iter()
                .zip(&s.theta)
                .zip(&s.theta_dot)
                .map(|((&t, &th), &w)| {
                    let rocking = r.rocking_start.is_some_and(|t0| t >= t0)
                        && r.rest_time.is_none_or(|t1| t < t1);
                    if rocking || th != 0.0 || w != 0.0 {
                        Mode::Rock
                    } else {
                        Mode::Stick
                    }
                })
                .collect(),
        }),
    }
}

/// The pure-rocking shape of a Coulomb history.
fn to_response<G: Kinematics>(
    c: &ContactResponse,
    forcing: &G,
    options: &Options,
    method: &'static str,
    rtol: f64,
    atol: f64,
) -> Response {
    let rocks = |m: &ModeSpan| matches!(m.mode, Mode::Rock | Mode::SlideRock);
    let starts = c
        .modes
        .windows(2)
        .filter(|w| !rocks(&w[0]) && rocks(&w[1]))
        .count()
        + usize::from(c.modes.first().is_some_and(rocks));
    let rocking_start = c.modes.iter().find(|m| rocks(m)).map(|m| m.from);
    let warnings = match c.cut {
        Some(Cut::FreeImpacts(n)) => vec![Warning::FreeRockingTruncated(n)],
        Some(Cut::Limit(l)) => vec![Warning::LimitReached(l, c.end_time)],
        None => Vec::new(),
    };
    Response {
        rocked: rocking_start.is_some(),
        rocking_start,
        rocking_starts: u32::try_from(starts).unwrap_or(u32::MAX),
        overturned: c.overturned,
        mode: c.overturn_mode,
        impact_count: c.impact_count,
        impacts: if options.record_impacts {
            c.impacts
                .iter()
                .map(|i| Impact {
                    time: i.t,
                    velocity_before: i.theta_dot.0,
                    velocity_after: i.theta_dot.1,
                })
                .collect()
        } else {
            Vec::new()
        },
        rocking_impacts: c.rocking_impacts,
        summed_impacts: c.summed_impacts,
        overturn_time: c.overturn_time,
        overturn_side: c.overturn_side,
        rest_time: c.rest_time,
        decided_at: c.end_time,
        end_time: c.end_time,
        peak_theta_over_alpha: c.peak_theta_over_alpha,
        friction: None,
        lift_off: None,
        series: c.series.as_ref().map(|s| super::response::Series {
            t: s.t.clone(),
            theta: s.theta.clone(),
            theta_dot: s.theta_dot.clone(),
            ground_acceleration: s.t.iter().map(|&t| forcing.acceleration(t)).collect(),
            vertical_acceleration: G::VERTICAL.then(|| {
                s.t.iter()
                    .map(|&t| forcing.vertical_acceleration(t))
                    .collect()
            }),
            reaction_ratio: None,
        }),
        warnings,
        numerics: Numerics {
            method,
            rtol: Some(rtol),
            atol: Some(atol),
            steps_accepted: c.stats.accepted,
            steps_rejected: c.stats.rejected,
            rhs_evaluations: c.stats.rhs_evals,
            events: c.events,
            error_estimate: c.stats.local_error_sum,
            wall_time: 0.0,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::simulate::{REST_VELOCITY, ROCKING_IMPACT_VELOCITY};
    use crate::dynamics::{Formulation, Method, Pulse, PulseShape};

    /// Followed for the friction it needs, pure rocking stops at the step
    /// where that first exceeds μ (it is then not the Coulomb answer): it
    /// finds the same first excess as when followed on, and integrates no
    /// further than that step.
    #[test]
    fn pure_rocking_followed_for_its_demand_stops_at_the_first_excess_of_mu() {
        let solver = Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        };
        let block = Block::new(0.25, 2.14, None, Some(0.3), None).expect("valid");
        let on = Options {
            reactions: true,
            stop_at_sliding: true,
            ..Options::outcome(solver)
        };
        let followed_on = Options {
            stop_at_sliding: false,
            ..on.clone()
        };
        let mut stopped_early = 0;
        for ratio in [2.0, 4.0, 7.0] {
            for k in 1..=12 {
                let level = 0.5 + 0.5 * f64::from(k);
                let a = level * block.slenderness() * block.gravity();
                let pulse = Pulse::new(PulseShape::OneSine, a, ratio * block.frequency_parameter())
                    .expect("valid");
                let problem = Problem {
                    block,
                    pulse,
                    formulation: Formulation::Nonlinear,
                };
                let stop = simulate(&problem, &on).expect("runs");
                let whole = simulate(&problem, &followed_on).expect("runs");
                let at = format!("ω_p/p {ratio} at {level} αg");
                let first = |r: &Response| r.friction.and_then(|f| f.first_sliding);
                assert_eq!(first(&stop), first(&whole), "{at}");
                let Some(ts) = first(&stop) else {
                    continue;
                };
                // It ends on the step where the excess was found.
                assert!(stop.end_time >= ts, "{at}");
                assert!(
                    stop.end_time - ts <= 0.1 * pulse.duration,
                    "{at}: {} after {ts}",
                    stop.end_time
                );
                assert!(
                    stop.numerics.steps_accepted <= whole.numerics.steps_accepted,
                    "{at}"
                );
                stopped_early += usize::from(whole.end_time > stop.end_time);
            }
        }
        assert!(stopped_early >= 10, "{stopped_early}");
    }

    /// On the floor, as under pure rocking, the rocking impacts are those
    /// reached at |θ̇| ≥ 1e-2 p α: the chattering that ends a rocking
    /// episode, counted among all the impacts, is not among them.
    #[test]
    fn a_coulomb_historys_rocking_impacts_leave_out_its_chattering() {
        let block = Block::new(0.25, 2.14, None, None, None).expect("valid");
        let solver = Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        };
        let friction = Friction::new(0.3, None).expect("valid");
        let v_rest = REST_VELOCITY * block.frequency_parameter() * block.slenderness();
        let slow = ROCKING_IMPACT_VELOCITY * v_rest / REST_VELOCITY;
        let (mut with_chatter, mut by_modes) = (0, 0);
        for ratio in [2.0, 4.0] {
            for k in 1..=16 {
                let level = 0.5 * f64::from(k);
                let a = level * block.slenderness() * block.gravity();
                let pulse = Pulse::new(PulseShape::OneSine, a, ratio * block.frequency_parameter())
                    .expect("valid");
                let problem = Problem {
                    block,
                    pulse,
                    formulation: Formulation::Nonlinear,
                };
                let h = run_coulomb(&problem, &Options::history(solver), friction).expect("runs");
                if h.answered_by != AnsweredBy::Modes {
                    continue;
                }
                by_modes += 1;
                let c = &h.contact;
                let fast = c
                    .impacts
                    .iter()
                    .filter(|i| i.theta_dot.0.abs() >= slow)
                    .count() as u64;
                let at = format!("ω_p/p {ratio} at {level} αg");
                assert_eq!(h.response.rocking_impacts, fast, "{at}");
                assert!(fast <= h.response.impact_count, "{at}");
                with_chatter += usize::from((c.impacts.len() as u64) > fast);
            }
        }
        assert!(
            by_modes >= 16 && with_chatter > 0,
            "{by_modes} {with_chatter}"
        );
    }

    /// What a scan asks of a history (its outcome, stopped at its decision)
    /// is what the whole history answers: overturning, its side and its
    /// impacts, and the residual slide, to the bit — over pulses that
    /// rock, slide-rock, slide and overturn in either mode, on floors from
    /// below the least rocking's demand (μ = 0.15 for α = 0.25) to above
    /// every demand.
    #[test]
    fn a_history_stopped_at_its_decision_answers_as_the_whole_one() {
        let block = Block::new(0.25, 2.14, None, None, None).expect("valid");
        let solver = Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        };
        let (mut decided_early, mut cases) = (0, 0);
        for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
            for ratio in [1.5, 3.0, 6.0] {
                for mu in [0.15, 0.3, 0.5, 1.0] {
                    let friction = Friction::new(mu, None).expect("valid");
                    for k in 1..=24 {
                        let level = 0.5 * f64::from(k);
                        let a = level * block.slenderness() * block.gravity();
                        let pulse = Pulse::new(shape, a, ratio * block.frequency_parameter())
                            .expect("valid");
                        let problem = Problem {
                            block,
                            pulse,
                            formulation: Formulation::Nonlinear,
                        };
                        let whole = run_coulomb(&problem, &Options::history(solver), friction)
                            .expect("runs");
                        let scan = run_coulomb(&problem, &Options::outcome(solver), friction)
                            .expect("runs");
                        let at = format!("{shape:?} ω_p/p {ratio} μ {mu} at {level} αg");
                        let (w, s) = (&whole.contact, &scan.contact);
                        assert_eq!(w.overturned, s.overturned, "{at}");
                        assert_eq!(w.overturn_side, s.overturn_side, "{at}");
                        assert_eq!(w.residual_slide, s.residual_slide, "{at}");
                        if w.overturned {
                            assert_eq!(w.impact_count, s.impact_count, "{at}");
                        }
                        // Standing, rocking on after the ground stopped, on
                        // a floor where the least rocking holds (μ above
                        // 0.188, the demand at θ → 0): the scan stops at a
                        // decision instead of following the rocking to rest.
                        let rocks_on = w.modes.iter().any(|m| {
                            matches!(m.mode, Mode::Rock | Mode::SlideRock)
                                && m.to > problem.pulse.duration
                        });
                        if whole.answered_by == AnsweredBy::Modes
                            && !w.overturned
                            && rocks_on
                            && mu > 0.19
                        {
                            cases += 1;
                            decided_early += usize::from(s.end_time < w.end_time);
                        }
                    }
                }
            }
        }
        assert!(cases >= 20, "{cases}");
        assert_eq!(decided_early, cases);
    }
}
