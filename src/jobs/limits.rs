//! Limits on the size of a job, checked before it is accepted.
//!
//! Validation already refuses what no machine could run (see the `MAX_*`
//! constants of each job kind); these limits are the operator's, lower and
//! configurable, and name the setting that raises them.

use super::Job;

/// Largest job a service accepts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Samples of a time history's series (`outputs.series`).
    pub series_points: usize,
    /// Points of a spectrum's grid: frequencies × amplitude scan points
    /// (a friction spectrum: its amplitudes).
    pub grid_points: usize,
    /// Estimated simulations of one job.
    pub work: f64,
    /// Estimated simulations × record samples of one job (a simulation of a
    /// record costs in proportion to its samples).
    pub record_work: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            series_points: 200_000,
            grid_points: 4_000_000,
            work: 2e7,
            record_work: 5e9,
        }
    }
}

impl Limits {
    /// No limits beyond validation's (what `topple run` applies).
    pub fn none() -> Self {
        Limits {
            series_points: usize::MAX,
            grid_points: usize::MAX,
            work: f64::INFINITY,
            record_work: f64::INFINITY,
        }
    }
}

/// A job over a limit: the field to change, the limit's name and both values.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{pointer}: {message}")]
pub struct LimitError {
    /// JSON pointer to the field that sets the size.
    pub pointer: String,
    /// Which limit (as the setting names it, e.g. `max_grid_points`).
    pub limit: &'static str,
    /// The job's value.
    pub value: f64,
    /// The limit.
    pub maximum: f64,
    /// What to do about it.
    pub message: String,
}

impl LimitError {
    /// The error pointing at the field as the spec wrote it: a frequency or
    /// amplitude axis is normalised to ω_p/p or αg, but the user may have given
    /// it as `omega_p`, `frequency_hz`, `a_p` or `a_p_g`.
    pub fn as_written(mut self, spec: &serde_json::Value) -> Self {
        const AXES: [&[&str]; 4] = [
            &["omega_ratio", "omega_p", "frequency_hz"],
            &["a_alpha_g", "a_p", "a_p_g"],
            &["p", "R_m"],
            &["scale", "pga_g"],
        ];
        let field = self.pointer.trim_start_matches('/');
        if let Some(axis) = AXES.iter().find(|axis| axis.contains(&field))
            && let Some(given) = axis
                .iter()
                .find(|name| spec.get(**name).is_some_and(|v| !v.is_null()))
        {
            self.pointer = format!("/{given}");
        }
        self
    }
}

/// Bisection steps assumed per transition, and transitions per frequency, in
/// the work estimate of a spectrum: a bracket of one scan step narrowed to the
/// tolerance takes log2(step/tolerance) steps; a frequency has a handful of
/// transitions (Figs. 6, 10, 11 show at most four).
const TRANSITIONS_PER_FREQUENCY: f64 = 6.0;

/// Size of a job: its grid and its estimated simulations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// Series samples (time histories).
    pub series_points: usize,
    /// Grid points (spectra).
    pub grid_points: usize,
    /// Estimated simulations.
    pub work: f64,
    /// Estimated simulations × record samples (records only, else 0).
    pub record_work: f64,
}

impl Job {
    /// How big the job is.
    pub fn size(&self) -> Size {
        match self {
            Job::TimeHistory(j) => Size {
                series_points: j.outputs.series,
                grid_points: 1,
                work: 1.0,
                record_work: j.ground_motion.as_ref().map_or(0.0, |g| g.acc.len() as f64),
            },
            Job::Spectrum(j) => {
                let scan = (j.a_max_alpha_g / j.scan_step_alpha_g).ceil();
                let bisection = (j.scan_step_alpha_g / j.tolerance).log2().ceil().max(1.0);
                let per_frequency = scan + TRANSITIONS_PER_FREQUENCY * bisection;
                let n = j.omega_ratio.len() as f64;
                Size {
                    series_points: 0,
                    grid_points: (n * scan).min(usize::MAX as f64) as usize,
                    work: n * per_frequency,
                    record_work: 0.0,
                }
            }
            Job::FrictionSpectrum(j) => Size {
                series_points: 0,
                grid_points: j.a_alpha_g.len(),
                work: j.a_alpha_g.len() as f64,
                record_work: 0.0,
            },
            Job::Forensic(j) => {
                let (grid, work) = j.size();
                Size {
                    series_points: 0,
                    grid_points: grid.min(usize::MAX as f64) as usize,
                    work,
                    record_work: j
                        .ground_motion
                        .as_ref()
                        .map_or(0.0, |g| work * g.acc.len() as f64),
                }
            }
            Job::Fragility(j) => {
                let work = j.simulations() as f64;
                Size {
                    series_points: 0,
                    grid_points: work as usize,
                    work,
                    record_work: work * j.longest_record() as f64,
                }
            }
            // Closed forms: as cheap as one simulation.
            Job::Survival(_) => Size {
                series_points: 0,
                grid_points: 1,
                work: 1.0,
                record_work: 0.0,
            },
            Job::RecordSpectrum(j) => {
                let scan = j.points_per_size();
                let grid = j.grid();
                let bisection = (grid.step / grid.tolerance).log2().ceil().max(1.0);
                let n = j.p.len() as f64;
                let work = n * (scan + TRANSITIONS_PER_FREQUENCY * bisection);
                Size {
                    series_points: 0,
                    grid_points: (n * scan).min(usize::MAX as f64) as usize,
                    work,
                    record_work: work * j.ground_motion.acc.len() as f64,
                }
            }
        }
    }

