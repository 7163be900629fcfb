//! The ground motion of a time-history spec as a figure draws it: a
//! cycloidal pulse evaluated in closed form (smooth at any zoom), or a
//! recorded ground motion by its samples.

use std::sync::Arc;

use crate::dynamics::Pulse;
use crate::kinds::time_history::TimeHistoryJob;

/// Samples of a pulse across any drawn time span.
const PULSE_SAMPLES: u32 = 1200;
/// A record with more samples in a drawn span is drawn by the least and
/// largest sample of about this many buckets.
const RECORD_BUCKETS: usize = 2000;

/// The ground motion of a time-history spec.
pub enum Motion {
    /// A pulse (boxed: a wavelet carries its list of extrema).
    Pulse(Box<Pulse>),
    /// A record: samples (m/s²) every `dt` s, linear in between.
    Record {
        /// Sampling interval, s.
        dt: f64,
        /// Accelerations, m/s².
        acc: Arc<[f64]>,
    },
}

impl Motion {
    /// The ground motion of `spec`, if it names one the figure can draw.
    pub fn of(spec: &TimeHistoryJob) -> Option<Motion> {
        if let Some(g) = &spec.ground_motion {
            let dt = Some(g.dt).filter(|dt| *dt > 0.0)?;
            return (g.acc.len() >= 2).then(|| Motion::Record {
                dt,
                acc: g.acc.clone(),
            });
        }
        let pulse = spec.pulse.as_ref()?;
        Pulse::new(pulse.shape, pulse.a_p, pulse.omega_p)
            .ok()
            .map(|p| Motion::Pulse(Box::new(p)))
    }

    /// When the ground stops moving, s.
    pub fn duration(&self) -> f64 {
        match self {
            Motion::Pulse(p) => p.duration,
            Motion::Record { dt, acc } => dt * (acc.len() - 1) as f64,
        }
    }

    /// The largest |ü_g|, m/s² (a record's; a pulse's is its a_p).
    pub fn peak(&self) -> f64 {
        match self {
            Motion::Pulse(p) => (0..=PULSE_SAMPLES)
                .map(|k| {
                    p.acceleration(p.duration * f64::from(k) / f64::from(PULSE_SAMPLES))
                        .abs()
                })
                .fold(0.0, f64::max),
            Motion::Record { acc, .. } => acc.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        }
    }

    /// ü_g/g over [t0, t1]: a pulse sampled finely over its duration, a
    /// record by its samples, or by the least and largest sample of each
    /// bucket when it has many more than a figure shows (no peak is lost).
    /// The ground is still outside the motion.
    pub fn curve(&self, t0: f64, t1: f64, g: f64) -> Vec<(f64, f64)> {
        match self {
            Motion::Pulse(p) => {
                let (a, b) = (t0.max(0.0), t1.min(p.duration));
                let mut out = Vec::new();
                if t0 < a {
                    out.push((t0, 0.0));
                }
                if a < b {
                    out.extend((0..=PULSE_SAMPLES).map(|k| {
                        let t = a + (b - a) * f64::from(k) / f64::from(PULSE_SAMPLES);
                        (t, p.acceleration(t) / g)
                    }));
                }
                if b < t1 {
                    out.push((b.max(t0), 0.0));
                    out.push((t1, 0.0));
                }
                out
            }
            Motion::Record { dt, acc } => record_curve(*dt, acc, t0, t1, g),
        }
    }
}

/// The vertical ground acceleration ü_v (positive up) of a time-history
/// spec, as a figure draws it beside the horizontal [`Motion`].
pub enum Vertical {
    /// ü_v = r·ü_g.
    Ratio(f64),
    /// A motion of its own (a pulse, or a record's vertical samples),
    /// starting `delay` s after the horizontal one.
    Own {
        /// The vertical motion, in its own time.
        motion: Motion,
        /// Its start, s.
        delay: f64,
    },
}

impl Vertical {
    /// The vertical motion of `spec`, if it has one the figure can draw.
    pub fn of(spec: &TimeHistoryJob) -> Option<Vertical> {
        use crate::jobs::vertical::VerticalPulseNorm;
        if let Some(g) = &spec.ground_motion {
            let v = g.vertical.as_ref()?;
            return match (&v.acc, v.ratio) {
                (Some(acc), _) => (acc.len() >= 2 && g.dt > 0.0).then(|| Vertical::Own {
                    motion: Motion::Record {
                        dt: g.dt,
                        acc: acc.clone(),
                    },
                    delay: 0.0,
                }),
                (None, Some(r)) => Some(Vertical::Ratio(r)),
                (None, None) => None,
            };
        }
        match spec.vertical.as_ref()? {
            VerticalPulseNorm::Ratio(r) => Some(Vertical::Ratio(*r)),
            VerticalPulseNorm::Pulse { pulse, delay_s } => {
                Pulse::new(pulse.shape, pulse.a_p, pulse.omega_p)
                    .ok()
                    .map(|p| Vertical::Own {
                        motion: Motion::Pulse(Box::new(p)),
                        delay: *delay_s,
                    })
            }
            VerticalPulseNorm::Scaled(_) => None,
        }
    }

