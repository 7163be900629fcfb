"""Pure sliding on a Coulomb floor cross-checked against an independent SciPy
model, written from the equations of a block that cannot rock:

* it sticks (moves with the ground) until |ug| first exceeds mu_s (g + uv):
  a scan on a 1e-3-s grid and brentq; it then slides with s = -sgn(ug);
* sliding, its displacement relative to the ground obeys
      x'' = -ug - s mu_k (g + uv),
  integrated by solve_ivp (DOP853, rtol 1e-12, atol 1e-14) piece by piece
  between the kinks of the ground motion, with terminal events x' = 0
  (s x' falling through 0) and g + uv = 0 (lift-off);
* at x' = 0 it slides back at once if |ug| > mu_s (g + uv) there, the ground
  pushing the other way; otherwise it sticks;
* after the ground motion x'' = -s mu_k g until it stops;
* a lift-off ends the history: the displacement there is the residual, and
  the slide it interrupts is not counted as one that stopped.

Pulses, written from their definitions: a cos(w t + phi) on its support
(one-sine phi = -pi/2 over 2 pi/w; one-cosine phi = 0 over 2 pi/w;
rectangular a constant over pi/w; Type-C_n phi_n with
tan(phi)((2n+1) pi - 2 phi) = 2 over ((2n+1) pi - 2 phi)/w). The vertical is
r times the horizontal, or a pulse of its own starting `delay` s later.

topple's answers come from `examples/sliding_cases.rs` (the engine's
dynamics::sliding). Compared: the number, directions, start and end times
of the slides (1e-8 s), the residual and peak displacement (1e-9 m), lift-off.

    python3 bench/sliding_scipy.py
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

G = 9.81


def cn_phase(n):
    span = (2 * n + 1) * math.pi
    return brentq(lambda p: math.tan(p) * (span - 2 * p) - 2.0, 1e-9, math.pi / 2 - 1e-9, xtol=1e-15)


def pulse(spec):
    a, w = spec["a_g"] * G, spec["omega"]
    shape = spec["shape"]
    if shape == "one_sine":
        phi, span = -math.pi / 2, 2 * math.pi
    elif shape == "one_cosine":
        phi, span = 0.0, 2 * math.pi
    elif shape == "rectangular":
        phi, span = None, math.pi
    elif shape == "c3":
        phi = cn_phase(3)
        span = 7 * math.pi - 2 * phi
    else:
        raise ValueError(shape)
    dur = span / w

    def acc(t):
        if t < 0 or t > dur:
            return 0.0
        return a if phi is None else a * math.cos(w * t + phi)

    return acc, dur


def motion(case):
    ug, dur = pulse(case)
    kinks = [0.0, dur]
    if "ratio" in case:
        r = case["ratio"]
        uv = lambda t: r * ug(t)
    elif "vertical" in case:
        v, vdur = pulse(case["vertical"])
        d = case["vertical"].get("delay", 0.0)
        uv = lambda t: v(t - d)
        kinks += [d, d + vdur]
    else:
        uv = lambda t: 0.0
    return ug, uv, sorted(set(kinks))


def reference(case):
    ug, uv, kinks = motion(case)
    mu_s, mu_k = case["mu"], case.get("mu_k", case["mu"])
    end = kinks[-1]
    slides, t, x, lift = [], 0.0, 0.0, None

    def over(t):
        return abs(ug(t)) - mu_s * (G + uv(t))

    def weightless_before(t0, t1):
        grid = np.linspace(t0, t1, max(2, int((t1 - t0) / 1e-3) + 2))
        for a, b in zip(grid[:-1], grid[1:]):
            if G + uv(b) <= 0.0:
                if G + uv(a) <= 0.0:
                    return a
                return brentq(lambda s: G + uv(s), a, b, xtol=1e-15)
        return None

    def next_slip(t0):
        if over(t0) > 0:
            return t0
        grid = np.arange(t0, end + 1e-3, 1e-3)
        for a, b in zip(grid[:-1], grid[1:]):
            b = min(b, end)
            if over(b) > 0:
                return brentq(over, a, b, xtol=1e-15, rtol=8.9e-16)
        return None

    start = next_slip(0.0)
    while start is not None:
        wl = weightless_before(t, start)
        if wl is not None:
            lift = wl
            break
        s = -math.copysign(1.0, ug(start))
        t0, y = start, [x, 0.0]
        stopped = None
        while stopped is None:
            nxt = [k for k in kinks if k > t0 + 1e-15]
            t1 = nxt[0] if nxt else t0 + 1e3

            def rhs(t, y):
                return [y[1], -ug(t) - s * mu_k * (G + uv(t))]

            def halt(t, y):
                return s * y[1]

            halt.terminal, halt.direction = True, -1

            def fall(t, y):
                return G + uv(t)

            fall.terminal, fall.direction = True, -1
            sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-14,
                            events=[halt, fall], dense_output=False)
            if sol.t_events[1].size:
                # Lifted off while sliding: the displacement there is the
                # last one; the slide did not come to a stop.
                lift = sol.t_events[1][0]
                x = sol.y_events[1][0][0]
                stopped = "lift"
                break
            if sol.t_events[0].size:
                stopped = sol.t_events[0][0]
                y = sol.y_events[0][0]
                break
            t0, y = t1, list(sol.y[:, -1])
        if stopped == "lift":
            break
        slides.append({"from": start, "to": stopped, "direction": s, "x_to": y[0]})
        t, x = stopped, y[0]
        start = next_slip(t) if t < end else None
    peak = max([abs(w["x_to"]) for w in slides] + [abs(x)], default=0.0)
    return {"slides": slides, "residual": x, "peak": peak, "lift_off": lift}


CASES = []
for shape, omega in [("one_sine", 6.0), ("one_cosine", 4.0), ("rectangular", 8.0), ("c3", 12.0)]:
    for mu, mu_k, a in [(0.1, 0.1, 0.3), (0.2, 0.2, 0.6), (0.3, 0.2, 0.9), (0.5, 0.45, 1.2)]:
        CASES.append({"shape": shape, "omega": omega, "a_g": a, "mu": mu, "mu_k": mu_k})
# Kinetic well below static: sticks between slides that start anew.
CASES.append({"shape": "one_cosine", "omega": 2.0, "a_g": 0.35, "mu": 0.3, "mu_k": 0.1})
CASES.append({"shape": "c3", "omega": 6.0, "a_g": 0.5, "mu": 0.4, "mu_k": 0.2})
for r in [0.5, -0.5, 1.0, -1.0]:
    CASES.append({"shape": "one_sine", "omega": 5.0, "a_g": 0.7, "mu": 0.25, "ratio": r})
    CASES.append({"shape": "one_cosine", "omega": 3.0, "a_g": 0.5, "mu": 0.2, "mu_k": 0.15, "ratio": r})
for vshape, vw, va, d in [("one_sine", 12.0, 0.4, 0.1), ("one_cosine", 9.0, -0.5, 0.0),
                          ("c3", 20.0, 0.3, 0.2), ("one_sine", 7.0, 1.3, 0.05)]:
    CASES.append({"shape": "one_sine", "omega": 6.0, "a_g": 0.8, "mu": 0.3, "mu_k": 0.25,
                  "vertical": {"shape": vshape, "omega": vw, "a_g": va, "delay": d}})


def main():
    out = subprocess.run(["cargo", "run", "--quiet", "--release", "--example", "sliding_cases"],
                         input=json.dumps(CASES), capture_output=True, text=True, check=True).stdout
    ours = json.loads(out)
    worst_t, worst_x, failed = 0.0, 0.0, 0
    for k, (case, mine) in enumerate(zip(CASES, ours)):
        ref = reference(case)
        ok = len(mine["slides"]) == len(ref["slides"]) and (mine["lift_off"] is None) == (ref["lift_off"] is None)
        dt = dx = 0.0
        if ok:
            for a, b in zip(mine["slides"], ref["slides"]):
                ok &= a["direction"] == b["direction"]
                dt = max(dt, abs(a["from"] - b["from"]), abs(a["to"] - b["to"]))
                dx = max(dx, abs(a["x_to"] - b["x_to"]))
            dx = max(dx, abs(mine["residual"] - ref["residual"]), abs(mine["peak"] - ref["peak"]))
            if ref["lift_off"] is not None:
                dt = max(dt, abs(mine["lift_off"] - ref["lift_off"]))
            ok &= dt <= 1e-8 and dx <= 1e-9
        worst_t, worst_x = max(worst_t, dt), max(worst_x, dx)
        failed += not ok
        seq = " ".join("+" if w["direction"] > 0 else "-" for w in ref["slides"])
        print(f"{'ok  ' if ok else 'FAIL'} {k:2d} {case['shape']:11s} a={case['a_g']:<4} mu={case['mu']:<4} "
              f"mu_k={case.get('mu_k', case['mu']):<5} {('r=' + str(case['ratio'])) if 'ratio' in case else ('own v' if 'vertical' in case else '     ')} "
              f"slides [{seq}] residual {ref['residual']:+.6f} m"
              f"{' lift-off %.6f s' % ref['lift_off'] if ref['lift_off'] is not None else ''}"
              f"  |dt| {dt:.1e} s |dx| {dx:.1e} m")
    print(f"{len(CASES) - failed}/{len(CASES)} agree; largest time difference {worst_t:.1e} s, "
          f"displacement {worst_x:.1e} m")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
