#!/usr/bin/env python3
"""Independent check of the friction demand f_x/f_z (paper eqs. 7, 12, 20, 51).

Written from the paper's equations, not from topple's code: the nonlinear
equation of motion (eq. 12) is integrated with SciPy's DOP853, impacts multiply
theta_dot by eta, and eq. 20 is evaluated densely along the rocking motion.
Prints, for each case, the largest |f_x/f_z| while the block rocks (the
minimum friction coefficient for pure rocking), eq. 7 at the rocking start,
and the first time f_z reaches 0 (lift-off), if any.

Rule for a block that overturns: the demand is followed while the pulse acts;
once the pulse is over and the block is falling, the fall is not counted.

    python3 -m venv /tmp/bench-venv
    /tmp/bench-venv/bin/pip install -r bench/requirements.txt
    /tmp/bench-venv/bin/python bench/friction_scipy.py
"""

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

G = 9.81


def pulse(kind, a_p, w):
    """Ground acceleration of a one-sine or one-cosine pulse and its duration."""
    period = 2.0 * math.pi / w
    if kind == "one_sine":
        return (lambda t: a_p * math.sin(w * t) if 0.0 <= t <= period else 0.0), period
    return (lambda t: a_p * math.cos(w * t) if 0.0 <= t <= period else 0.0), period


def eq20(ug, theta, theta_dot, alpha, p):
    """Eq. 20 as printed: (numerator, denominator); the denominator has the sign of f_z."""
    s = -1.0 if theta < 0 else 1.0
    phi = alpha * s - theta
    u = ug / G
    w2 = (theta_dot / p) ** 2
    num = u * (5 - 3 * math.cos(2 * phi)) - 3 * math.sin(2 * phi) + 6 * w2 * math.sin(phi)
    den = 5 - 3 * u * math.sin(2 * phi) + 3 * math.cos(2 * phi) - 6 * w2 * math.cos(phi)
    return num, den


def eq7(lam_ap, alpha):
    """Eq. 7 (eq. 51 with lambda = 1): demand at the rocking start."""
    x = lam_ap / (G * math.tan(alpha)) - 1.0
    return (lam_ap - 0.75 * G * math.cos(alpha) * math.sin(alpha) * x) / (
        G + 0.75 * G * math.sin(alpha) ** 2 * x
    )


def run(kind, alpha, p, eta, omega_ratio, level, free_impacts=30):
    a_p = level * alpha * G
    ug, period = pulse(kind, a_p, omega_ratio * p)
    thr = G * math.tan(alpha)
    # Rocking starts where the ground first exceeds g tan(alpha).
    ts = np.linspace(0.0, period, 200001)
    start = next(t for t in ts if abs(ug(t)) > thr or (t == 0.0 and abs(ug(0.0)) >= thr))
    side = -math.copysign(1.0, ug(start))

    def rhs(t, y, sgn):
        th, w = y
        return [w, -p * p * (math.sin(alpha * sgn - th) + ug(t) / G * math.cos(alpha * sgn - th))]

    peak, peak_t, lift = 0.0, None, None
    t, y, sgn = start, [0.0, 0.0], side
    impacts = 0
    overturned = False
    horizon = period + 200.0 / p
    while t < horizon and impacts <= free_impacts:
        forced = t < period
        t_end = period if forced else horizon

        def hit(tt, yy, _sgn):
            return yy[0]

        hit.terminal, hit.direction = True, sgn * -1.0

        def fall(tt, yy, _sgn):
            return abs(yy[0]) - math.pi / 2

        fall.terminal = True
        sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=1e-11, atol=1e-13,
                        args=(sgn,), events=[hit, fall], dense_output=True)
        # The first instants after an impact sit on theta = 0: skip the event at t.
        t1 = sol.t[-1]
        grid = np.linspace(t, t1, max(2000, int((t1 - t) * 4000)))
        falling_free = not forced and sol.t_events[1].size > 0
        if not falling_free and lift is None:
            def den_at(tt, sgn=sgn):
                th, w = sol.sol(tt)
                return eq20(ug(tt), th if th != 0 else sgn * 1e-300, w, alpha, p)[1]

            prev = None
            for tt in grid:
                th, w = sol.sol(tt)
                num, den = eq20(ug(tt), th if th != 0 else sgn * 1e-300, w, alpha, p)
                if den <= 0:
                    # f_z = 0 located by Brent's method between the samples.
                    lift = brentq(den_at, prev, tt, xtol=1e-13) if prev is not None else tt
                    break
                prev = tt
                if abs(num / den) > peak:
                    peak, peak_t = abs(num / den), tt
        if sol.t_events[1].size:
            overturned = True
            break
        if sol.t_events[0].size:
            t = sol.t_events[0][0]
            w = sol.y_events[0][0][1] * eta
            y, sgn, impacts = [0.0, w], math.copysign(1.0, w), impacts + 1
            if abs(w) < 1e-8 * p * alpha:
                break
            continue
        t, y = t1, list(sol.y[:, -1])
    return {
        "peak": peak,
        "peak_t": peak_t,
        "eq7": eq7(abs(ug(start)), alpha),
        "lift_off": lift,
        "overturned": overturned,
        "impacts": impacts,
    }


def main():
    cases = [
        ("one_cosine", 0.25, 2.14, 0.9, 4.0, 6.0, "Fig. 9 bottom: ~2 alpha"),
        ("one_cosine", 0.25, 2.14, 0.9, 4.0, 2.0, ""),
        ("one_cosine", 0.25, 2.14, 0.9, 4.0, 4.0, ""),
        ("one_cosine", 0.25, 2.14, 0.9, 1.0, 6.0, "lift-off expected"),
        ("one_sine", 0.25, 2.14, 0.9, 15.7 / 2.14, 8.9, "Fig. 9 top: ~2.5 tan alpha"),
    ]
    print(f"{'pulse':<11}{'w/p':>7}{'a/ag':>6}  {'peak':>10} {'at t':>9} {'eq.7':>8}"
          f" {'peak/tan':>9} {'lift-off':>10} {'over':>5}  note")
    for kind, alpha, p, eta, wr, lv, note in cases:
        r = run(kind, alpha, p, eta, wr, lv)
        lift = f"{r['lift_off']:.7f}" if r["lift_off"] is not None else "-"
        peak = "unbounded" if r["lift_off"] is not None else f"{r['peak']:.6f}"
        pt = f"{r['peak_t']:.5f}" if r["peak_t"] is not None else "-"
        print(f"{kind:<11}{wr:>7.3f}{lv:>6.1f}  {peak:>10} {pt:>9} {r['eq7']:>8.5f}"
              f" {r['peak'] / math.tan(alpha):>9.4f} {lift:>10} {str(r['overturned']):>5}  {note}")


if __name__ == "__main__":
    main()
