//! Peak ground acceleration, velocity and displacement (PGA, PGV, PGD) of a
//! ground motion from rest, exactly: for a pulse from its closed-form
//! integrals, for a record (piecewise linear in acceleration) from the
//! quadratic velocity and cubic displacement of each piece. Fragility of
//! precariously balanced rocks is read in PGA and PGV/PGA.

use super::excitation::Pulse;
use super::forcing::Record;

/// The peaks of a ground motion, SI units, over its duration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundPeaks {
    /// max |ü_g|, m/s².
    pub pga: f64,
    /// max |u̇_g|, m/s.
    pub pgv: f64,
    /// max |u_g|, m.
    pub pgd: f64,
}

/// The peaks of `pulse` (from rest).
pub fn of_pulse(pulse: &Pulse) -> GroundPeaks {
    GroundPeaks {
        pga: pulse.amplitude.abs(),
        pgv: pulse.peak_velocity(),
        pgd: pulse.peak_displacement(),
    }
}

/// The peaks of `record` (from rest, linear between samples).
pub fn of_record(record: &Record) -> GroundPeaks {
    let a = record.samples();
    let dt = record.dt();
    let (mut v, mut u) = (0.0f64, 0.0f64);
    let mut peaks = GroundPeaks {
        pga: a.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        pgv: 0.0,
        pgd: 0.0,
    };
    for w in a.windows(2) {
        let (a0, a1) = (w[0], w[1]);
        let slope = (a1 - a0) / dt;
        // On the piece, with s ∈ [0, dt]: a = a0 + slope s,
        // v = v + a0 s + slope s²/2, u = u + v s + a0 s²/2 + slope s³/6.
        let vel = |s: f64| v + a0 * s + 0.5 * slope * s * s;
        let disp = |s: f64| u + v * s + 0.5 * a0 * s * s + slope * s * s * s / 6.0;
        // Velocity peaks where a = 0 inside the piece.
        if a0 * a1 < 0.0 {
            let s = a0 / (a0 - a1) * dt;
            peaks.pgv = peaks.pgv.max(vel(s).abs());
        }
        // Displacement peaks where v = 0 inside the piece.
        for s in quadratic_roots(0.5 * slope, a0, v).into_iter().flatten() {
            if s > 0.0 && s < dt {
                peaks.pgd = peaks.pgd.max(disp(s).abs());
            }
        }
        let (v1, u1) = (vel(dt), disp(dt));
        v = v1;
        u = u1;
        peaks.pgv = peaks.pgv.max(v.abs());
        peaks.pgd = peaks.pgd.max(u.abs());
    }
    peaks
}

/// Real roots of c2 s² + c1 s + c0 (none, one or two), without allocating:
/// a record's peaks look at every sample interval.
fn quadratic_roots(c2: f64, c1: f64, c0: f64) -> [Option<f64>; 2] {
    if c2 == 0.0 {
        return [(c1 != 0.0).then(|| -c0 / c1), None];
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        return [None, None];
    }
    // The stable pair: q = −(c1 + sign(c1)√disc)/2, roots q/c2 and c0/q.
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [Some(q / c2), Some(c0 / q)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::PulseShape;
    use std::f64::consts::PI;
    use std::sync::Arc;

    /// A one-sine pulse sampled finely: the record's peaks are the pulse's
    /// (v peaks at 2a/ω mid-pulse, u at the end, 2πa/ω²), to the sampling
    /// error of a piecewise-linear acceleration.
    #[test]
    fn a_sampled_pulse_has_the_pulses_peaks() {
        for shape in [
            PulseShape::OneSine,
            PulseShape::OneCosine,
            PulseShape::Cn(1),
            PulseShape::HalfSine,
        ] {
            let pulse = Pulse::new(shape, 3.0, 2.0 * PI).expect("valid");
            let n = 40_000;
            let dt = pulse.duration / n as f64;
            let samples: Vec<f64> = (0..=n).map(|k| pulse.acceleration(k as f64 * dt)).collect();
            let record = Record::new(Arc::from(samples), dt).expect("valid");
            let (p, r) = (of_pulse(&pulse), of_record(&record));
            // The crest falls between samples: the sampled PGA is lower by O((ω dt)²).
            assert!(
                ((p.pga - r.pga) / p.pga).abs() < 1e-7,
                "{shape:?}: {p:?} {r:?}"
            );
            assert!(
                ((p.pgv - r.pgv) / p.pgv).abs() < 1e-7,
                "{shape:?}: {p:?} {r:?}"
            );
            assert!(
                ((p.pgd - r.pgd) / p.pgd).abs() < 1e-7,
                "{shape:?}: {p:?} {r:?}"
            );
        }
        let sine = of_pulse(&Pulse::new(PulseShape::OneSine, 3.0, 2.0 * PI).expect("valid"));
        assert!((sine.pgv - 2.0 * 3.0 / (2.0 * PI)).abs() < 1e-12);
        assert!((sine.pgd - 3.0 / (2.0 * PI)).abs() < 1e-12);
    }

    /// A record of two samples (a ramp from 0 to a over dt): v = a dt/2,
    /// u = a dt²/6 at its end.
    #[test]
    fn a_ramp_integrates_exactly() {
        let r = of_record(&Record::new(Arc::from(vec![0.0, 4.0]), 0.5).expect("valid"));
        assert_eq!(r.pga, 4.0);
        assert!((r.pgv - 1.0).abs() < 1e-15);
        assert!((r.pgd - 4.0 * 0.25 / 6.0).abs() < 1e-15);
    }
}
