"""Vertical ground motion cross-checked against an independent SciPy model.

The model, written from the rocking equation with vertical acceleration
(gravity g + uv in the block's frame; uv positive up):

    theta'' = -p^2 [(1 + uv/g) sin(alpha s - theta) + (ug/g) cos(alpha s - theta)]

* at rest until s*ug - k*uv first exceeds k*g for s = +1 or -1 (k = tan alpha):
  a scan and brentq; rocking then on side -s;
* a lift-off when g + uv <= 0 (a terminal event; nothing is said after it);
* an impact when theta returns to 0 (terminal, directional solve_ivp event):
  theta' is multiplied by eta; below 1e-9 rad/s the block is at rest and
  waits for the next exceedance;
* overturning when |theta| reaches pi/2 while the ground moves; after the
  ground motion (the later of both components) it is decided from the energy
  E = theta'^2/(2p^2) + cos(alpha - |theta|) against the barrier's top (1, at
  |theta| = alpha): past it the block falls unless it moves inward with E > 1;
  inside it, it falls if it moves outward with E > 1;
* every leg is integrated piece by piece between the kinks of the ground
  motion (pulse ends, record samples), DOP853 at rtol 1e-11, atol 1e-13.

Each case is run by `topple run` (time_history, nonlinear, dop853 at the same
tolerances) and compared: outcome (overturned, lift-off), mode, and the times
of the rocking impacts (|theta'| before at least 1e-2 p alpha, the cycles
without the chattering that ends them). Cases: pulse pairs with ratios +-0.5
and +-1, vertical pulses of their own at other frequencies with delays, and a
short record with a vertical component.

    target/bench-venv/bin/python bench/vertical_scipy.py --topple target/release/topple
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

ALPHA, P, ETA, G = 0.25, 2.14, 0.9, 9.81
K = math.tan(ALPHA)
RTOL, ATOL = 1e-11, 1e-13
ROCKING_IMPACT = 1e-2 * P * ALPHA


# Ground motions: (ug, uv, kinks, end) with ug, uv callables in m/s^2.

def pulse(kind, a, w):
    """A pulse of `kind` ('one_sine', 'one_cosine'): (acc(t) on its support, duration)."""
    T = 2 * math.pi / w
    if kind == "one_sine":
        return (lambda t: a * math.sin(w * t) if 0 <= t <= T else 0.0), T
    if kind == "one_cosine":
        return (lambda t: a * math.cos(w * t) if 0 <= t <= T else 0.0), T
    raise ValueError(kind)


def pulse_pair(h, v, delay):
    (ug, th), (vv, tv) = h, v
    uv = lambda t: vv(t - delay)
    end = max(th, delay + tv)
    return ug, uv, sorted({0.0, th, delay, delay + tv, end}), end


def record_pair(dt, acc_h, acc_v):
    n = max(len(acc_h), len(acc_v))
    h = np.array(list(acc_h) + [0.0] * (n - len(acc_h)))
    v = np.array(list(acc_v) + [0.0] * (n - len(acc_v)))
    end = (n - 1) * dt
    ts = np.arange(n) * dt

    def interp(arr):
        return lambda t: float(np.interp(t, ts, arr)) if 0 <= t <= end else 0.0

    return interp(h), interp(v), [float(x) for x in ts], end


def excess(ug, uv, s):
    return lambda t: s * ug(t) - K * uv(t) - K * G


def first_start(ug, uv, t_from, end, n):
    """(time, s) of the first rocking start in [t_from, end] (n scan intervals), or None."""
    ts = np.linspace(t_from, end, n + 1)
    best = None
    for s in (1.0, -1.0):
        f = excess(ug, uv, s)
        vals = [f(t) for t in ts]
        if vals[0] > 0:
            t = t_from
        else:
            t = None
            for j in range(n):
                if vals[j + 1] > 0:
                    t = brentq(f, ts[j], ts[j + 1], xtol=1e-15, rtol=8.9e-16)
                    break
        if t is not None and (best is None or t < best[0]):
            best = (t, s)
    return best


def first_weightless(uv, t_from, end, n):
    ts = np.linspace(t_from, end, n + 1)
    f = lambda t: -(G + uv(t))
    vals = [f(t) for t in ts]
    if vals[0] >= 0:
        return t_from
    for j in range(n):
        if vals[j + 1] >= 0:
            return brentq(f, ts[j], ts[j + 1], xtol=1e-15, rtol=8.9e-16)
    return None


def energy(theta, theta_dot):
    return theta_dot**2 / (2 * P**2) + math.cos(ALPHA - abs(theta))


def simulate(motion, scan):
    """{'overturned', 'lift_off', 'mode', 'impacts': [(t, v_before)]}."""
    ug, uv, kinks, end = motion
    weightless = first_weightless(uv, 0.0, end, scan)
    stop = min(end, weightless) if weightless is not None else end
    impacts = []

    start = []

    def result(overturned=False, lift_off=None):
        mode = (1 if impacts else 2) if overturned else None
        return {"overturned": overturned, "lift_off": lift_off, "mode": mode, "impacts": impacts,
                "start": start[0] if start else None}

    def wait(t_from):
        st = first_start(ug, uv, t_from, end, scan)
        if st is None or st[0] >= stop:
            return None
        return st

    st = wait(0.0)
    if st is None:
        return result(lift_off=weightless)
    t, s = st
    start.append(t)
    side, y = -s, [0.0, 0.0]
    armed_after = t  # the impact event is armed once theta has left 0
    while True:
        if t >= stop:
            break
        sd = side

        def rhs(tt, yy):
            w = 1.0 + uv(tt) / G
            u = ug(tt) / G
            ph = ALPHA * sd - yy[0]
            return [yy[1], -P**2 * (w * math.sin(ph) + u * math.cos(ph))]

        def hit_zero(tt, yy):
            return yy[0]

        hit_zero.terminal = True
        hit_zero.direction = -sd

        def topple(tt, yy):
            return abs(yy[0]) - math.pi / 2

        topple.terminal = True
        event = None
        # Piece by piece between the kinks of the ground motion.
        pieces = [k for k in kinks if t < k < stop] + [stop]
        ta = t
        for tb in pieces:
            sol = solve_ivp(rhs, (ta, tb), y, method="DOP853", rtol=RTOL, atol=ATOL,
                            events=[hit_zero, topple])
            if sol.t_events[1].size:
                event = ("over", float(sol.t_events[1][0]), None)
                break
            if sol.t_events[0].size and float(sol.t_events[0][0]) > armed_after:
                event = ("impact", float(sol.t_events[0][0]), float(sol.y_events[0][0][1]))
                break
            y = [float(sol.y[0][-1]), float(sol.y[1][-1])]
            ta = tb
        if event is None:
            t = stop
            break
        kind, te, vb = event
        if kind == "over":
            return result(overturned=True)
        impacts.append((te, vb))
        v = vb * ETA
        t = te
        if abs(v) < 1e-9:
            st = wait(te + 1e-12)
            if st is None:
                if weightless is not None:
                    return result(lift_off=weightless)
                return result()
            t, s = st
            side, y, armed_after = -s, [0.0, 0.0], t
            continue
        side, y, armed_after = math.copysign(1.0, v), [0.0, v], te
    if weightless is not None and t >= weightless:
        return result(lift_off=weightless)
    # Free motion after the ground motion, decided by the energy.
    theta, theta_dot = y
    while True:
        outward = theta * theta_dot > 0 or (theta == 0 and theta_dot != 0)
        e = energy(theta, theta_dot)
        if abs(theta) > ALPHA:
            # Past the barrier's top (|theta| = alpha, where the potential
            # is 1): outward it falls; inward it comes back only over the top.
            if outward or e <= 1:
                return result(overturned=True)
        elif outward and e > 1:
            return result(overturned=True)
        e = energy(theta, theta_dot)
        v0 = math.sqrt(max(0.0, 2 * P**2 * (e - math.cos(ALPHA))))
        v = ETA * v0
        impacts.append((math.nan, v0))
        if energy(0.0, v) <= 1 or v < 1e-12:
            return result()
        theta, theta_dot = 0.0, v


def topple(binary, spec):
    out = subprocess.run([binary, "run", "-"], input=json.dumps(spec), capture_output=True,
                         text=True, check=True).stdout
    return json.loads(out)


def cases():
    """(name, spec fields, scipy motion)."""
    block_g = ALPHA * G
    out = []
    # (Not 8 αg: with a ratio of 0.5 its vertical would touch −g exactly.)
    for level, ratio_w in [(3.0, 2.0), (5.0, 4.0), (7.5, 6.0), (2.0, 1.0)]:
        for kind in ("one_sine", "one_cosine"):
            for r in (0.5, -0.5, 1.0, -1.0):
                a, w = level * block_g, ratio_w * P
                name = f"{kind} {level} αg ω/p={ratio_w} ratio {r:+}"
                spec = {"pulse": {"type": kind, "omega_p": w, "a_p": a}, "vertical": {"ratio": r}}
                h = pulse(kind, a, w)
                v = pulse(kind, r * a, w)
                out.append((name, spec, pulse_pair(h, v, 0.0)))
    for level, ratio_w, vk, va_g, vw_ratio, delay in [
        (4.0, 2.0, "one_cosine", 0.4, 7.0, 0.1),
        (6.0, 3.0, "one_sine", -0.6, 5.0, 0.25),
        (3.0, 1.5, "one_sine", 0.8, 10.0, 0.0),
        (7.0, 5.0, "one_cosine", -0.5, 2.0, 0.05),
        (2.5, 1.0, "one_cosine", -0.3, 4.0, 0.6),
        (5.0, 2.5, "one_sine", 1.2, 8.0, 0.3),
    ]:
        a, w = level * block_g, ratio_w * P
        vw = vw_ratio * P
        name = f"one_sine {level} αg ω/p={ratio_w} + {vk} {va_g} g ω/p={vw_ratio} at {delay} s"
        spec = {"pulse": {"type": "one_sine", "omega_p": w, "a_p": a},
                "vertical": {"type": vk, "omega_p": vw, "a_p": va_g * G, "delay_s": delay}}
        out.append((name, spec, pulse_pair(pulse("one_sine", a, w), pulse(vk, va_g * G, vw), delay)))
    # A short record with a vertical component (deterministic).
    dt = 0.02
    rng = np.random.default_rng(11)
    n = 151
    t = np.arange(n) * dt
    env = np.sin(math.pi * t / t[-1]) ** 2
    for peak_h, peak_v in [(0.45, 0.3), (0.6, -0.5), (0.35, 0.6)]:
        h = env * (np.sin(2 * math.pi * 1.3 * t) + 0.4 * rng.standard_normal(n))
        v = env * (np.sin(2 * math.pi * 3.1 * t + 0.7) + 0.4 * rng.standard_normal(n))
        h = list(peak_h * G * h / np.abs(h).max())
        v = list(peak_v * G * v / np.abs(v).max())[: n - 20]
        spec = {"ground_motion": {"dt": dt, "unit": "m/s2", "acc": h,
                                  "vertical": {"acc": v, "unit": "m/s2"}}}
        out.append((f"record PGA {peak_h} g, PGA_v {peak_v} g", spec, record_pair(dt, h, v)))
    return out


def compare(binary, tol):
    rows, worst_all, failures = [], 0.0, 0
    for name, fields, motion in cases():
        spec = {"kind": "time_history", "block": {"alpha": ALPHA, "p": P, "eta": ETA},
                "formulation": "nonlinear",
                "solver": {"method": "dop853", "rtol": RTOL, "atol": ATOL},
                "outputs": {"max_free_impacts": 0, "reactions": False}}
        spec.update(fields)
        doc = topple(binary, spec)
        scan = 4000
        ref = simulate(motion, scan)
        t_imp = [i["t"] for i in doc.get("impacts", []) if abs(i["theta_dot_before"]) >= ROCKING_IMPACT]
        s_imp = [tt for tt, vb in ref["impacts"] if abs(vb) >= ROCKING_IMPACT and not math.isnan(tt)]
        lift_t = doc.get("lift_off_time") if doc.get("lift_off") else None
        same = (doc["overturned"] == ref["overturned"] and doc["mode"] == ref["mode"]
                and (lift_t is None) == (ref["lift_off"] is None) and len(t_imp) == len(s_imp))
        worst = 0.0
        if same:
            for a, b in zip(t_imp, s_imp):
                worst = max(worst, abs(a - b))
            if lift_t is not None:
                worst = max(worst, abs(lift_t - ref["lift_off"]))
            if (doc["rocking_start"] is None) != (ref["start"] is None):
                same = False
            elif ref["start"] is not None:
                worst = max(worst, abs(doc["rocking_start"] - ref["start"]))
        ok = same and worst <= tol
        failures += not ok
        worst_all = max(worst_all, worst if same else math.inf)
        outcome = ("lift-off" if lift_t is not None else
                   ("overturns" if doc["overturned"] else "survives"))
        rows.append((name, outcome, doc["mode"], len(t_imp), worst if same else math.inf, ok,
                     ref["overturned"], ref["mode"], len(s_imp)))
    return rows, worst_all, failures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--topple", default="target/release/topple")
    ap.add_argument("--tol", type=float, default=1e-8, help="largest impact-time difference, s")
    args = ap.parse_args()
    rows, worst, failures = compare(args.topple, args.tol)
    print("| case | outcome | mode | rocking impacts | max Δt (s) | agrees |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, outcome, mode, n, d, ok, ro, rm, rn in rows:
        extra = "" if ok else f" (SciPy: overturned {ro}, mode {rm}, {rn} impacts)"
        print(f"| {name} | {outcome} | {mode if mode is not None else '–'} | {n} | {d:.1e} | "
              f"{'yes' if ok else 'NO'}{extra} |")
    print(f"\n{len(rows)} cases, {len(rows) - failures} agree; largest impact-time difference "
          f"{worst:.1e} s (tolerance {args.tol:g} s)")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
