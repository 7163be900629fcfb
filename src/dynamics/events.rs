//! Event location: bracketed root finding (Brent) and the first root of a dense
//! output polynomial on a step (Bernstein sign tests with subdivision), so that no
//! event inside a step is missed even when the function returns to its sign
//! before the step ends.

use super::integrator::MAX_DEGREE;

/// Brent's method for a root of `f` in `[a, b]`, given `fa = f(a)`, `fb = f(b)`
/// of opposite signs (or one of them zero). Returns the root to within
/// `4 ε |x| + xtol`.
///
/// ## Reference
/// R. P. Brent, *Algorithms for Minimization without Derivatives* (1973), ch. 4.
pub fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    xtol: f64,
) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return b;
        }
        if e.abs() < tol || fa.abs() <= fb.abs() {
            d = m;
            e = m;
        } else {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
    }
    b
}

/// A polynomial in σ on [0, 1], monomial coefficients, degree ≤ [`MAX_DEGREE`].
#[derive(Clone, Copy, Debug)]
pub struct Poly {
    /// `c[k]` multiplies σ^k.
    pub c: [f64; MAX_DEGREE + 1],
    /// Number of coefficients in use.
    pub len: usize,
}

impl Poly {
    /// Value at σ (Horner).
    #[inline]
    pub fn eval(&self, sigma: f64) -> f64 {
        let mut acc = 0.0;
        for k in (0..self.len).rev() {
            acc = acc * sigma + self.c[k];
        }
        acc
    }
}

const BINOM: [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1] = {
    let mut t = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    let mut n = 0;
    while n <= MAX_DEGREE {
        t[n][0] = 1.0;
        let mut k = 1;
        while k <= n {
            t[n][k] = t[n - 1][k - 1] + if k < n { t[n - 1][k] } else { 0.0 };
            k += 1;
        }
        n += 1;
    }
    t
};

/// Bernstein coefficients on [0, 1] of a monomial polynomial of degree n = len − 1:
/// `b_i = Σ_{k ≤ i} C(i,k)/C(n,k) c_k`.
#[allow(clippy::needless_range_loop)]
fn to_bernstein(p: &Poly) -> [f64; MAX_DEGREE + 1] {
    let n = p.len - 1;
    let mut b = [0.0; MAX_DEGREE + 1];
    for (i, bi) in b.iter_mut().enumerate().take(n + 1) {
        let mut acc = 0.0;
        for k in 0..=i {
            acc += BINOM[i][k] / BINOM[n][k] * p.c[k];
        }
        *bi = acc;
    }
    b
}

/// Splits Bernstein coefficients at the midpoint (de Casteljau).
fn split_half(
    b: &[f64; MAX_DEGREE + 1],
    len: usize,
) -> ([f64; MAX_DEGREE + 1], [f64; MAX_DEGREE + 1]) {
    let mut work = *b;
    let mut left = [0.0; MAX_DEGREE + 1];
    let mut right = [0.0; MAX_DEGREE + 1];
    let n = len - 1;
    left[0] = work[0];
    right[n] = work[n];
    for r in 1..=n {
        for i in 0..=(n - r) {
            work[i] = 0.5 * (work[i] + work[i + 1]);
        }
        left[r] = work[0];
        right[n - r] = work[n - r];
    }
    (left, right)
}

fn sign_changes(b: &[f64], len: usize) -> usize {
    let mut changes = 0;
    let mut last = 0.0;
    for &v in &b[..len] {
        if v != 0.0 {
            if last != 0.0 && (v > 0.0) != (last > 0.0) {
                changes += 1;
            }
            last = v;
        }
    }
    changes
}

/// On a step's dense output of θ (`theta`: the coefficients of σ^k, `len`
/// of them), for a block on side `s`: the polynomials whose first
/// non-positive value marks a return to θ = 0 (s θ) and overturning
/// (π/2 − s θ).
pub fn return_and_overturn(theta: &[f64], len: usize, s: f64) -> (Poly, Poly) {
    let mut back = Poly {
        c: [0.0; MAX_DEGREE + 1],
        len,
    };
    let mut top = back;
    for (k, &c) in theta.iter().take(len).enumerate() {
        back.c[k] = s * c;
        top.c[k] = -s * c;
    }
    top.c[0] += std::f64::consts::FRAC_PI_2;
    (back, top)
}

