//! Hazard curves: the annual rate λ(x) at which an intensity measure (PGA in
//! g, or PGV in m/s) exceeds x, tabulated and interpolated log-log; and the
//! annual rate at which a block with a lognormal fragility topples,
//!
//! λ_t = ∫ P(topple | x) |dλ(x)| = E[λ(X)],  X lognormal (median θ, β),
//!
//! (integration by parts: P(topple | 0) = 0 and λ(∞) = 0). Between two
//! points ln λ is linear in ln x, λ = λ_i (x/x_i)^s_i; beyond the table the
//! end segments' power laws continue. On each piece, with u = ln θ + βz,
//! ∫ φ(z) e^(a + bz) dz = e^(a + b²/2) [Φ(z₂ − b) − Φ(z₁ − b)], so λ_t is a
//! finite sum, exact for the interpolated curve: for a single power law
//! H(x) = k₀x^(−k) it is H(θ)·exp(k²β²/2) (Cornell et al. 2002).

use super::normal;

/// A hazard curve: intensities rising, annual exceedance rates falling.
#[derive(Clone, Debug, PartialEq)]
pub struct HazardCurve {
    /// (ln x, ln λ) at the tabulated points.
    log_points: Vec<(f64, f64)>,
}

/// Why a curve cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HazardError {
    /// Fewer than two points.
    #[error("a hazard curve needs at least two points")]
    TooFew,
    /// A point that is not positive and finite.
    #[error("point {0}: the intensity and the rate must be finite and > 0")]
    NotPositive(usize),
    /// Intensities not rising or rates not falling.
    #[error("point {0}: intensities must rise and rates fall from one point to the next")]
    NotMonotone(usize),
}

/// The annual toppling rate and how much of it the curve's extrapolation gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopplingRate {
    /// λ_t, 1/yr.
    pub rate: f64,
    /// The share of λ_t from intensities outside the tabulated range.
    pub extrapolated_share: f64,
}

impl HazardCurve {
    /// A curve through `points` (intensity, annual exceedance rate).
    pub fn new(points: &[[f64; 2]]) -> Result<Self, HazardError> {
        if points.len() < 2 {
            return Err(HazardError::TooFew);
        }
        let mut log_points = Vec::with_capacity(points.len());
        for (i, &[x, rate]) in points.iter().enumerate() {
            if !(x.is_finite() && x > 0.0 && rate.is_finite() && rate > 0.0) {
                return Err(HazardError::NotPositive(i));
            }
            if let Some(&(u, l)) = log_points.last()
                && !(x.ln() > u && rate.ln() < l)
            {
                return Err(HazardError::NotMonotone(i));
            }
            log_points.push((x.ln(), rate.ln()));
        }
        Ok(HazardCurve { log_points })
    }

    /// Slope of ln λ against ln x on segment `i` (clamped to the ends).
    fn slope(&self, i: usize) -> f64 {
        let i = i.min(self.log_points.len() - 2);
        let (u0, l0) = self.log_points[i];
        let (u1, l1) = self.log_points[i + 1];
        (l1 - l0) / (u1 - u0)
    }

    /// λ(x): the annual rate of exceeding `x`.
    pub fn rate(&self, x: f64) -> f64 {
        let u = x.ln();
        let n = self.log_points.len();
        let i = self.log_points[1..n - 1]
            .iter()
            .take_while(|p| p.0 <= u)
            .count();
        let (ui, li) = self.log_points[i];
        (li + self.slope(i) * (u - ui)).exp()
    }

    /// The annual rate at which a block of lognormal fragility (median
    /// `median`, dispersion `beta`) topples; `beta` = 0 is a sharp threshold.
    pub fn toppling_rate(&self, median: f64, beta: f64) -> TopplingRate {
        if beta == 0.0 {
            let (lo, hi) = self.range();
            let inside = (lo..=hi).contains(&median);
            return TopplingRate {
                rate: self.rate(median),
                extrapolated_share: if inside { 0.0 } else { 1.0 },
            };
        }
        let mu = median.ln();
        let n = self.log_points.len();
        // Breaks in z, and the law on each piece (its segment).
        let z: Vec<f64> = self.log_points.iter().map(|p| (p.0 - mu) / beta).collect();
        let piece = |seg: usize, z_lo: f64, z_hi: f64| -> f64 {
            let (ui, li) = self.log_points[seg.min(n - 1)];
            let s = self.slope(seg);
            let (a, b) = (li + s * (mu - ui), s * beta);
            (a + 0.5 * b * b).exp() * normal::between(z_lo - b, z_hi - b)
        };
        let below = piece(0, f64::NEG_INFINITY, z[0]);
        let above = piece(n - 2, z[n - 1], f64::INFINITY);
        let inside: f64 = (0..n - 1).map(|i| piece(i, z[i], z[i + 1])).sum();
        let rate = below + inside + above;
        TopplingRate {
            rate,
            extrapolated_share: if rate > 0.0 {
                (below + above) / rate
            } else {
                0.0
            },
        }
    }

