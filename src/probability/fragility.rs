//! Fragility from counts: the Wilson interval of a stripe's probability of
//! toppling, and the lognormal fragility P(topple | x) = Φ(ln(x/θ)/β) fitted
//! to several stripes by maximum likelihood (Baker 2015's multiple-stripe
//! method), with a parametric bootstrap for its uncertainty.

use super::normal;

/// One stripe: intensity, simulations, topplings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stripe {
    /// Intensity (g or m/s).
    pub im: f64,
    /// Simulations.
    pub n: u64,
    /// How many toppled.
    pub k: u64,
}

/// The Wilson score interval of k successes in n at normal quantile `z`
/// (1.959964 for 95 %).
pub fn wilson(k: u64, n: u64, z: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (n, p) = (n as f64, k as f64 / n as f64);
    let z2 = z * z;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = z / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// ln L(θ, β) = Σ k ln Φ(u) + (n − k) ln(1 − Φ(u)), u = ln(x/θ)/β.
pub fn log_likelihood(theta: f64, beta: f64, stripes: &[Stripe]) -> f64 {
    stripes
        .iter()
        .map(|s| {
            let u = (s.im / theta).ln() / beta;
            let (p, q) = (normal::cdf(u), normal::sf(u));
            let term = |count: u64, prob: f64| {
                if count == 0 {
                    0.0
                } else {
                    count as f64 * prob.max(f64::MIN_POSITIVE).ln()
                }
            };
            term(s.k, p) + term(s.n - s.k, q)
        })
        .sum()
}

/// Nelder–Mead minimisation of `f` on the plane from `start` with initial
/// `step`, to a simplex smaller than `tol`.
fn nelder_mead<F: Fn([f64; 2]) -> f64>(f: F, start: [f64; 2], step: f64, tol: f64) -> [f64; 2] {
    let mut s = [
        start,
        [start[0] + step, start[1]],
        [start[0], start[1] + step],
    ];
    let mut v = s.map(&f);
    for _ in 0..2_000 {
        // Order: best first.
        let mut idx = [0, 1, 2];
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        s = idx.map(|i| s[i]);
        v = idx.map(|i| v[i]);
        let size = (0..2)
            .map(|d| (s[1][d] - s[0][d]).abs().max((s[2][d] - s[0][d]).abs()))
            .fold(0.0, f64::max);
        if size < tol {
            break;
        }
        let c = [0.5 * (s[0][0] + s[1][0]), 0.5 * (s[0][1] + s[1][1])];
        let at = |t: f64| [c[0] + t * (s[2][0] - c[0]), c[1] + t * (s[2][1] - c[1])];
        let r = at(-1.0);
        let fr = f(r);
        if fr < v[0] {
            let e = at(-2.0);
            let fe = f(e);
            (s[2], v[2]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < v[1] {
            (s[2], v[2]) = (r, fr);
        } else {
            let k = if fr < v[2] { at(-0.5) } else { at(0.5) };
            let fk = f(k);
            if fk < v[2].min(fr) {
                (s[2], v[2]) = (k, fk);
            } else {
                for i in 1..3 {
                    s[i] = [0.5 * (s[0][0] + s[i][0]), 0.5 * (s[0][1] + s[i][1])];
                    v[i] = f(s[i]);
                }
            }
        }
    }
    s[0]
}

/// The maximum-likelihood lognormal (θ, β), or `None` when the counts do
/// not bound it (no stripe with toppled and standing cases between an
/// all-standing one below and an all-toppled one above is enough: every
/// stripe all standing, or all toppled, or a step with no spread).
pub fn fit_lognormal(stripes: &[Stripe]) -> Option<(f64, f64)> {
    let mixed = stripes.iter().any(|s| s.k > 0 && s.k < s.n);
    let lowest_topple = stripes
        .iter()
        .filter(|s| s.k > 0)
        .map(|s| s.im)
        .fold(f64::INFINITY, f64::min);
    let highest_stand = stripes
        .iter()
        .filter(|s| s.k < s.n)
        .map(|s| s.im)
        .fold(0.0, f64::max);
    // Without overlap of toppled and standing cases the likelihood grows as β → 0.
    if !mixed && lowest_topple > highest_stand {
        return None;
    }
    if stripes.iter().all(|s| s.k == 0) || stripes.iter().all(|s| s.k == s.n) {
        return None;
    }
    // Start at the stripes' geometric centre, β = 0.5.
    let total: f64 = stripes.iter().map(|s| s.n as f64).sum();
    let centre = stripes.iter().map(|s| s.n as f64 * s.im.ln()).sum::<f64>() / total;
    let best = nelder_mead(
        |[ln_theta, ln_beta]| -log_likelihood(ln_theta.exp(), ln_beta.exp(), stripes),
        [centre, 0.5f64.ln()],
        0.3,
        1e-10,
    );
    let (theta, beta) = (best[0].exp(), best[1].exp());
    (theta.is_finite() && beta.is_finite() && beta > 1e-6 && beta < 50.0).then_some((theta, beta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_its_formula() {
        // 5 of 20 at 95 %: (0.1119, 0.4687).
        let (lo, hi) = wilson(5, 20, 1.959_964);
        assert!(
            (lo - 0.111_86).abs() < 1e-4 && (hi - 0.468_71).abs() < 1e-4,
            "{lo} {hi}"
        );
        let (lo, hi) = wilson(0, 10, 1.959_964);
        assert_eq!(lo, 0.0);
        assert!((hi - 0.277_53).abs() < 1e-4, "{hi}");
    }

    #[test]
    fn the_mle_recovers_the_fragility_from_expected_counts() {
        // Counts equal to their expectations: the MLE is (θ, β) exactly.
        let (theta, beta) = (0.38f64, 0.38f64);
        let stripes: Vec<Stripe> = [0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 0.9]
            .iter()
            .map(|&im| {
                let n = 1_000_000u64;
                let p = normal::cdf((im / theta).ln() / beta);
                Stripe {
                    im,
                    n,
                    k: (p * n as f64).round() as u64,
                }
            })
            .collect();
        let (t, b) = fit_lognormal(&stripes).expect("fits");
        assert!(
            (t / theta - 1.0).abs() < 1e-4 && (b / beta - 1.0).abs() < 1e-3,
            "{t} {b}"
        );
        // No overlap: no fit.
        let step = [
            Stripe {
                im: 0.1,
                n: 10,
                k: 0,
            },
            Stripe {
                im: 0.2,
                n: 10,
                k: 10,
            },
        ];
        assert_eq!(fit_lognormal(&step), None);
    }
}