/// The smallest σ ∈ (0, 1] where `p(σ) ≤ 0`, for a polynomial that is positive
/// just after σ = 0 (exactly-zero leading coefficients, i.e. a root at the start
/// of the step, are factored out first). `None` if `p > 0` on (0, 1].
pub fn first_nonpositive(p: &Poly) -> Option<f64> {
    // Factor σ^m out of p: roots of the quotient in (0, 1] are those of p.
    let mut q = *p;
    while q.len > 1 && q.c[0] == 0.0 {
        for k in 0..q.len - 1 {
            q.c[k] = q.c[k + 1];
        }
        q.len -= 1;
        q.c[q.len] = 0.0;
    }
    if q.len == 1 {
        return if q.c[0] > 0.0 { None } else { Some(0.0) };
    }
    let bern = to_bernstein(&q);
    if bern[..q.len].iter().all(|&v| v > 0.0) {
        return None;
    }
    // Depth-first, left to right, over dyadic subintervals.
    let mut stack: [([f64; MAX_DEGREE + 1], f64, f64); 64] =
        [([0.0; MAX_DEGREE + 1], 0.0, 0.0); 64];
    let mut top = 0;
    stack[top] = (bern, 0.0, 1.0);
    top += 1;
    while top > 0 {
        top -= 1;
        let (b, lo, hi) = stack[top];
        let len = q.len;
        if b[..len].iter().all(|&v| v > 0.0) {
            continue;
        }
        if b[0] <= 0.0 {
            // q(lo) ≤ 0: lo is the first point (earlier intervals were positive).
            return Some(lo);
        }
        let single = sign_changes(&b, len) == 1 && b[len - 1] <= 0.0;
        if single || hi - lo < 1e-12 || top + 2 >= stack.len() {
            if b[len - 1] <= 0.0 {
                let f = |s: f64| q.eval(s);
                let (flo, fhi) = (f(lo), f(hi));
                if flo > 0.0 && fhi <= 0.0 {
                    return Some(brent(f, lo, hi, flo, fhi, 1e-16));
                }
                if flo <= 0.0 {
                    return Some(lo);
                }
            }
            if hi - lo < 1e-12 {
                // A touch of the axis narrower than resolution: treat as no root.
                continue;
            }
        }
        let mid = 0.5 * (lo + hi);
        let (l, r) = split_half(&b, len);
        // Push right first so the left half is examined first.
        stack[top] = (r, mid, hi);
        top += 1;
        stack[top] = (l, lo, mid);
        top += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(c: &[f64]) -> Poly {
        let mut p = Poly {
            c: [0.0; MAX_DEGREE + 1],
            len: c.len(),
        };
        p.c[..c.len()].copy_from_slice(c);
        p
    }

    #[test]
    fn brent_finds_a_transcendental_root() {
        let r = brent(|x: f64| x.cos() - x, 0.0, 1.0, 1.0, 1f64.cos() - 1.0, 0.0);
        assert!((r - 0.739_085_133_215_160_6).abs() < 1e-15);
    }

    #[test]
    fn finds_a_double_crossing_inside_the_step_that_end_values_hide() {
        // (σ − 0.3)(σ − 0.35) + tiny: positive at both ends, negative in between.
        let p = poly(&[0.105, -0.65, 1.0]);
        assert!(p.eval(0.0) > 0.0 && p.eval(1.0) > 0.0);
        let r = first_nonpositive(&p).expect("root");
        assert!((r - 0.3).abs() < 1e-14, "{r}");
    }

    #[test]
    fn a_root_at_the_start_is_factored_out() {
        // σ (0.5 − σ): starts at zero, positive, first root at 0.5.
        let p = poly(&[0.0, 0.5, -1.0]);
        let r = first_nonpositive(&p).expect("root");
        assert!((r - 0.5).abs() < 1e-15);
        // σ² (1 + σ): no root in (0, 1].
        assert!(first_nonpositive(&poly(&[0.0, 0.0, 1.0, 1.0])).is_none());
    }

    #[test]
    fn bernstein_conversion_reproduces_values() {
        let p = poly(&[0.3, -1.2, 2.0, 0.7, -0.4, 0.1, -0.05, 0.02]);
        let b = to_bernstein(&p);
        assert!((b[0] - p.eval(0.0)).abs() < 1e-15);
        assert!((b[7] - p.eval(1.0)).abs() < 1e-14);
    }
}
