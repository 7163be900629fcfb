//! A random-like ground motion for tests and benchmarks, with no dependency:
//! 24 sines of log-uniform frequency in [f_lo, f_hi] Hz, random phase and
//! weight (from a 64-bit linear congruential generator with Knuth's MMIX
//! constants, reproducible from a seed), ramped in over the first tenth and
//! scaled to a peak.

/// `n` samples at `dt`, peak `peak` (m/s²).
pub fn synthetic(seed: u64, n: usize, dt: f64, peak: f64, f_lo: f64, f_hi: f64) -> Vec<f64> {
    let mut state = seed;
    let mut uniform = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let components: Vec<(f64, f64, f64)> = (0..24)
        .map(|_| {
            let f = f_lo * (f_hi / f_lo).powf(uniform());
            let phase = std::f64::consts::TAU * uniform();
            (std::f64::consts::TAU * f, phase, 0.5 + uniform())
        })
        .collect();
    let ramp = 0.1 * n as f64 * dt;
    let raw: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let sum: f64 = components
                .iter()
                .map(|(w, phase, weight)| weight * (w * t + phase).sin())
                .sum();
            (t / ramp).min(1.0) * sum
        })
        .collect();
    let max = raw.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    raw.iter().map(|a| peak * a / max).collect()
}