    /// When the vertical ground stops moving, s (under `horizontal`).
    pub fn end(&self, horizontal: &Motion) -> f64 {
        match self {
            Vertical::Ratio(_) => horizontal.duration(),
            Vertical::Own { motion, delay } => delay + motion.duration(),
        }
    }

    /// The largest |ü_v|, m/s² (under `horizontal`).
    pub fn peak(&self, horizontal: &Motion) -> f64 {
        match self {
            Vertical::Ratio(r) => r.abs() * horizontal.peak(),
            Vertical::Own { motion, .. } => motion.peak(),
        }
    }

    /// ü_v/g over [t0, t1] (under `horizontal`), drawn as [`Motion::curve`]
    /// draws ü_g/g.
    pub fn curve(&self, horizontal: &Motion, t0: f64, t1: f64, g: f64) -> Vec<(f64, f64)> {
        match self {
            Vertical::Ratio(r) => horizontal
                .curve(t0, t1, g)
                .into_iter()
                .map(|(t, a)| (t, r * a))
                .collect(),
            // In its own time: still ground before it starts, then a step
            // to its first value.
            Vertical::Own { motion, delay } => {
                let mut out: Vec<(f64, f64)> = motion
                    .curve(t0 - delay, t1 - delay, g)
                    .into_iter()
                    .map(|(t, a)| (t + delay, a))
                    .collect();
                if let Some(k) = out.iter().position(|p| p.0 >= *delay)
                    && k > 0
                    && out[k].1 != 0.0
                {
                    out.insert(k, (*delay, 0.0));
                }
                out
            }
        }
    }
}

