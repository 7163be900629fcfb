//! Distributions of uncertain inputs: normal (optionally truncated),
//! lognormal and uniform; expectations by quadrature.

use super::normal;

/// A distribution of one uncertain quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Normal, truncated to `[min, max]` (either may be infinite).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation (> 0).
        sd: f64,
        /// Lower truncation.
        min: f64,
        /// Upper truncation.
        max: f64,
    },
    /// Lognormal: ln X normal with mean ln(median) and deviation beta.
    LogNormal {
        /// Median (> 0).
        median: f64,
        /// Dispersion β (> 0).
        beta: f64,
    },
    /// Uniform on `[min, max]`.
    Uniform {
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
}

/// Composite Simpson on `[a, b]` with `n` (even) intervals.
fn simpson<F: Fn(f64) -> f64>(a: f64, b: f64, n: usize, f: F) -> f64 {
    let h = (b - a) / n as f64;
    let mut sum = f(a) + f(b);
    for k in 1..n {
        sum += if k % 2 == 1 { 4.0 } else { 2.0 } * f(a + k as f64 * h);
    }
    sum * h / 3.0
}

/// Intervals of the quadratures (Simpson, error ∝ h⁴): smooth integrands
/// reach 1e-13 relative.
const PANELS: usize = 20_000;
/// Where a standard normal's tails are dropped (P(|Z| > 12) ≈ 4e-33).
const Z_MAX: f64 = 12.0;

impl Distribution {
    /// The smallest and largest values it can take.
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Distribution::Normal { min, max, .. } => (min, max),
            Distribution::LogNormal { .. } => (0.0, f64::INFINITY),
            Distribution::Uniform { min, max } => (min, max),
        }
    }

    /// The median.
    pub fn median(&self) -> f64 {
        match *self {
            Distribution::Normal { mean, sd, min, max } => {
                let (a, b) = ((min - mean) / sd, (max - mean) / sd);
                let target = 0.5 * (normal::cdf(a) + normal::cdf(b));
                // Bisection on the truncated law's CDF.
                let (mut lo, mut hi) = (a.max(-Z_MAX), b.min(Z_MAX));
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if normal::cdf(mid) < target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                mean + sd * 0.5 * (lo + hi)
            }
            Distribution::LogNormal { median, .. } => median,
            Distribution::Uniform { min, max } => 0.5 * (min + max),
        }
    }

    /// The value at probability `u` ∈ (0, 1) of the law (its inverse CDF):
    /// a uniform `u` gives a sample.
    pub fn sample(&self, u: f64) -> f64 {
        match *self {
            Distribution::Normal { mean, sd, min, max } => {
                let (a, b) = ((min - mean) / sd, (max - mean) / sd);
                // On the side of the lighter tail, so that deep truncations
                // keep their precision.
                let z = if a > 0.0 {
                    let (sa, sb) = (normal::sf(a), normal::sf(b));
                    -normal::quantile(sa - u * (sa - sb))
                } else {
                    let (ca, cb) = (normal::cdf(a), normal::cdf(b));
                    normal::quantile(ca + u * (cb - ca))
                };
                (mean + sd * z).clamp(min, max)
            }
            Distribution::LogNormal { median, beta } => median * (beta * normal::quantile(u)).exp(),
            Distribution::Uniform { min, max } => min + u * (max - min),
        }
    }

    /// E[f(X)].
    pub fn expect<F: Fn(f64) -> f64>(&self, f: F) -> f64 {
        match *self {
            Distribution::Normal { mean, sd, min, max } => {
                let a = ((min - mean) / sd).max(-Z_MAX);
                let b = ((max - mean) / sd).min(Z_MAX);
                let mass = normal::between(a, b);
                simpson(a, b, PANELS, |z| normal::pdf(z) * f(mean + sd * z)) / mass
            }
            Distribution::LogNormal { median, beta } => simpson(-Z_MAX, Z_MAX, PANELS, |z| {
                normal::pdf(z) * f(median * (beta * z).exp())
            }),
            Distribution::Uniform { min, max } => {
                if max > min {
                    simpson(min, max, PANELS, f) / (max - min)
                } else {
                    f(min)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_the_law_and_stay_inside() {
        let t = Distribution::Normal {
            mean: 0.2,
            sd: 0.05,
            min: 0.15,
            max: 0.3,
        };
        let n = 20_000;
        let xs: Vec<f64> = (0..n)
            .map(|k| t.sample((k as f64 + 0.5) / n as f64))
            .collect();
        assert!(xs.iter().all(|x| (0.15..=0.3).contains(x)));
        let mean = xs.iter().sum::<f64>() / n as f64;
        assert!((mean - t.expect(|x| x)).abs() < 1e-6, "{mean}");
        let ln = Distribution::LogNormal {
            median: 3.0,
            beta: 0.4,
        };
        assert!((ln.sample(0.5) - 3.0).abs() < 1e-14);
        assert!((ln.sample(normal::cdf(1.0)) - 3.0 * 0.4f64.exp()).abs() < 1e-12);
        // A truncation deep in the upper tail.
        let deep = Distribution::Normal {
            mean: 0.0,
            sd: 1.0,
            min: 9.0,
            max: 10.0,
        };
        let x = deep.sample(0.5);
        assert!(x > 9.0 && x < 9.2, "{x}");
    }

    #[test]
    fn expectations_match_closed_forms() {
        let ln = Distribution::LogNormal {
            median: 2.0,
            beta: 0.5,
        };
        // E[X] = median·exp(β²/2).
        assert!((ln.expect(|x| x) / (2.0 * 0.125f64.exp()) - 1.0).abs() < 1e-12);
        let u = Distribution::Uniform { min: 1.0, max: 3.0 };
        // E[e^(−X)] = (e^(−1) − e^(−3))/2.
        let expected = 0.5 * ((-1.0f64).exp() - (-3.0f64).exp());
        assert!((u.expect(|x| (-x).exp()) / expected - 1.0).abs() < 1e-12);
        let n = Distribution::Normal {
            mean: 1.0,
            sd: 0.2,
            min: f64::NEG_INFINITY,
            max: f64::INFINITY,
        };
        assert!((n.expect(|x| x * x) - 1.04).abs() < 1e-12);
        // Truncated at the mean: the median is the 75th percentile.
        let half = Distribution::Normal {
            mean: 0.0,
            sd: 1.0,
            min: 0.0,
            max: f64::INFINITY,
        };
        assert!((half.median() - 0.674_489_750_196_081_7).abs() < 1e-12);
        let e = half.expect(|x| x);
        assert!(
            (e - (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-12,
            "{e:e}"
        );
    }
}
