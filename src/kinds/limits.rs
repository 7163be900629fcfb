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
        self.pointer = written_pointer(&self.pointer, spec);
        self
    }
}

/// `pointer`, a field of a normalised spec, as `spec` wrote it (an axis
/// normalised to ω_p/p or αg may have been given as `omega_p`,
/// `frequency_hz`, `a_p`, `a_p_g`, `R_m` or `pga_g`).
pub fn written_pointer(pointer: &str, spec: &serde_json::Value) -> String {
    const AXES: [&[&str]; 4] = [
        &["omega_ratio", "omega_p", "frequency_hz"],
        &["a_alpha_g", "a_p", "a_p_g"],
        &["p", "R_m"],
        &["scale", "pga_g"],
    ];
    let field = pointer.trim_start_matches('/');
    if let Some(axis) = AXES.iter().find(|axis| axis.contains(&field))
        && let Some(given) = axis
            .iter()
            .find(|name| spec.get(**name).is_some_and(|v| !v.is_null()))
    {
        return format!("/{given}");
    }
    pointer.to_string()
}

pub use crate::jobs::kind::Size;

impl Job {
    /// `Ok` when the job is within `limits`, else the first limit it exceeds.
    pub fn check_limits(&self, limits: &Limits) -> Result<Size, LimitError> {
        let size = self.size();
        self.check_size(&size, limits)?;
        Ok(size)
    }

    /// `Ok` when the job of `size` (its model's, or measured on a sample of
    /// it) is within `limits`, else the first limit it exceeds.
    pub fn check_size(&self, size: &Size, limits: &Limits) -> Result<(), LimitError> {
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
        let grid_field = self.grid_field();
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
        Ok(())
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