    /// `Ok` when the job is within `limits`, else the first limit it exceeds.
    pub fn check_limits(&self, limits: &Limits) -> Result<Size, LimitError> {
        let size = self.size();
        if size.series_points > limits.series_points {
            return Err(LimitError {
                pointer: "/outputs/series".into(),
                limit: "max_series_points",
                value: size.series_points as f64,
                maximum: limits.series_points as f64,
                message: format!(
                    "{} series samples exceed this service's limit of {} (max_series_points); ask for fewer samples",
                    size.series_points, limits.series_points
                ),
            });
        }
        let grid_field = match self {
            Job::FrictionSpectrum(_) => "/a_alpha_g",
            Job::Forensic(j) if j.ground_motion.is_some() => "/scale",
            Job::Fragility(_) => "/samples",
            Job::Forensic(_) => "/frequency_hz",
            Job::RecordSpectrum(_) => "/p",
            _ => "/omega_ratio",
        };
        if size.grid_points > limits.grid_points {
            return Err(LimitError {
                pointer: grid_field.into(),
                limit: "max_grid_points",
                value: size.grid_points as f64,
                maximum: limits.grid_points as f64,
                message: format!(
                    "the grid has {} points (frequencies × a_max_alpha_g/scan_step_alpha_g), over this service's limit of {} (max_grid_points); use fewer frequencies or a coarser scan step",
                    size.grid_points, limits.grid_points
                ),
            });
        }
        if size.work > limits.work {
            return Err(LimitError {
                pointer: grid_field.into(),
                limit: "max_work",
                value: size.work,
                maximum: limits.work,
                message: format!(
                    "the job needs about {:.3e} simulations, over this service's limit of {:.3e} (max_work); split it into smaller jobs",
                    size.work, limits.work
                ),
            });
        }
        if size.record_work > limits.record_work {
            return Err(LimitError {
                pointer: grid_field.into(),
                limit: "max_record_work",
                value: size.record_work,
                maximum: limits.record_work,
                message: format!(
                    "the job needs about {:.3e} simulations × record samples, over this service's limit of {:.3e} (max_record_work); use fewer block sizes, a coarser scan step, a narrower scale range or a shorter record",
                    size.record_work, limits.record_work
                ),
            });
        }
        Ok(size)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spectrum(steps: usize, step: f64) -> Job {
        let text = format!(
            r#"{{"kind":"spectrum","block":{{"alpha":0.25,"p":2.14}},"pulse":{{"type":"one_sine"}},
                "omega_ratio":{{"from":1,"to":10,"steps":{steps}}},"scan_step_alpha_g":{step}}}"#
        );
        Job::parse(&text).expect("valid")
    }

    #[test]
    fn a_spectrum_is_sized_by_its_grid_and_bisections() {
        let s = spectrum(40, 0.02).size();
        // 20 αg / 0.02 = 1000 scan points per frequency.
        assert_eq!(s.grid_points, 40_000);
        // Each of 6 transitions narrows 0.02 to 1e-4: 8 bisection steps.
        assert_eq!(s.work, 40.0 * (1000.0 + 6.0 * 8.0));
        assert!(spectrum(40, 0.02).check_limits(&Limits::default()).is_ok());
    }

    #[test]
    fn an_oversized_job_names_the_field_as_written() {
        let text = r#"{"kind":"spectrum","block":{"alpha":0.2,"p":2},"pulse":{"type":"one_sine"},
            "omega_p":{"from":1,"to":20,"steps":2000},"scan_step_alpha_g":0.0001}"#;
        let Job::Spectrum(job) = Job::parse(text).expect("valid") else {
            panic!("a spectrum")
        };
        let e = Job::Spectrum(job)
            .check_limits(&Limits::default())
            .expect_err("over the grid limit");
        assert_eq!(e.pointer, "/omega_ratio");
        let spec: serde_json::Value = serde_json::from_str(text).expect("json");
        assert_eq!(e.as_written(&spec).pointer, "/omega_p");
    }

    #[test]
    fn an_oversized_job_names_its_field_and_limit() {
        let limits = Limits {
            grid_points: 10_000,
            ..Limits::default()
        };
        let e = spectrum(40, 0.02).check_limits(&limits).expect_err("over");
        assert_eq!(
            (e.pointer.as_str(), e.limit),
            ("/omega_ratio", "max_grid_points")
        );
        assert_eq!((e.value, e.maximum), (40_000.0, 10_000.0));
        let limits = Limits {
            work: 1e4,
            ..Limits::default()
        };
        let e = spectrum(40, 0.02).check_limits(&limits).expect_err("over");
        assert_eq!(e.limit, "max_work");
        let history = Job::parse(
            r#"{"kind":"time_history","block":{"alpha":0.2,"p":2},"pulse":{"type":"one_sine","omega_ratio":4,"a_p_alpha_g":3},"outputs":{"series":5000}}"#,
        )
        .expect("valid");
        let limits = Limits {
            series_points: 1000,
            ..Limits::default()
        };
        let e = history.check_limits(&limits).expect_err("over");
        assert_eq!(
            (e.pointer.as_str(), e.limit),
            ("/outputs/series", "max_series_points")
        );
        assert!(history.check_limits(&Limits::none()).is_ok());
    }
}
