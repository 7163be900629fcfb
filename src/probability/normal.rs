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

#[cfg(test)]
mod tests {
    use super::*;

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