/// A record's samples over [t0, t1] (the two samples around each end
/// included, so the drawn line reaches the ends), ü_g/g.
fn record_curve(dt: f64, acc: &[f64], t0: f64, t1: f64, g: f64) -> Vec<(f64, f64)> {
    let last = acc.len() - 1;
    let index = |t: f64| ((t / dt).max(0.0) as usize).min(last);
    let first = index(t0);
    let end = (index(t1) + 1).min(last);
    let mut out = Vec::new();
    if t0 < 0.0 {
        out.push((t0, 0.0));
        out.push((0.0, 0.0));
    }
    if first <= end {
        let n = end - first + 1;
        let bucket = n.div_ceil(RECORD_BUCKETS).max(1);
        for (b, chunk) in acc[first..=end].chunks(bucket).enumerate() {
            let start = first + b * bucket;
            if bucket == 1 {
                out.push((start as f64 * dt, chunk[0] / g));
                continue;
            }
            let (lo, hi) = chunk.iter().enumerate().fold(
                ((0, f64::INFINITY), (0, f64::NEG_INFINITY)),
                |(lo, hi), (k, &v)| {
                    (
                        if v < lo.1 { (k, v) } else { lo },
                        if v > hi.1 { (k, v) } else { hi },
                    )
                },
            );
            let (a, b) = if lo.0 <= hi.0 { (lo, hi) } else { (hi, lo) };
            for (k, v) in [a, b] {
                out.push(((start + k) as f64 * dt, v / g));
            }
        }
    }
    // Still ground after the record ends.
    let stop = last as f64 * dt;
    if t1 > stop {
        out.push((stop.max(t0), 0.0));
        out.push((t1, 0.0));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::time_history::TimeHistorySpec;
    use serde_json::json;

    /// The validated time-history job of the spec `doc`.
    fn job(doc: serde_json::Value) -> TimeHistoryJob {
        use crate::jobs::kind::Validate;
        serde_json::from_value::<TimeHistorySpec>(doc)
            .expect("a spec")
            .validate()
            .expect("a valid spec")
    }

    #[test]
    fn a_one_sine_pulse_lasts_one_period() {
        let spec = job(
            json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                              "pulse": {"type": "one_sine", "a_p": 7.4, "omega_p": 10.7}}),
        );
        let m = Motion::of(&spec).expect("pulse");
        assert!(matches!(m, Motion::Pulse(_)));
        assert!((m.duration() - std::f64::consts::TAU / 10.7).abs() < 1e-12);
        let c = m.curve(0.0, 1.0, 9.81);
        assert_eq!(c.len(), 1203);
        assert!(c.iter().all(|p| p.0 >= 0.0 && p.0 <= 1.0));
        // Ground still after the pulse.
        assert_eq!(c.last().map(|p| p.1), Some(0.0));
        assert!((m.peak() - 7.4).abs() < 1e-3, "{}", m.peak());
    }

    #[test]
    fn a_record_of_the_spec_is_its_samples() {
        let acc: Vec<f64> = (0..300).map(|k| (f64::from(k) * 0.1).sin() * 5.0).collect();
        let spec = job(
            json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                              "ground_motion": {"dt": 0.01, "acc": acc, "unit": "m/s2"}}),
        );
        let m = Motion::of(&spec).expect("record");
        let Motion::Record { dt, acc: samples } = &m else {
            panic!("a record");
        };
        assert_eq!((*dt, &samples[..]), (0.01, &acc[..]));
        assert!((m.duration() - 2.99).abs() < 1e-12);
        let peak = acc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert_eq!(m.peak(), peak);
        // Neither a pulse nor a record: nothing to draw.
        let mut bare = spec;
        bare.ground_motion = None;
        assert!(Motion::of(&bare).is_none());
    }

    #[test]
    fn a_vertical_motion_is_drawn_in_its_own_time_or_as_a_ratio() {
        let base = json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                          "pulse": {"type": "one_sine", "a_p": 7.4, "omega_p": 10.7}});
        let mut own = base.clone();
        own["vertical"] = json!({"type": "one_sine", "a_p": 3.0, "omega_p": 20.0, "delay_s": 0.25});
        let spec = job(own);
        let h = Motion::of(&spec).expect("pulse");
        let v = Vertical::of(&spec).expect("vertical");
        let pulse = Pulse::new(crate::dynamics::PulseShape::OneSine, 3.0, 20.0).expect("pulse");
        assert!((v.end(&h) - (0.25 + pulse.duration)).abs() < 1e-12);
        let c = v.curve(&h, 0.0, 1.0, 2.0);
        assert!(c.iter().any(|p| p.1 != 0.0));
        for &(t, a) in &c {
            let expected = if (0.25..=0.25 + pulse.duration).contains(&t) {
                pulse.acceleration(t - 0.25) / 2.0
            } else {
                0.0
            };
            assert!((a - expected).abs() < 1e-9, "t = {t}: {a} vs {expected}");
        }
        assert_eq!(c.first().map(|p| p.0), Some(0.0));
        assert_eq!(c.last(), Some(&(1.0, 0.0)));
        // A pulse starting at its amplitude steps up where it starts.
        let mut cosine = base.clone();
        cosine["vertical"] =
            json!({"type": "one_cosine", "a_p": 3.0, "omega_p": 20.0, "delay_s": 0.25});
        let c = Vertical::of(&job(cosine))
            .expect("vertical")
            .curve(&h, 0.0, 1.0, 2.0);
        let k = c.iter().position(|p| p.1 != 0.0).expect("moves");
        assert_eq!(c[k - 1], (0.25, 0.0));
        assert!(
            (c[k].0 - 0.25).abs() < 1e-12 && (c[k].1 - 1.5).abs() < 1e-12,
            "{:?}",
            c[k]
        );
        // A ratio: the horizontal curve scaled.
        let mut ratio = base;
        ratio["vertical"] = json!({"ratio": -0.5});
        let spec = job(ratio);
        let v = Vertical::of(&spec).expect("vertical");
        let scaled: Vec<(f64, f64)> = h
            .curve(0.0, 1.0, 2.0)
            .into_iter()
            .map(|(t, a)| (t, -0.5 * a))
            .collect();
        assert_eq!(v.curve(&h, 0.0, 1.0, 2.0), scaled);
        assert_eq!(v.peak(&h), 0.5 * h.peak());
        // None without one.
        assert!(
            Vertical::of(&job(json!({"kind": "time_history",
            "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "a_p": 7.4, "omega_p": 10.7}})))
            .is_none()
        );
    }

    #[test]
    fn a_record_is_drawn_by_its_samples_inside_a_span() {
        let acc: Vec<f64> = (0..300).map(|k| f64::from(k) * 0.01).collect();
        let m = Motion::Record {
            dt: 0.01,
            acc: acc.into(),
        };
        assert!((m.duration() - 2.99).abs() < 1e-12);
        let c = m.curve(1.0, 1.5, 1.0);
        assert!(c.first().is_some_and(|p| p.0 <= 1.0), "{c:?}");
        assert!(c.iter().all(|p| p.0 >= 0.99 && p.0 <= 1.52), "{c:?}");
        // After its end the ground is still.
        let tail = m.curve(2.5, 4.0, 1.0);
        assert_eq!(tail.last(), Some(&(4.0, 0.0)));
    }
}
