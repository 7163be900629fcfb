#!/usr/bin/env python3
"""Scale-out benchmark: one 200-frequency nonlinear spectrum on one topple
instance vs two instances sharing one PostgreSQL, each instance with one worker
thread (--workers 1). Prints the wall time from submission to the finished
result for both, and their ratio. Standard library only; needs PostgreSQL at
127.0.0.1:5432 (user postgres, trust auth) and the release binary.

    python3 bench/scale_out.py [--topple target/release/topple] [--frequencies 200]
"""
import argparse
import json
import os
import socket
import subprocess
import sys
import time
import urllib.request

ADMIN = os.environ.get("TOPPLE_TEST_POSTGRES", "postgres://postgres@127.0.0.1:5432/postgres")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def psql(sql):
    subprocess.run(["psql", ADMIN, "-q", "-c", sql], check=True, stdout=subprocess.DEVNULL)


def http(method, url, body=None):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url, data=data, method=method, headers={"content-type": "application/json"})
    with urllib.request.urlopen(req, timeout=60) as r:
        return json.loads(r.read())


def start(binary, db, name, workers=1):
    """An instance on database `db` with `workers` worker threads: (process, base URL)."""
    port = free_port()
    p = subprocess.Popen(
        [binary, "serve", "--addr", f"127.0.0.1:{port}", "--workers", str(workers), "--instance", name],
        env={**os.environ, "DATABASE_URL": db},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    base = f"http://127.0.0.1:{port}"
    for _ in range(400):
        try:
            http("GET", f"{base}/readyz")
            return p, base
        except Exception:
            time.sleep(0.05)
    p.kill()
    sys.exit(f"{name} never became ready")


def run(binary, instances, frequencies):
    name = f"topple_scale_{os.getpid()}_{instances}"
    psql(f"CREATE DATABASE {name}")
    db = ADMIN.rsplit("/", 1)[0] + "/" + name
    procs = [start(binary, db, chr(ord("A") + i)) for i in range(instances)]
    spec = {
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies},
        "a_max_alpha_g": 20,
        "tolerance": 1e-4,
    }
    try:
        base = procs[0][1]
        t0 = time.perf_counter()
        job = http("POST", f"{base}/v1/jobs", spec)
        while True:
            job = http("GET", f"{base}/v1/jobs/{job['id']}")
            if job["status"] in ("succeeded", "failed", "canceled"):
                break
            time.sleep(0.01)
        wall = time.perf_counter() - t0
        assert job["status"] == "succeeded", job
        result = http("GET", f"{base}/v1/jobs/{job['id']}/result")
        return wall, result["numerics"]
    finally:
        for p, _ in procs:
            p.terminate()
            p.wait(timeout=30)
        psql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--topple", default="target/release/topple")
    ap.add_argument("--frequencies", type=int, default=200)
    a = ap.parse_args()
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    one, n1 = run(a.topple, 1, a.frequencies)
    two, n2 = run(a.topple, 2, a.frequencies)
    print(f"{a.frequencies}-frequency nonlinear one-sine spectrum, each instance --workers 1")
    print(f"  one instance : {one:7.2f} s  (compute {n1['wall_time_s']:.2f} s in {n1['tasks']} tasks)")
    print(f"  two instances: {two:7.2f} s  (compute {n2['wall_time_s']:.2f} s in {n2['tasks']} tasks)")
    print(f"  speed-up     : {one / two:5.2f}x")
    print(f"load average at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
