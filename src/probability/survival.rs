//! The survival of rocks of known age: with an annual toppling rate λ_t (a
//! Poisson process of topplings), a rock of age T still stands with
//! probability P_s = exp(−λ_t T); over an uncertain age, E[exp(−λ_t T)];
//! several rocks toppling independently all stand with the product. The rate
//! scale at 5 %: the factor s by which every hazard rate (λ → sλ, so
//! λ_t → sλ_t) must grow for P_s to fall to 5 %.

use super::distribution::Distribution;

/// A rock's age: known, or uncertain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Age {
    /// Years.
    Known(f64),
    /// A distribution, years.
    Uncertain(Distribution),
}

impl Age {
    /// P(still standing) at toppling rate `rate` (1/yr).
    pub fn survival(&self, rate: f64) -> f64 {
        match *self {
            Age::Known(t) => (-rate * t).exp(),
            Age::Uncertain(d) => d.expect(|t| (-rate * t.max(0.0)).exp()),
        }
    }
}

/// The factor s with Π P_s,i(s·λ_i) = `target` for rocks (λ_i, age_i), or
/// `None` when no finite factor does (every λ_i = 0, or too small).
pub fn rate_scale(rocks: &[(f64, Age)], target: f64) -> Option<f64> {
    let joint = |s: f64| -> f64 { rocks.iter().map(|(l, a)| a.survival(s * l)).product() };
    // Known ages only: a closed form.
    if rocks.iter().all(|(_, a)| matches!(a, Age::Known(_))) {
        let exposure: f64 = rocks
            .iter()
            .map(|(l, a)| match a {
                Age::Known(t) => l * t,
                Age::Uncertain(_) => 0.0,
            })
            .sum();
        return Some(-target.ln() / exposure).filter(|s| s.is_finite() && *s > 0.0);
    }
    if joint(1e300f64.sqrt()) > target {
        return None;
    }
    // Bracket in ln s, then bisect: P_s falls as s grows.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while joint(hi.exp()) > target {
        lo = hi;
        hi *= 2.0;
    }
    while joint(lo.exp()) < target {
        hi = lo;
        lo = if lo > 0.0 { -lo } else { lo * 2.0 - 1.0 };
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if joint(mid.exp()) > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-13 {
            break;
        }
    }
    Some((0.5 * (lo + hi)).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn survival_of_a_rock_of_known_age() {
        let rate = 1.785e-4;
        // The published values, to the digits printed.
        for (t, p, half_digit) in [(1e3, 0.837, 5e-4), (1e4, 0.168, 5e-4), (3e4, 0.0047, 5e-5)] {
            let ps = Age::Known(t).survival(rate);
            assert!((ps - p).abs() <= half_digit, "{t}: {ps}");
        }
        // s: exp(−s λ T) = 0.05.
        let s = rate_scale(&[(rate, Age::Known(1e4))], 0.05).expect("topples");
        assert!((s - 20f64.ln() / (rate * 1e4)).abs() < 1e-12);
    }

    #[test]
    fn uncertain_ages_and_joint_survival() {
        let age = Age::Uncertain(Distribution::Uniform {
            min: 5e3,
            max: 15e3,
        });
        let rate = 1e-4;
        // E[exp(−λT)] over a uniform age: (e^(−λa) − e^(−λb))/(λ(b − a)).
        let expected = ((-0.5f64).exp() - (-1.5f64).exp()) / 1.0;
        assert!((age.survival(rate) / expected - 1.0).abs() < 1e-12);
        let s = rate_scale(&[(rate, age)], 0.05).expect("topples");
        assert!((age.survival(s * rate) - 0.05).abs() < 1e-10, "{s}");
        // Two rocks: the product; the joint scale is below either alone.
        let rocks = [(rate, age), (2e-4, Age::Known(8e3))];
        let joint = rate_scale(&rocks, 0.05).expect("topples");
        let p: f64 = rocks.iter().map(|(l, a)| a.survival(joint * l)).product();
        assert!((p - 0.05).abs() < 1e-10);
        assert!(joint < s);
        assert_eq!(rate_scale(&[(0.0, Age::Known(1e4))], 0.05), None);
    }
}