    /// The tabulated intensities' range.
    pub fn range(&self) -> (f64, f64) {
        let n = self.log_points.len();
        (self.log_points[0].0.exp(), self.log_points[n - 1].0.exp())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// H(x) = H(0.4 g)·(x/0.4)^(−k), tabulated at `xs`.
    fn power_law(k: f64, xs: &[f64]) -> HazardCurve {
        let points: Vec<[f64; 2]> = xs
            .iter()
            .map(|&x| [x, 1e-4 * (x / 0.4f64).powf(-k)])
            .collect();
        HazardCurve::new(&points).expect("valid")
    }

    #[test]
    fn cornells_closed_form_for_a_power_law() {
        let h = power_law(2.5, &[0.05, 0.1, 0.2, 0.4, 0.8, 1.6]);
        let t = h.toppling_rate(0.38, 0.38);
        // H(θ)·exp(k²β²/2) = 1.7850e-4 /yr.
        let expected = 1e-4 * (0.38f64 / 0.4).powf(-2.5) * (2.5f64 * 2.5 * 0.38 * 0.38 / 2.0).exp();
        assert!(
            (t.rate / expected - 1.0).abs() < 1e-12,
            "{} vs {expected}",
            t.rate
        );
        assert!((t.rate - 1.785e-4).abs() < 5e-8, "{}", t.rate);
        // Two points are the same power law everywhere.
        let two = power_law(2.5, &[0.1, 1.0]).toppling_rate(0.38, 0.38);
        assert!((two.rate / expected - 1.0).abs() < 1e-12);
        assert!(two.extrapolated_share > t.extrapolated_share);
    }

    #[test]
    fn a_kinked_curve_against_quadrature() {
        let h = HazardCurve::new(&[
            [0.05, 2e-2],
            [0.1, 6e-3],
            [0.3, 4e-4],
            [0.6, 3e-5],
            [1.2, 1e-6],
        ])
        .expect("valid");
        let (theta, beta) = (0.35, 0.45);
        // E[λ(X)] by composite Simpson over z in [−12, 12], piece by piece
        // between the curve's kinks.
        let f = |z: f64| normal::pdf(z) * h.rate(theta * (beta * z).exp());
        let mut cuts = vec![-12.0];
        cuts.extend(
            [0.05f64, 0.1, 0.3, 0.6, 1.2]
                .iter()
                .map(|x| (x / theta).ln() / beta)
                .filter(|z| z.abs() < 12.0),
        );
        cuts.push(12.0);
        let mut quadrature = 0.0;
        for w in cuts.windows(2) {
            let n = 4_000;
            let hz = (w[1] - w[0]) / n as f64;
            let mut sum = f(w[0]) + f(w[1]);
            for k in 1..n {
                sum += if k % 2 == 1 { 4.0 } else { 2.0 } * f(w[0] + k as f64 * hz);
            }
            quadrature += sum * hz / 3.0;
        }
        let t = h.toppling_rate(theta, beta);
        assert!(
            (t.rate / quadrature - 1.0).abs() < 1e-9,
            "{} vs {quadrature}",
            t.rate
        );
        // A sharp threshold is the curve's value there.
        assert!((h.toppling_rate(0.3, 0.0).rate - 4e-4).abs() < 1e-18);
    }

    #[test]
    fn curves_that_are_not_curves_are_refused() {
        assert_eq!(HazardCurve::new(&[[0.1, 1e-3]]), Err(HazardError::TooFew));
        assert_eq!(
            HazardCurve::new(&[[0.1, 1e-3], [0.2, 2e-3]]),
            Err(HazardError::NotMonotone(1))
        );
        assert_eq!(
            HazardCurve::new(&[[0.1, 1e-3], [0.0, 1e-4]]),
            Err(HazardError::NotPositive(1))
        );
    }
}
