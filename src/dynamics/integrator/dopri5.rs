//! Dormand–Prince 5(4) with Hairer's quartic dense output (code DOPRI5).

use super::{DenseStep, MAX_DEGREE, Rhs, State, TrialStep, scale};

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Error exponent: the embedded solution is of order 4.
pub const ERROR_ORDER: f64 = 4.0;

#[inline]
fn axpy(y: State, h: f64, terms: &[(f64, State)]) -> State {
    let mut out = y;
    for c in 0..2 {
        let mut acc = 0.0;
        for (w, k) in terms {
            acc += w * k[c];
        }
        out[c] += h * acc;
    }
    out
}

/// One trial step from `(t, y)` with `f0 = f(t, y)` and step `h`.
pub fn trial<R: Rhs>(
    rhs: &R,
    t: f64,
    y: State,
    f0: State,
    h: f64,
    atol: f64,
    rtol: f64,
) -> (TrialStep, [State; 7]) {
    let k1 = f0;
    let k2 = rhs.eval(t + C2 * h, axpy(y, h, &[(A21, k1)]));
    let k3 = rhs.eval(t + C3 * h, axpy(y, h, &[(A31, k1), (A32, k2)]));
    let k4 = rhs.eval(t + C4 * h, axpy(y, h, &[(A41, k1), (A42, k2), (A43, k3)]));
    let k5 = rhs.eval(
        t + C5 * h,
        axpy(y, h, &[(A51, k1), (A52, k2), (A53, k3), (A54, k4)]),
    );
    let k6 = rhs.eval(
        t + h,
        axpy(
            y,
            h,
            &[(A61, k1), (A62, k2), (A63, k3), (A64, k4), (A65, k5)],
        ),
    );
    let y1 = axpy(
        y,
        h,
        &[(A71, k1), (A73, k3), (A74, k4), (A75, k5), (A76, k6)],
    );
    let k7 = rhs.eval(t + h, y1);
    let sc = scale(atol, rtol, y, y1);
    let mut err2 = 0.0;
    let mut err_theta = 0.0;
    for c in 0..2 {
        let e = h * (E1 * k1[c] + E3 * k3[c] + E4 * k4[c] + E5 * k5[c] + E6 * k6[c] + E7 * k7[c]);
        if c == 0 {
            err_theta = e.abs();
        }
        err2 += (e / sc[c]).powi(2);
    }
    (
        TrialStep {
            y1,
            f1: k7,
            err: (err2 / 2.0).sqrt(),
            err_theta,
            nfev: 6,
        },
        [k1, k2, k3, k4, k5, k6, k7],
    )
}

/// Dense output of an accepted step, in monomial form (Hairer's `CONTD5`).
pub fn dense(t: f64, h: f64, y0: State, y1: State, k: &[State; 7]) -> DenseStep {
    let mut coeffs = [[0.0; MAX_DEGREE + 1]; 2];
    for c in 0..2 {
        let ydiff = y1[c] - y0[c];
        let bspl = h * k[0][c] - ydiff;
        let r4 = ydiff - h * k[6][c] - bspl;
        let r5 = h
            * (D1 * k[0][c]
                + D3 * k[2][c]
                + D4 * k[3][c]
                + D5 * k[4][c]
                + D6 * k[5][c]
                + D7 * k[6][c]);
        // y(σ) = y0 + σ(ydiff + (1−σ)(r3 + σ(r4 + (1−σ) r5))) expanded in powers of σ.
        let c1 = h * k[0][c];
        let c3 = -(r4 + 2.0 * r5);
        let c4 = r5;
        coeffs[c][0] = y0[c];
        coeffs[c][1] = c1;
        coeffs[c][2] = ydiff - c1 - c3 - c4;
        coeffs[c][3] = c3;
        coeffs[c][4] = c4;
    }
    DenseStep {
        t0: t,
        h,
        y0,
        y1,
        coeffs,
        len: 5,
    }
}
