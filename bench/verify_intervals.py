#!/usr/bin/env python3
"""Checks a forensic query's or record spectrum's certain intervals, gaps
and mixed zones against time histories at the same scale.

  python3 bench/verify_intervals.py SPEC.json [--points N] [--zone-points M]

SPEC is a record forensic query (`ground_motion` a file beside it, or
samples) with one observation, or a record spectrum with one size. The
script runs it with `topple run`, then at N random points inside the
certain intervals and N inside the certain gaps (uniform over their total
width) runs the time history of the same block under the record scaled
there, and counts disagreements; in each mixed zone it runs M evenly spaced
time histories and compares their fraction with the zone's.
"""
import argparse, json, os, random, subprocess, sys, tempfile

BIN = os.environ.get("TOPPLE_BIN", "target/release/topple")


def run(spec, cwd):
    with tempfile.NamedTemporaryFile("w", suffix=".json", dir=cwd, delete=False) as f:
        json.dump(spec, f)
        name = f.name
    try:
        out = subprocess.run([BIN, "run", name], capture_output=True, text=True, check=True)
    finally:
        os.unlink(name)
    return json.loads(out.stdout)


def overturns(block, gm, scale, formulation, contact, cwd):
    spec = {"kind": "time_history", "block": block, "formulation": formulation,
            "ground_motion": {"dt": gm["dt"], "unit": "m/s2",
                              "acc": [a * scale for a in gm["acc"]]},
            "outputs": {"reactions": False, "impacts": False}}
    if contact:
        spec["contact"] = contact
    return run(spec, cwd)["overturned"]


def pick(intervals, n, rng):
    total = sum(b - a for a, b in intervals)
    if total <= 0:
        return []
    out = []
    for _ in range(n):
        x = rng.uniform(0, total)
        for a, b in intervals:
            if x <= b - a:
                out.append(a + x)
                break
            x -= b - a
    return out


def gaps(certain, zones, lo, hi):
    cuts = sorted([tuple(i) for i in certain] + [(z["from"], z["to"]) for z in zones])
    out, at = [], lo
    for a, b in cuts:
        if a > at:
            out.append((at, a))
        at = max(at, b)
    if hi > at:
        out.append((at, hi))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("spec")
    ap.add_argument("--points", type=int, default=40)
    ap.add_argument("--zone-points", type=int, default=60)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    cwd = os.path.dirname(os.path.abspath(args.spec))
    spec = json.load(open(args.spec))
    rng = random.Random(args.seed)
    result = run(spec, cwd)
    job = result["spec"]
    gm = job["ground_motion"]
    contact = job.get("contact")
    formulation = job["formulation"]
    if result["kind"] == "forensic":
        o = job["observations"][0]
        block, seen = o["block"], o["overturned"]
        per = result["per_observation"][0]
        certain = per["consistent_scale"]
        zones = per.get("mixed_scale", [])
        hit = lambda over: over == seen
        rng_lo = result["scale"]["from"] if result.get("scale") else certain[0][0]
        rng_hi = result["scale"]["to"] if result.get("scale") else certain[-1][1]
    else:
        size = result["sizes"][0]
        b = job["block"]
        block = {"alpha": b["alpha"], "p": size["p"], "eta": b["eta"], "g": b["g"]}
        certain = [[t, u] for t, u in bands(size)]
        zones = size.get("mixed", [])
        hit = lambda over: over
        rng_lo, rng_hi = size["threshold_scale"], job["scale"]["to"]
    print(f"{result['kind']}: {len(certain)} certain intervals, {len(zones)} mixed zones;"
          f" simulations {result['numerics']['simulations']}")
    wrong = 0
    inside = pick(certain, args.points, rng)
    outside = pick(gaps(certain, zones, rng_lo, rng_hi), args.points, rng)
    for x in inside:
        if not hit(overturns(block, gm, x, formulation, contact, cwd)):
            wrong += 1
            print(f"  inside {x:.6f}: disagrees")
    for x in outside:
        if hit(overturns(block, gm, x, formulation, contact, cwd)):
            wrong += 1
            print(f"  gap {x:.6f}: disagrees")
    print(f"intervals and gaps: {wrong} of {len(inside) + len(outside)} points disagree")
    worst = 0.0
    for z in zones:
        n = args.zone_points
        xs = [z["from"] + (k + 0.5) * (z["to"] - z["from"]) / n for k in range(n)]
        f = sum(hit(overturns(block, gm, x, formulation, contact, cwd)) for x in xs) / n
        worst = max(worst, abs(f - z["fraction"]))
        print(f"  zone [{z['from']:.5f}, {z['to']:.5f}]: fraction {z['fraction']:.3f}"
              f" ({z['probes']} probes), {n} time histories {f:.3f}")
    print(f"zones: largest difference of fraction {worst:.3f}")
    return 1 if wrong else 0


def bands(size):
    """A record spectrum size's certain overturning bands, in scale."""
    out, up = [], None
    for t in size["transitions"]:
        if t["direction"] == "up":
            up = t["scale"]
        elif up is not None:
            out.append((up, t["scale"]))
            up = None
    if up is not None:
        out.append((up, size.get("scale_to", 1e9)))
    return out


if __name__ == "__main__":
    sys.exit(main())
