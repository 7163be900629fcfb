#!/usr/bin/env python3
"""Status polls with and without If-None-Match, side by side in one run.

Starts topple (target/release/topple unless --topple) on a free port with a
fresh SQLite database, finishes two jobs (a small time history, and one whose
spec holds a 40,000-sample record, so its status view is large), then polls
each job's status N times over one keep-alive connection:

- plain: GET /v1/jobs/{id}            (200 with the whole job view)
- etag:  the same with If-None-Match   (304, no body)

and prints p50/p99 latency, bytes per answer and the ratios. Also prints the
sizes of a large result as JSON, CSV and SVG, plain and gzip/br compressed.

    python3 bench/poll_etag.py [--topple PATH] [--polls 2000]
"""

import argparse
import http.client
import json
import math
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(conn, method, path, body=None, headers=None):
    conn.request(method, path, body=body, headers=headers or {})
    r = conn.getresponse()
    data = r.read()
    return r.status, dict((k.lower(), v) for k, v in r.getheaders()), data


def percentile(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(math.ceil(q * len(xs))) - 1)]


def poll(conn, path, n, etag=None):
    times, sizes, statuses = [], [], set()
    headers = {"If-None-Match": etag} if etag else {}
    for _ in range(n):
        t0 = time.perf_counter()
        status, _, data = request(conn, "GET", path, headers=headers)
        times.append(time.perf_counter() - t0)
        sizes.append(len(data))
        statuses.add(status)
    return times, statuses, statistics.mean(sizes)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--topple", default="target/release/topple")
    ap.add_argument("--polls", type=int, default=2000)
    args = ap.parse_args()
    if not os.path.exists(args.topple):
        sys.exit(f"no {args.topple}: cargo build --release first, or pass --topple")
    port = free_port()
    work = tempfile.mkdtemp(prefix="topple-poll-")
    server = subprocess.Popen(
        [args.topple, "serve", "--addr", f"127.0.0.1:{port}",
         "--database", f"sqlite://{work}/topple.db", "--max-body", str(8 << 20)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            try:
                socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
                break
            except OSError:
                time.sleep(0.05)
        conn = http.client.HTTPConnection("127.0.0.1", port)
        small = {"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                 "pulse": {"type": "one_sine", "omega_ratio": 5, "a_p_alpha_g": 4},
                 "formulation": "nonlinear", "outputs": {"series": 2000}}
        dt = 0.005
        acc = [0.4 * math.sin(2 * math.pi * 1.3 * k * dt) * math.exp(-((k * dt - 20) / 8) ** 2)
               for k in range(40000)]
        large = {"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                 "ground_motion": {"dt": dt, "acc": acc, "unit": "g"},
                 "formulation": "nonlinear"}
        jobs = {}
        for name, spec in (("small spec", small), ("40k-sample record", large)):
            status, _, data = request(conn, "POST", "/v1/jobs?wait=60", json.dumps(spec),
                                      {"content-type": "application/json"})
            job = json.loads(data)
            if status != 200 or job["status"] != "succeeded":
                sys.exit(f"{name}: {status} {data[:300]!r}")
            jobs[name] = job["id"]
        print(f"{args.polls} sequential status polls per row, one keep-alive connection\n")
        print(f"{'job':<20}{'mode':<16}{'status':>8}{'bytes':>10}{'p50 ms':>9}{'p99 ms':>9}")
        for name, jid in jobs.items():
            path = f"/v1/jobs/{jid}"
            _, headers, _ = request(conn, "GET", path)
            etag = headers["etag"]
            poll(conn, path, 50)
            poll(conn, path, 50, etag)
            plain, s1, b1 = poll(conn, path, args.polls)
            cond, s2, b2 = poll(conn, path, args.polls, etag)
            for mode, t, s, b in (("plain", plain, s1, b1), ("If-None-Match", cond, s2, b2)):
                print(f"{name:<20}{mode:<16}{'/'.join(map(str, sorted(s))):>8}{b:>10.0f}"
                      f"{1e3 * percentile(t, 0.5):>9.3f}{1e3 * percentile(t, 0.99):>9.3f}")
            print(f"{'':<20}{'ratio':<16}{'':>8}{b1 / max(b2, 1):>10.0f}"
                  f"{percentile(plain, 0.5) / percentile(cond, 0.5):>9.2f}"
                  f"{percentile(plain, 0.99) / percentile(cond, 0.99):>9.2f}")
        print("\nresult sizes (small-spec job, series of 2000 samples), bytes:")
        jid = jobs["small spec"]
        for label, path in (("JSON", f"/v1/jobs/{jid}/result"),
                            ("CSV", f"/v1/jobs/{jid}/result?format=csv"),
                            ("SVG", f"/v1/jobs/{jid}/plot.svg")):
            sizes = []
            for enc in ("identity", "gzip", "br"):
                _, h, data = request(conn, "GET", path, headers={"Accept-Encoding": enc})
                sizes.append(f"{enc} {len(data)}")
            print(f"  {label:<5}" + ", ".join(sizes))
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    main()
