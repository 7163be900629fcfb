#!/usr/bin/env python3
"""Side-by-side speed comparison: topple vs SciPy ``solve_ivp`` (DOP853 + events).

The Python half re-implements, in plain SciPy, the model and the spectrum
algorithm that topple uses for the rocking/overturning of a rigid block under a
one-sine pulse (Makris & Zhang 2001, nonlinear eq. 49), so that both sides do
the same work:

* state y = [theta, theta_dot]; while pivoting on side s (= sign of theta)
      theta'' = -p^2 ( sin(alpha s - theta) + (ug/g) cos(alpha s - theta) )
* one-sine pulse ug(t) = a_p cos(w t - pi/2) on 0 <= t <= T = 2 pi / w;
* at rest the block moves with the ground; rocking starts (from theta =
  theta_dot = 0, on side -sign(ug)) when |ug| first exceeds g tan(alpha),
  located in closed form on the sinusoid; the impact event is armed only once
  that exceedance window is over (as in topple);
* events: impact theta = 0 (theta_dot <- eta theta_dot), overturning
  |theta| = pi/2, pulse end; each leg is one ``solve_ivp(method="DOP853",
  rtol, atol, events=[...])`` call with terminal, directional events;
* rest after an impact slower than 1e-12 p alpha; chattering tails below
  1e-4 p alpha summed in closed form (port of src/dynamics/chatter.rs);
* at the pulse end, overturning is decided exactly from the energy
  (port of src/dynamics/separatrix.rs);
* signature (overturned, mode, impacts), impacts = rocking impacts
  (|theta_dot before| >= 1e-2 p alpha) for survivors;
* spectrum: scan a_p/(alpha g) from tan(alpha)/alpha to a_max with step h,
  bisect (left half first) wherever neighbouring signatures differ until the
  bracket is <= tol (port of src/spectrum/scan.rs).

Run ``python bench/compare_scipy.py --help`` for options; see bench/README.md.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp

# --------------------------------------------------------------------------
# Problem constants (the block of the paper's spectra) and topple's constants
# --------------------------------------------------------------------------
ALPHA = 0.25
P = 2.14
ETA = 0.9
G = 9.81
RTOL = 1e-10
ATOL = 1e-12

REST_VELOCITY = 1e-12           # simulate.rs: |v after| <= this * p alpha -> at rest
ROCKING_IMPACT_VELOCITY = 1e-2  # simulate.rs: rocking impacts, |v before| >= this * p alpha
CHATTER_VELOCITY = 1e-4         # chatter.rs
CHATTER_EXCURSION = 1e-6        # chatter.rs
MAX_FORCED_IMPACTS = 5_000_000  # simulate.rs safeguard

OMEGA_FROM, OMEGA_TO, OMEGA_STEPS = 0.25, 10.0, 40
A_MAX = 20.0
SCAN_STEP = 0.02
TOLERANCE = 1e-4
REF_OMEGA_RATIO = 5.0
REF_A_ALPHA_G = 4.0

HALF_PI = 0.5 * math.pi


# --------------------------------------------------------------------------
# Pulse (port of src/dynamics/excitation.rs, one-sine only)
# --------------------------------------------------------------------------
class Pulse:
    __slots__ = ("amplitude", "omega", "phase", "duration")

    def __init__(self, amplitude: float, omega: float):
        self.amplitude = amplitude
        self.omega = omega
        self.phase = -HALF_PI
        self.duration = 2.0 * math.pi / omega

    def acceleration(self, t: float) -> float:
        if 0.0 <= t <= self.duration:
            return self.amplitude * math.cos(self.omega * t + self.phase)
        return 0.0

    def next_exceedance(self, frm: float, threshold: float):
        """(start, end, side) of the first stretch with |ug| > threshold at or
        after ``frm``, in closed form; None if there is none."""
        amp = abs(self.amplitude)
        if amp <= threshold or frm >= self.duration:
            return None
        frm = max(frm, 0.0)
        w = self.omega
        beta = math.acos(threshold / amp)
        chi0 = w * frm + self.phase
        m = math.floor(chi0 / math.pi)
        offset = chi0 - m * math.pi
        if offset < beta:
            chi_start, k = chi0, m
        elif offset > math.pi - beta:
            chi_start, k = chi0, m + 1
        else:
            chi_start, k = (m + 1) * math.pi - beta, m + 1
        start = frm if chi_start == chi0 else (chi_start - self.phase) / w
        if start >= self.duration:
            return None
        end = min(((k * math.pi + beta) - self.phase) / w, self.duration)
        cos_sign = 1.0 if k % 2 == 0 else -1.0
        accel_sign = cos_sign * math.copysign(1.0, self.amplitude)
        return start, end, -accel_sign


# --------------------------------------------------------------------------
# Events (terminal, directional), one set per side
# --------------------------------------------------------------------------
def _make_events(side: float):
    def impact(t, y):
        return y[0]

    impact.terminal = True
    impact.direction = -side  # theta returns to 0 from the side s

    def overturn(t, y):
        return side * y[0] - HALF_PI

    overturn.terminal = True
    overturn.direction = 1.0
    return impact, overturn


EVENTS = {1.0: _make_events(1.0), -1.0: _make_events(-1.0)}


# --------------------------------------------------------------------------
# Exact decisions (ports of separatrix.rs and chatter.rs, nonlinear)
# --------------------------------------------------------------------------
def barrier_excess(theta: float, theta_dot: float) -> float:
    d = ALPHA - abs(theta)
    return 0.5 * (theta_dot / P) ** 2 - 2.0 * math.sin(0.5 * d) ** 2


BARRIER = 2.0 * math.sin(0.5 * ALPHA) ** 2


def decide(theta: float, theta_dot: float, side: float):
    """Free-vibration outcome from the pulse-end state: ('over', impacts) or None."""
    gamma = side * theta
    gamma_dot = side * theta_dot
    if gamma >= HALF_PI:
        return 0
    excess = barrier_excess(theta, theta_dot)
    outward = gamma_dot > 0.0
    if gamma > ALPHA:
        reaches_zero = (not outward) and excess > 0.0
    else:
        reaches_zero = not (outward and excess > 0.0)
    if not reaches_zero:
        return 0
    if gamma == 0.0 and gamma_dot == 0.0:
        return None
    after = ETA * ETA * (excess + BARRIER) - BARRIER
    return 1 if after > 0.0 else None


def settle(pulse: Pulse, t: float, v: float, v_rest: float, threshold: float):
    """Closed-form sum of a chattering tail: (rest_time, impacts) or None."""
    speed = abs(v)
    if not (0.0 < ETA < 1.0) or speed <= v_rest or speed > CHATTER_VELOCITY * P * ALPHA:
        return None
    u = pulse.acceleration(t) / G
    p2 = P * P
    # Pull-back accelerations at theta = 0 on sides +1 and -1.
    plus = p2 * (math.sin(ALPHA) + u * math.cos(ALPHA))
    minus = p2 * (math.sin(ALPHA) - u * math.cos(ALPHA))
    if not (plus > 0.0 and minus > 0.0):
        return None
    if speed * speed / (2.0 * min(plus, minus)) > CHATTER_EXCURSION * ALPHA:
        return None
    own, other = (plus, minus) if v > 0.0 else (minus, plus)
    duration = 2.0 * speed * (1.0 / own + ETA / other) / (1.0 - ETA * ETA)
    rest_time = t + duration
    ex = pulse.next_exceedance(t, threshold)
    if ex is not None and ex[0] <= t + 2.0 * duration:
        return None
    if rest_time >= pulse.duration:
        return None
    impacts = max(1, math.ceil(math.log(v_rest / speed) / math.log(ETA)))
    return rest_time, impacts


# --------------------------------------------------------------------------
# One simulation (the outcome only, as topple's spectra compute it)
# --------------------------------------------------------------------------
def _leg(pulse: Pulse, side: float, t0: float, y0, t_stop: float, lift_until: float,
         rtol: float, atol: float):
    """Integrates one forced leg on ``side``. Returns ('impact', t, v),
    ('over', t) or ('reached', t, y)."""
    p2 = P * P
    a_side = ALPHA * side
    aog = pulse.amplitude / G
    w, ph = pulse.omega, pulse.phase
    sin, cos = math.sin, math.cos

    def rhs(t, y):
        x = a_side - y[0]
        return (y[1], -p2 * (sin(x) + aog * cos(w * t + ph) * cos(x)))

    impact, overturn = EVENTS[side]
    t, y = t0, y0
    # Lift-off from rest: the impact event is armed only after the exceedance window.
    if lift_until > t:
        t1 = min(lift_until, t_stop)
        sol = solve_ivp(rhs, (t, t1), y, method="DOP853", rtol=rtol, atol=atol,
                        events=(overturn,))
        if sol.status == -1:
            raise RuntimeError(sol.message)
        if sol.t_events[0].size:
            return ("over", float(sol.t_events[0][0]))
        t, y = t1, sol.y[:, -1]
        if t >= t_stop:
            return ("reached", t, y)
    if t >= t_stop:
        return ("reached", t_stop, y)
    sol = solve_ivp(rhs, (t, t_stop), y, method="DOP853", rtol=rtol, atol=atol,
                    events=(impact, overturn))
    if sol.status == -1:
        raise RuntimeError(sol.message)
    ti = sol.t_events[0]
    to = sol.t_events[1]
    if ti.size and (not to.size or ti[0] <= to[0]):
        return ("impact", float(ti[0]), float(sol.y_events[0][0][1]))
    if to.size:
        return ("over", float(to[0]))
    return ("reached", t_stop, sol.y[:, -1])


def simulate(a_alpha_g: float, omega_ratio: float, rtol: float = RTOL, atol: float = ATOL):
    """Signature (overturned, mode, impacts) of one block/pulse, as topple's
    ``Line::classify``: impacts before overturning, or rocking impacts of a survivor."""
    pulse = Pulse(a_alpha_g * ALPHA * G, omega_ratio * P)
    threshold = G * math.tan(ALPHA)
    v_rest = REST_VELOCITY * P * ALPHA
    v_rocking = ROCKING_IMPACT_VELOCITY * P * ALPHA
    impact_count = 0
    rocking_impacts = 0
    forced_impacts = 0
    overturned = False
    t = 0.0
    rocking = None  # (y, side, lift_until) while rocking; None at rest
    while True:
        if rocking is None:
            ex = pulse.next_exceedance(t, threshold)
            if ex is None:
                break
            t = ex[0]
            rocking = ((0.0, 0.0), ex[2], ex[1])
            continue
        y, side, lift_until = rocking
        end = _leg(pulse, side, t, y, pulse.duration, lift_until, rtol, atol)
        if end[0] == "impact":
            _, ti, v = end
            impact_count += 1
            if abs(v) >= v_rocking:
                rocking_impacts += 1
            after = ETA * v
            t = ti
            forced_impacts += 1
            if forced_impacts > MAX_FORCED_IMPACTS:
                raise RuntimeError("impact limit reached during the pulse")
            if abs(after) <= v_rest:
                rocking = None
                continue
            settled = settle(pulse, ti, after, v_rest, threshold)
            if settled is not None:
                impact_count += settled[1]
                t = settled[0]
                rocking = None
                continue
            rocking = ((0.0, after), math.copysign(1.0, after), ti)
        elif end[0] == "over":
            overturned = True
            break
        else:  # pulse end: exact decision from the state
            _, _, yend = end
            more = decide(float(yend[0]), float(yend[1]), side)
            if more is not None:
                overturned = True
                impact_count += more
                rocking_impacts += more
            break
    if overturned:
        return (True, 1 if impact_count > 0 else 2, impact_count)
    return (False, None, rocking_impacts)


# --------------------------------------------------------------------------
# Spectrum line (port of src/spectrum/scan.rs and the grid of overturning.rs)
# --------------------------------------------------------------------------
def threshold_alpha_g() -> float:
    return (G * math.tan(ALPHA)) / (G * ALPHA)


def grid(a_max: float, h: float):
    thr = threshold_alpha_g()
    if a_max <= thr:
        return [thr]
    n = math.ceil((a_max - thr) / h) + 1
    return [thr + h * k if k + 1 < n else max(a_max, thr) for k in range(n)]


def scan_line(omega_ratio: float, a_max=A_MAX, h=SCAN_STEP, tol=TOLERANCE,
              rtol=RTOL, atol=ATOL):
    """Transitions of one frequency: list of dicts like topple's, and the
    number of simulations run."""
    count = [0]
    transitions = []

    def classify(level):
        count[0] += 1
        return simulate(level, omega_ratio, rtol, atol)

    def record(a, b):
        at = 0.5 * (a[0] + b[0])
        if not a[1][0] and b[1][0]:
            transitions.append({"a_alpha_g": at, "direction": "up", "mode": b[1][1],
                                "impacts": b[1][2], "bracket": [a[0], b[0]]})
        elif a[1][0] and not b[1][0]:
            transitions.append({"a_alpha_g": at, "direction": "down", "mode": a[1][1],
                                "impacts": a[1][2], "bracket": [a[0], b[0]]})

    def refine(a, b):
        if b[0] - a[0] <= tol:
            record(a, b)
            return
        mid = 0.5 * (a[0] + b[0])
        m = (mid, classify(mid))
        if m[1] != a[1]:
            refine(a, m)
        if m[1] != b[1]:
            refine(m, b)

    levels = grid(a_max, h)
    prev = (levels[0], classify(levels[0]))
    for level in levels[1:]:
        cur = (level, classify(level))
        if cur[1] != prev[1]:
            refine(prev, cur)
        prev = cur
    return transitions, count[0]


def omega_grid():
    n = OMEGA_STEPS
    return [OMEGA_FROM + (OMEGA_TO - OMEGA_FROM) * k / (n - 1) for k in range(n)]


# --------------------------------------------------------------------------
# topple
# --------------------------------------------------------------------------
def find_topple(arg: str | None, repo: Path, rebuild: bool) -> Path:
    if arg:
        path = Path(arg)
        if not path.exists():
            sys.exit(f"--topple {arg}: no such file")
        return path
    path = repo / "target" / "release" / "topple"
    if rebuild or not path.exists():
        print(f"building topple: cargo build --release (in {repo}) ...", flush=True)
        subprocess.run(["cargo", "build", "--release"], cwd=repo, check=True)
    return path


def spectrum_spec(omegas) -> dict:
    return {
        "kind": "spectrum",
        "block": {"alpha": ALPHA, "p": P, "eta": ETA, "g": G},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": omegas,
        "a_max_alpha_g": A_MAX,
        "tolerance": TOLERANCE,
        "scan_step_alpha_g": SCAN_STEP,
        "solver": {"method": "dop853", "rtol": RTOL, "atol": ATOL},
    }


def run_topple(exe: Path, spec: dict, threads: int | None, repeats: int):
    """Runs ``topple run`` ``repeats`` times; returns (last result, median
    in-process wall_time_s, median process wall time incl. start-up)."""
    env = dict(os.environ)
    env.pop("RAYON_NUM_THREADS", None)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(spec, f)
        spec_path = f.name
    try:
        inner, outer, doc = [], [], None
        for _ in range(repeats):
            t0 = time.perf_counter()
            out = subprocess.run([str(exe), "run", spec_path], env=env, check=True,
                                 capture_output=True, text=True).stdout
            outer.append(time.perf_counter() - t0)
            doc = json.loads(out)
            inner.append(doc["numerics"]["wall_time_s"])
    finally:
        os.unlink(spec_path)
    return doc, statistics.median(inner), statistics.median(outer)


# --------------------------------------------------------------------------
# Comparison of transitions
# --------------------------------------------------------------------------
def compare_transitions(ours, theirs, a_tol):
    """Returns (max |da| over matched pairs, list of mismatch descriptions)."""
    problems = []
    if len(ours) != len(theirs):
        problems.append(f"count differs: SciPy {len(ours)}, topple {len(theirs)}")
    max_da = 0.0
    for i, (a, b) in enumerate(zip(ours, theirs)):
        da = abs(a["a_alpha_g"] - b["a_alpha_g"])
        max_da = max(max_da, da)
        diffs = []
        if a["direction"] != b["direction"]:
            diffs.append("direction")
        if a["mode"] != b["mode"]:
            diffs.append("mode")
        if da > a_tol:
            diffs.append(f"|da|={da:.2e}")
        if diffs:
            problems.append(
                f"#{i}: {', '.join(diffs)} - SciPy {a['direction']} mode {a['mode']} "
                f"({a['impacts']} imp) at {a['a_alpha_g']:.6f}; topple {b['direction']} "
                f"mode {b['mode']} ({b['impacts']} imp) at {b['a_alpha_g']:.6f}")
    if len(ours) != len(theirs):
        n = min(len(ours), len(theirs))
        for name, extra in (("SciPy", ours[n:]), ("topple", theirs[n:])):
            for t in extra:
                problems.append(f"only in {name}: {t['direction']} mode {t['mode']} "
                                f"({t['impacts']} imp) at {t['a_alpha_g']:.6f}")
    return max_da, problems


# --------------------------------------------------------------------------
# Output helpers
# --------------------------------------------------------------------------
def fmt_t(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:.1f} us"
    if s < 1.0:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def table(headers, rows, align=None):
    cols = list(zip(*([headers] + rows))) if rows else [[h] for h in headers]
    widths = [max(len(str(c)) for c in col) for col in cols]
    align = align or ["<"] + [">"] * (len(headers) - 1)
    def line(cells):
        return "  ".join(f"{str(c):{a}{w}}" for c, a, w in zip(cells, align, widths))
    out = [line(headers), "  ".join("-" * w for w in widths)]
    out += [line(r) for r in rows]
    print("\n".join(out))


def pick_subset(n_all: int, k: int):
    if k >= n_all:
        return list(range(n_all))
    if k == 1:
        return [n_all // 2]
    return sorted({round(i * (n_all - 1) / (k - 1)) for i in range(k)})


# --------------------------------------------------------------------------
# Main
# --------------------------------------------------------------------------
def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--topple", help="path to the topple binary (default: "
                    "target/release/topple, built with cargo if missing)")
    ap.add_argument("--rebuild", action="store_true",
                    help="run cargo build --release even if the binary exists")
    ap.add_argument("--full", action="store_true",
                    help="SciPy on all 40 frequencies (takes minutes)")
    ap.add_argument("--subset", type=int, default=4,
                    help="number of evenly chosen frequencies for SciPy (default 4)")
    ap.add_argument("--runs", type=int, default=50,
                    help="SciPy repetitions of the reference simulation (default 50)")
    ap.add_argument("--repeats", type=int, default=5,
                    help="topple repetitions per measurement; medians reported (default 5)")
    ap.add_argument("--a-tol", type=float, default=2e-4,
                    help="largest |da| (alpha g) for transitions to match (default 2e-4)")
    ap.add_argument("--json", metavar="PATH", help="also write all measurements as JSON")
    args = ap.parse_args()

    repo = Path(__file__).resolve().parent.parent
    built = find_topple(args.topple, repo, args.rebuild)
    # Measure one fixed binary even if target/ is rebuilt while this runs.
    tmpdir = tempfile.mkdtemp(prefix="topple-bench-")
    exe = Path(tmpdir) / "topple"
    shutil.copy2(built, exe)
    try:
        return run_all(args, built, exe)
    finally:
        shutil.rmtree(tmpdir, ignore_errors=True)


def loadavg() -> str:
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


def run_all(args, built: Path, exe: Path) -> int:
    cores = os.cpu_count() or 1
    wall_start = time.perf_counter()
    version = subprocess.run([str(exe), "--version"], capture_output=True,
                             text=True).stdout.strip()
    cpu = platform.processor() or platform.machine()
    try:
        for ln in Path("/proc/cpuinfo").read_text().splitlines():
            if ln.startswith("model name"):
                cpu = ln.split(":", 1)[1].strip()
                break
    except OSError:
        pass

    print("topple vs SciPy solve_ivp(DOP853) - rocking block, one-sine pulse, nonlinear eq. 49")
    print(f"machine: {cpu}, {cores} logical cores; Python {platform.python_version()}, "
          f"numpy {np.__version__}, scipy {scipy.__version__}; {version} ({built})")
    print(f"load average at start: {loadavg()} (other work on the machine skews timings)")
    print(f"block alpha={ALPHA} p={P} eta={ETA} g={G}; rtol={RTOL:g} atol={ATOL:g}; "
          f"spectrum: omega_p/p {OMEGA_FROM}..{OMEGA_TO} ({OMEGA_STEPS} values), "
          f"a_p/(alpha g) tan(a)/a..{A_MAX:g} step {SCAN_STEP}, bisection to {TOLERANCE:g}")
    print()
    results: dict = {"machine": cpu, "cores": cores, "numpy": np.__version__,
                     "scipy": scipy.__version__, "topple": version}

    # ---------------------------------------------------------------- 1
    sig = simulate(REF_A_ALPHA_G, REF_OMEGA_RATIO)  # warm-up (imports, caches)
    t0 = time.perf_counter()
    for _ in range(args.runs):
        sig = simulate(REF_A_ALPHA_G, REF_OMEGA_RATIO)
    sp_ref = (time.perf_counter() - t0) / args.runs

    t0 = time.perf_counter()
    sp_line, sp_line_sims = scan_line(REF_OMEGA_RATIO)
    sp_line_t = time.perf_counter() - t0
    sp_line_per = sp_line_t / sp_line_sims

    tp_line_doc, tp_line_t, _ = run_topple(exe, spectrum_spec([REF_OMEGA_RATIO]), 1,
                                           args.repeats)
    tp_line_sims = tp_line_doc["numerics"]["simulations"]
    tp_line_per = tp_line_t / tp_line_sims

    th_spec = {"kind": "time_history", "block": {"alpha": ALPHA, "p": P, "eta": ETA, "g": G},
               "pulse": {"type": "one_sine", "omega_ratio": REF_OMEGA_RATIO,
                         "a_p_alpha_g": REF_A_ALPHA_G},
               "formulation": "nonlinear",
               "solver": {"method": "dop853", "rtol": RTOL, "atol": ATOL},
               "outputs": {"series": 0, "reactions": False, "impacts": False,
                           "max_free_impacts": 0}}
    th_doc, th_t, _ = run_topple(exe, th_spec, 1, max(args.repeats, 11))
    tp_sig = (th_doc["overturned"], th_doc["mode"], th_doc["impact_count"])

    print(f"1. Per simulation (single thread; reference case omega_p/p = {REF_OMEGA_RATIO:g}, "
          f"a_p = {REF_A_ALPHA_G:g} alpha g)")
    print(f"   outcome (overturned, mode, impacts): SciPy {sig}, topple {tp_sig}"
          + ("" if sig == tp_sig else "   <-- MISMATCH"))
    table(["per simulation", "SciPy", "topple", "SciPy/topple"], [
        [f"(a) reference case: SciPy mean of {args.runs} runs vs topple's per-sim mean (b)",
         fmt_t(sp_ref), fmt_t(tp_line_per), f"{sp_ref / tp_line_per:,.0f}x"],
        [f"(b) mean over the omega_p/p={REF_OMEGA_RATIO:g} spectrum "
         f"(SciPy {sp_line_sims} sims, topple {tp_line_sims})", fmt_t(sp_line_per),
         fmt_t(tp_line_per), f"{sp_line_per / tp_line_per:,.0f}x"],
        ["(c) info: reference case, topple time_history, 1 cold call per process (median)",
         fmt_t(sp_ref), fmt_t(th_t), f"{sp_ref / th_t:,.0f}x"],
    ])
    print(f"   topple per-sim = numerics.wall_time_s / numerics.simulations of "
          f"`topple run` with RAYON_NUM_THREADS=1 (median of {args.repeats}; no process start-up)")
    print()
    results["per_simulation"] = {
        "scipy_reference_s": sp_ref, "scipy_line_per_sim_s": sp_line_per,
        "scipy_line_sims": sp_line_sims, "scipy_line_s": sp_line_t,
        "topple_line_per_sim_s": tp_line_per, "topple_line_sims": tp_line_sims,
        "topple_line_s": tp_line_t, "topple_time_history_s": th_t,
        "signature_scipy": list(sig), "signature_topple": list(tp_sig)}

    # ---------------------------------------------------------------- 2
    omegas = omega_grid()
    idx = list(range(len(omegas))) if args.full else pick_subset(len(omegas), args.subset)
    sub = [omegas[i] for i in idx]
    print(f"2. Per spectrum: SciPy on {len(sub)} of {len(omegas)} frequencies "
          f"(omega_p/p = {', '.join(f'{w:g}' for w in sub)})", flush=True)

    per_freq = []
    sp_sub_t = 0.0
    sp_sub_sims = 0
    sp_lines = {}
    for w in sub:
        if w == REF_OMEGA_RATIO:
            tr, n, dt = sp_line, sp_line_sims, sp_line_t  # already computed in part 1
        else:
            t0 = time.perf_counter()
            tr, n = scan_line(w)
            dt = time.perf_counter() - t0
        sp_lines[w] = tr
        sp_sub_t += dt
        sp_sub_sims += n
        tdoc, tt, _ = run_topple(exe, spectrum_spec([w]), 1, args.repeats)
        per_freq.append((w, n, dt, tdoc["numerics"]["simulations"], tt,
                         tdoc["spectrum"][0]["transitions"]))
        print(f"   omega_p/p = {w:<5g}: SciPy {n} sims in {dt:.2f} s", flush=True)

    full_spec = spectrum_spec({"from": OMEGA_FROM, "to": OMEGA_TO, "steps": OMEGA_STEPS})
    if not args.full:
        sub_spec = spectrum_spec(sub)
        tp_sub1_doc, tp_sub1, tp_sub1_proc = run_topple(exe, sub_spec, 1, args.repeats)
        _, tp_subN, tp_subN_proc = run_topple(exe, sub_spec, None, args.repeats)
        tp_sub_sims = tp_sub1_doc["numerics"]["simulations"]
    tp_full1_doc, tp_full1, tp_full1_proc = run_topple(exe, full_spec, 1, args.repeats)
    tp_fullN_doc, tp_fullN, tp_fullN_proc = run_topple(exe, full_spec, None, args.repeats)
    tp_full_sims = tp_full1_doc["numerics"]["simulations"]

    print()
    table(["omega_p/p", "SciPy sims", "SciPy time", "topple sims", "topple time (1 thr)",
           "SciPy/topple"],
          [[f"{w:g}", n, fmt_t(dt), tn, fmt_t(tt), f"{dt / tt:,.0f}x"]
           for (w, n, dt, tn, tt, _) in per_freq])
    print()

    topple_full_rows = [
        [f"topple, 40 frequencies, {cores} threads", tp_full_sims,
         f"{fmt_t(tp_fullN)} ({fmt_t(tp_fullN_proc)})", "", ""],
        ["topple, 40 frequencies, 1 thread", tp_full_sims,
         f"{fmt_t(tp_full1)} ({fmt_t(tp_full1_proc)})", "", ""],
    ]
    if args.full:
        sp_full_t = sp_sub_t
        tp_sub1 = tp_subN = None
        rows = [["SciPy, 40 frequencies (measured, 1 process)", sp_sub_sims, fmt_t(sp_full_t),
                 f"{sp_full_t / tp_fullN:,.0f}x", f"{sp_full_t / tp_full1:,.0f}x"]]
        rows += topple_full_rows
    else:
        scale = len(omegas) / len(sub)
        sp_full_t = sp_sub_t * tp_full1 / tp_sub1
        rows = [
            [f"SciPy, subset of {len(sub)} (measured, 1 process)", sp_sub_sims,
             fmt_t(sp_sub_t), f"{sp_sub_t / tp_subN:,.0f}x", f"{sp_sub_t / tp_sub1:,.0f}x"],
            [f"topple, subset of {len(sub)}, {cores} threads", tp_sub_sims,
             f"{fmt_t(tp_subN)} ({fmt_t(tp_subN_proc)})", "", ""],
            [f"topple, subset of {len(sub)}, 1 thread", tp_sub_sims,
             f"{fmt_t(tp_sub1)} ({fmt_t(tp_sub1_proc)})", "", ""],
            ["SciPy, 40 frequencies - EXTRAPOLATED (subset time x topple's 1-thread "
             "40/subset time ratio)", f"~{round(sp_sub_sims * tp_full_sims / tp_sub_sims)}",
             fmt_t(sp_full_t), f"{sp_full_t / tp_fullN:,.0f}x",
             f"{sp_full_t / tp_full1:,.0f}x"],
            [f"SciPy, 40 frequencies - EXTRAPOLATED (subset time x {scale:g}, naive)", "",
             fmt_t(sp_sub_t * scale), f"{sp_sub_t * scale / tp_fullN:,.0f}x",
             f"{sp_sub_t * scale / tp_full1:,.0f}x"],
        ] + topple_full_rows
    table(["run", "sims", "wall time", f"vs topple {cores} thr", "vs topple 1 thr"], rows)
    print("   topple wall time = numerics.wall_time_s (in-process), median of "
          f"{args.repeats}; in parentheses the whole `topple run` process incl. start-up "
          "and JSON output.")
    if not args.full:
        print("   Ratios compare like with like: SciPy subset vs topple subset, SciPy 40 vs "
              "topple 40.")
    print()
    results["per_spectrum"] = {
        "subset": sub, "scipy_subset_s": sp_sub_t, "scipy_subset_sims": sp_sub_sims,
        "scipy_40_s": sp_full_t, "scipy_40_extrapolated": not args.full,
        "topple_subset_1thread_s": tp_sub1, "topple_subset_nthreads_s": tp_subN,
        "topple_40_1thread_s": tp_full1, "topple_40_nthreads_s": tp_fullN,
        "topple_40_sims": tp_full_sims,
        "per_frequency": [{"omega_ratio": w, "scipy_sims": n, "scipy_s": dt,
                           "topple_sims": tn, "topple_1thread_s": tt}
                          for (w, n, dt, tn, tt, _) in per_freq]}

    # ---------------------------------------------------------------- 3
    print(f"3. Cross-check of transitions (same count, direction, mode; "
          f"|da| <= {args.a_tol:g} alpha g)")
    full_lines = {round(l["omega_ratio"], 9): l["transitions"]
                  for l in tp_fullN_doc["spectrum"]}
    rows, all_problems = [], []
    for (w, _, _, _, _, tp_single) in per_freq:
        tp_tr = full_lines.get(round(w, 9), tp_single)
        ours = sp_lines[w]
        max_da, problems = compare_transitions(ours, tp_tr, args.a_tol)
        rows.append([f"{w:g}", len(ours), len(tp_tr),
                     f"{max_da:.1e}" if ours and tp_tr else "-",
                     "OK" if not problems else f"{len(problems)} MISMATCH"])
        all_problems += [f"   omega_p/p = {w:g}: {p}" for p in problems]
    # The single-frequency reference line of part 1 as well, if not in the subset.
    if REF_OMEGA_RATIO not in sub:
        tp_tr = tp_line_doc["spectrum"][0]["transitions"]
        max_da, problems = compare_transitions(sp_line, tp_tr, args.a_tol)
        rows.append([f"{REF_OMEGA_RATIO:g} (part 1)", len(sp_line), len(tp_tr),
                     f"{max_da:.1e}" if sp_line and tp_tr else "-",
                     "OK" if not problems else f"{len(problems)} MISMATCH"])
        all_problems += [f"   omega_p/p = {REF_OMEGA_RATIO:g}: {p}" for p in problems]
    table(["omega_p/p", "SciPy transitions", "topple transitions", "max |da|", "status"], rows)
    if all_problems:
        print("   mismatches:")
        print("\n".join(all_problems))
    else:
        print("   all transitions agree.")
    results["cross_check_problems"] = all_problems
    elapsed = time.perf_counter() - wall_start
    results["elapsed_s"] = elapsed
    print()
    print(f"total run time of this script: {elapsed:.0f} s; load average at end: {loadavg()}")
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
