//! The standard normal law, by the complementary error function (libm, the musl port: within an ulp or two), so
//! that tail probabilities keep their relative precision.

use libm::erfc;

/// Φ(z) = P(Z ≤ z).
pub fn cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// 1 − Φ(z) = P(Z > z), without cancellation for large z.
pub fn sf(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Φ(b) − Φ(a) for a ≤ b, from the tail on the side both lie on.
pub fn between(a: f64, b: f64) -> f64 {
    if a >= 0.0 {
        sf(a) - sf(b)
    } else {
        cdf(b) - cdf(a)
    }
}

/// The standard normal density φ(z).
pub fn pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// Φ⁻¹(p) for 0 < p < 1: Newton (Halley) steps on Φ from a tail-aware
/// start, on the side of the smaller tail, to full precision.
pub fn quantile(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    // Solve on the lower tail: q = min(p, 1 − p), z ≤ 0, then mirror.
    let (q, sign) = if p < 0.5 { (p, -1.0) } else { (1.0 - p, 1.0) };
    // Start: the tail's asymptote (Abramowitz & Stegun 26.2.23).
    let t = (-2.0 * q.ln()).sqrt();
    let mut z = -(t
        - (2.515_517 + 0.802_853 * t + 0.010_328 * t * t)
            / (1.0 + 1.432_788 * t + 0.189_269 * t * t + 0.001_308 * t * t * t));
    for _ in 0..6 {
        let f = cdf(z) - q;
        let d = pdf(z);
        if d == 0.0 {
            break;
        }
        // Halley: Φ'' = −zφ.
        let step = f / d;
        let dz = step / (1.0 + 0.5 * z * step);
        z -= dz;
        if dz.abs() <= 1e-15 * z.abs().max(1e-300) {
            break;
        }
    }
    sign * -z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quantile_inverts_the_cdf() {
        assert!((quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-14);
        assert!(quantile(0.5).abs() < 1e-15);
        for p in [1e-300, 1e-20, 1e-8, 0.01, 0.3, 0.7, 0.99, 1.0 - 1e-12] {
            let z = quantile(p);
            let back = if p < 0.5 { cdf(z) } else { 1.0 - sf(z) };
            assert!((back / p - 1.0).abs() < 1e-12, "{p}: {z} → {back}");
        }
    }

    #[test]
    fn known_values_and_tails() {
        assert!((cdf(0.0) - 0.5).abs() < 1e-16);
        let c = cdf(1.959_963_984_540_054);
        assert!((c - 0.975).abs() < 1e-15, "{c:e}");
        // Far tails keep relative precision: P(Z > 10) = 7.6198530241605e-24.
        assert!((sf(10.0) / 7.619_853_024_160_527e-24 - 1.0).abs() < 1e-12);
        assert!((between(9.0, 10.0) / (sf(9.0) - sf(10.0)) - 1.0).abs() < 1e-15);
        assert!((between(-1.0, 1.0) - 0.682_689_492_137_085_9).abs() < 1e-15);
    }
}
