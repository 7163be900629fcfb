//! How a forensic job is computed.

use super::result::{Bounds, ForensicFrequency, ForensicNumerics, ForensicResult, ObservationSet};
use super::sets::{Intervals, LineSet, intersect};
use super::spec::{AmplitudeRange, ForensicJob, common_g};
use crate::jobs::names::{Excitation, tag};
use crate::kinds::record_spectrum::{ScaleRangeNorm, pga};
use crate::kinds::spectrum::ScanCost;
use crate::spectrum::scan::{ScanError, ScanStats};
impl ForensicJob {
    /// The amplitudes examined, g: a pulse's peak, or the scaled record's
    /// PGA; under a vertical motion, up to just below the amplitude where the
    /// ground falls away faster than gravity ([`ForensicJob::lift_off_g`]).
    pub fn range_g(&self) -> AmplitudeRange {
        let range = self
            .a_p_g
            .or(self.pga_g)
            .unwrap_or(AmplitudeRange { from: 0.0, to: 0.0 });
        match self.lift_off_g() {
            Some((lo, _)) => AmplitudeRange {
                from: range.from,
                to: range.to.min(lo).max(range.from),
            },
            None => range,
        }
    }

    /// ü_v/ü_g, when the query has a vertical motion given as a ratio.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// The vertical motion scaled with the ground motion (a ratio, or a
    /// record's own samples), when the query has one.
    pub fn scaled_vertical(&self) -> Option<crate::jobs::vertical::ScaledVertical<'_>> {
        crate::jobs::vertical::ScaledVertical::of(
            self.vertical.as_ref(),
            self.ground_motion.as_ref(),
        )
    }

    /// Under a vertical motion ü_v = r ü_g: the amplitude (g; a pulse's
    /// peak, or the scaled record's PGA) from which the ground falls away
    /// faster than gravity somewhere (g + ü_v ≤ 0) and the block leaves it,
    /// bracketed `(lo, hi)`; `None` when it does not within the range asked
    /// (or without a vertical motion). The same for every block: it is the
    /// ground's.
    pub fn lift_off_g(&self) -> Option<(f64, f64)> {
        use crate::dynamics::{Block, Pulse};
        // On a Coulomb floor the block's flights are followed.
        if self.contact.is_some() {
            return None;
        }
        use crate::spectrum::scan::lift_off_level;
        let vertical = self.scaled_vertical()?;
        let asked = self.a_p_g.or(self.pga_g)?;
        // Any block of slenderness 1 under the observations' g: levels in g.
        let g = self.observations.first()?.block.g;
        let unit = Block::new(1.0, 1.0, None, None, Some(g)).ok()?;
        let (lo, hi) = match (&self.ground_motion, &self.pulse) {
            (Some(gm), _) => vertical.record_lift_off(&gm.record().ok()?, &unit, asked.to)?,
            (None, Some(family)) => {
                // (The same at every frequency: the vertical motion's
                // extremes scale with the amplitude, whatever its length.)
                let pulse = Pulse::new(family.shape(), g, 1.0).ok()?;
                let pair = vertical.pulse_pair(pulse)?.ok()?;
                lift_off_level(&pair, &unit, asked.to)?
            }
            (None, None) => return None,
        };
        Some((lo, hi))
    }

    /// The scale factors examined by a record query: `pga_g` over the
    /// record's PGA (in the g every block shares); `None` for a pulse query.
    pub fn scale(&self) -> Option<ScaleRangeNorm> {
        let gm = self.ground_motion.as_ref()?;
        self.pga_g?;
        // (Under a vertical motion, up to just below the lift-off.)
        let range = self.range_g();
        let peak_g = pga(&gm.acc) / common_g(&self.observations)?;
        Some(ScaleRangeNorm {
            from: range.from / peak_g,
            to: range.to / peak_g,
        })
    }

    /// The result of a pulse query from each observation's overturning set
    /// at each frequency (`sets[observation][frequency]`, g): the sets
    /// consistent with what was seen, intersected at each frequency.
    pub(super) fn pulse_result(
        &self,
        sets: &[Vec<LineSet>],
        stats: &ScanStats,
    ) -> Result<ForensicResult, ScanError> {
        let pulse = self
            .pulse
            .ok_or(ScanError::Simulation(crate::dynamics::SimError::Tolerance))?;
        let frequencies = self.frequency_sets(sets);
        let bounds = Self::pulse_bounds(&frequencies);
        Ok(ForensicResult {
            warnings: Vec::new(),
            kind: tag::Forensic,
            formulation: self.formulation,
            excitation: Excitation::Pulse,
            pulse: Some(pulse),
            record: None,
            a_p_g: self.range_g(),
            scale: None,
            observations: self.observations.clone(),
            frequencies,
            consistent_scale: None,
            consistent_pga_g: None,
            mixed_scale: None,
            mixed_pga_g: None,
            per_observation: None,
            bounds,
            lift_off_above_g: self.lift_off_g().map(|(_, hi)| hi),
            numerics: ForensicNumerics {
                cost: ScanCost::new(&self.solver, stats),
                tolerance_g: self.tolerance_g,
                scan_step_g: self.scan_step_g,
                wall_time_s: 0.0,
                tasks: None,
            },
            spec: self.clone(),
            engine: None,
        })
    }

    /// Per frequency, the amplitudes, g, consistent with every observation,
    /// and each observation's own, with their mixed zones
    /// (`sets[observation][frequency]`).
    fn frequency_sets(&self, sets: &[Vec<LineSet>]) -> Vec<ForensicFrequency> {
        let two_pi = 2.0 * std::f64::consts::PI;
        let AmplitudeRange { from, to } = self.range_g();
        // Each observation's certain intervals and mixed zones, per frequency.
        let (consistent, zones): (Vec<Vec<Intervals>>, Vec<Vec<Vec<super::mixed::MixedDoc>>>) =
            self.observations
                .iter()
                .zip(sets)
                .map(|(o, per_frequency)| {
                    per_frequency
                        .iter()
                        .map(|line| {
                            (
                                line.consistent(o.overturned, from),
                                super::mixed::observation_zones(line, o, from),
                            )
                        })
                        .unzip()
                })
                .unzip();
        self.frequency_hz
            .iter()
            .enumerate()
            .map(|(k, &f)| {
                let mut all: Intervals = vec![[from, to]];
                let per_observation = self
                    .observations
                    .iter()
                    .zip(&consistent)
                    .zip(&zones)
                    .zip(sets)
                    .map(|(((o, s), z), lines)| {
                        all = intersect(&all, &s[k]);
                        ObservationSet {
                            name: o.name.clone(),
                            consistent_g: s[k].clone(),
                            mixed_g: z[k].clone(),
                            lift_off_above_g: lines.get(k).and_then(|l| l.lift_off_g),
                        }
                    })
                    .collect();
                let here: Vec<Intervals> = consistent.iter().map(|v| v[k].clone()).collect();
                let here_zones: Vec<Vec<super::mixed::MixedDoc>> =
                    zones.iter().map(|v| v[k].clone()).collect();
                ForensicFrequency {
                    frequency_hz: f,
                    omega_p: two_pi * f,
                    consistent_g: all,
                    mixed_g: super::mixed::combined(&here, &here_zones),
                    per_observation,
                }
            })
            .collect()
    }

    /// The bounds of the consistent amplitudes, g, over the frequencies, and
    /// the frequencies, Hz, where some are.
    fn pulse_bounds(frequencies: &[ForensicFrequency]) -> Bounds {
        let mut bounds = Bounds {
            min_g: None,
            max_g: None,
            frequency_hz: None,
            min_scale: None,
            max_scale: None,
        };
        for f in frequencies {
            if let (Some(first), Some(last)) = (f.consistent_g.first(), f.consistent_g.last()) {
                bounds.min_g = Some(bounds.min_g.map_or(first[0], |m| m.min(first[0])));
                bounds.max_g = Some(bounds.max_g.map_or(last[1], |m| m.max(last[1])));
                bounds.frequency_hz = Some(match bounds.frequency_hz {
                    None => [f.frequency_hz, f.frequency_hz],
                    Some([lo, hi]) => [lo.min(f.frequency_hz), hi.max(f.frequency_hz)],
                });
            }
        }
        bounds
    }
}
