//! What a record upload found, as the service stores and shows it (and
//! `topple record` prints): typed both ways.

use serde::{Deserialize, Serialize};

use super::RecordFile;

/// A warning about a record: valid, but possibly not what was meant.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordWarningDoc {
    /// "npts_mismatch" | "baseline_drift" | "large_pga".
    pub kind: String,
    /// What was found, and what to do about it.
    pub message: String,
}

/// A record's metadata.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordMeta {
    /// Its name (from the file, or as given).
    pub name: String,
    /// The format it was read as: "at2" | "csv" | "json".
    pub format: String,
    /// The unit its samples were given in: "g" | "m/s2" | "cm/s2" (stored
    /// in m/s²; g is 9.81 m/s²).
    pub unit: String,
    /// Sampling interval, s.
    pub dt: f64,
    /// Number of samples.
    pub samples: usize,
    /// (samples − 1)·dt, s.
    pub duration_s: f64,
    /// Peak ground acceleration, g.
    pub pga_g: f64,
    /// Peak ground acceleration, m/s².
    pub pga_m_s2: f64,
    /// Peak ground velocity from rest (the acceleration linear between
    /// samples), m/s.
    pub pgv_m_s: f64,
    /// Peak ground displacement from rest, m.
    pub pgd_m: f64,
    /// What may be wrong with it (the record is stored all the same).
    pub warnings: Vec<RecordWarningDoc>,
}

/// `x` to 12 significant digits: (N − 1)·dt without the binary noise of the
/// product (29.99, not 29.990000000000002).
fn decimal(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

impl RecordMeta {
    /// The metadata of what was read.
    pub fn of(file: &RecordFile) -> Result<Self, String> {
        let record = crate::dynamics::Record::new(file.acc.clone().into(), file.dt)
            .map_err(|e| e.to_string())?;
        let peaks = crate::dynamics::peaks::of_record(&record);
        Ok(RecordMeta {
            name: file.name.clone(),
            format: file.format.as_str().to_string(),
            unit: file.unit.as_str().to_string(),
            dt: file.dt,
            samples: file.acc.len(),
            duration_s: decimal(file.acc.len().saturating_sub(1) as f64 * file.dt),
            pga_g: peaks.pga / super::G_M_S2,
            pga_m_s2: peaks.pga,
            pgv_m_s: peaks.pgv,
            pgd_m: peaks.pgd,
            warnings: file
                .warnings
                .iter()
                .map(|w| RecordWarningDoc {
                    kind: w.kind.to_string(),
                    message: w.message.clone(),
                })
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_duration_is_written_without_binary_noise() {
        assert_eq!(3000_f64 - 1.0, 2999.0);
        assert_eq!(decimal(2999.0 * 0.01), 29.99);
        assert_eq!(decimal(199_999.0 * 0.005), 999.995);
        assert_eq!(decimal(0.0), 0.0);
    }
}
