#!/usr/bin/env python3
"""Fragility campaigns through the service: a 100,000-simulation pulse
fragility (the README's PBR walkthrough rock and pulse family, 20 stripes of
0.1–1.5 g × 5,000 samples) and a 10,000-simulation record fragility (the same
rock under four synthetic 2,000-sample records, 20 stripes × 500 samples),
each timed from submission to the finished result on

  1. one instance on embedded SQLite with both cores (--workers 2),
  2. one instance on PostgreSQL with one worker thread (--workers 1),
  3. two instances on one PostgreSQL, one worker thread each.

Prints wall times, simulations per second, the tasks each instance computed,
and checks that every configuration returns the same stripes and fit.
Standard library only; needs PostgreSQL at 127.0.0.1:5432 (user postgres,
trust auth) for 2 and 3, and the release binary.

    python3 bench/fragility_scale.py [--topple target/release/topple]
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import tempfile
import time

from scale_out import http, start

ADMIN = os.environ.get("TOPPLE_TEST_POSTGRES", "postgres://postgres@127.0.0.1:5432/postgres")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def psql(sql, db=ADMIN):
    out = subprocess.run(["psql", db, "-qAt", "-c", sql], check=True, capture_output=True, text=True)
    return out.stdout


def synthetic(seed, n, dt, peak, f_lo, f_hi):
    """tests/common/synthetic.rs in Python (same generator, same samples)."""
    state = seed
    mask = (1 << 64) - 1

    def uniform():
        nonlocal state
        state = (state * 6364136223846793005 + 1442695040888963407) & mask
        return (state >> 11) / float(1 << 53)

    comps = []
    for _ in range(24):
        f = f_lo * (f_hi / f_lo) ** uniform()
        phase = 2 * math.pi * uniform()
        comps.append((2 * math.pi * f, phase, 0.5 + uniform()))
    ramp = 0.1 * n * dt
    raw = []
    for k in range(n):
        t = k * dt
        raw.append(min(t / ramp, 1.0) * sum(w8 * math.sin(w * t + ph) for w, ph, w8 in comps))
    peak_raw = max(abs(a) for a in raw)
    return [peak * a / peak_raw for a in raw]


def pulse_spec():
    with open(os.path.join(ROOT, "specs", "pbr_fragility.json")) as f:
        spec = json.load(f)
    spec["stripes"] = {"from": 0.1, "to": 1.5, "steps": 20}
    spec["samples"] = 5000
    return spec


def record_spec():
    spec = pulse_spec()
    del spec["pulse"]
    spec["ground_motions"] = [
        {"name": f"synthetic {k}", "dt": 0.01, "unit": "m/s2", "acc": synthetic(11 + k, 2000, 0.01, 3.0, 0.3, 5.0)}
        for k in range(4)
    ]
    spec["samples"] = 500
    return spec


def campaign(base, spec):
    t0 = time.perf_counter()
    job = http("POST", f"{base}/v1/jobs", spec)
    while job["status"] not in ("succeeded", "failed", "canceled"):
        time.sleep(0.02)
        job = http("GET", f"{base}/v1/jobs/{job['id']}")
    wall = time.perf_counter() - t0
    assert job["status"] == "succeeded", job
    return job["id"], wall, http("GET", f"{base}/v1/jobs/{job['id']}/result")


def run(binary, config, specs):
    """(wall, result, tasks by instance) per spec under one configuration."""
    procs, db, tmp = [], None, None
    try:
        if config == "sqlite":
            tmp = tempfile.mkdtemp(prefix="topple-fragility-")
            procs.append(start(binary, f"sqlite://{tmp}/topple.db", "A", workers=2))
        else:
            name = f"topple_fragility_{os.getpid()}_{config}"
            psql(f"CREATE DATABASE {name}")
            db = ADMIN.rsplit("/", 1)[0] + "/" + name
            for i in range(2 if config == "pg2" else 1):
                procs.append(start(binary, db, chr(ord("A") + i)))
        out = []
        for spec in specs:
            id_, wall, result = campaign(procs[0][1], spec)
            by = {}
            if db:
                rows = psql(
                    "SELECT split_part(done_by, '#', 1), count(*) FROM tasks WHERE computation_id = "
                    f"(SELECT computation_id FROM jobs WHERE id = '{id_}') GROUP BY 1 ORDER BY 1",
                    db,
                )
                by = dict(line.split("|") for line in rows.split())
            out.append((wall, result, by))
        return out
    finally:
        for p, _ in procs:
            p.terminate()
            p.wait(timeout=60)
        if db:
            psql(f"DROP DATABASE IF EXISTS {db.rsplit('/', 1)[1]} WITH (FORCE)")
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--topple", default="target/release/topple")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="topple-bin-")
    binary = shutil.copy(a.topple, os.path.join(tmp, "topple"))
    specs = [("pulse fragility, 100,000 simulations", pulse_spec()),
             ("record fragility, 10,000 simulations of 2,000 samples", record_spec())]
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    runs = {}
    labels = {"sqlite": "one instance, SQLite, 2 workers",
              "pg1": "one instance, PostgreSQL, 1 worker",
              "pg2": "two instances, PostgreSQL, 1 worker each"}
    for config in ["sqlite", "pg1", "pg2"]:
        runs[config] = run(binary, config, [s for _, s in specs])
    for i, (title, _) in enumerate(specs):
        print(title)
        ref = runs["sqlite"][i][1]
        for config, label in labels.items():
            wall, result, by = runs[config][i]
            same = all(result[f] == ref[f] for f in ("stripes", "lognormal"))
            n = result["numerics"]
            print(f"  {label:42s} {wall:8.2f} s  {n['simulations'] / wall:9.0f} sim/s  "
                  f"{n['tasks']:3d} tasks {json.dumps(by) if by else '':18s} same result: {same}")
            assert same, f"{config} differs"
        print(f"  two instances vs one (PostgreSQL, 1 worker each): "
              f"{runs['pg1'][i][0] / runs['pg2'][i][0]:.2f}x")
    print(f"load average at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
