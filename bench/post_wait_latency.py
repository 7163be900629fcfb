#!/usr/bin/env python3
"""Client side of bench/load.sh: readiness, one primed job, and the latency of
POST /v1/jobs?wait=… against a topple server on 127.0.0.1.

Standard library only. Every loop is bounded in count and in time, and every
request goes to 127.0.0.1 (the host is not configurable on purpose).

  post_wait_latency.py --port P ready   [--timeout S]
  post_wait_latency.py --port P submit  [--a-alpha-g A]        # prints the job id
  post_wait_latency.py --port P latency [--n N] [--concurrency C] [--base A]
                                        [--warmup W] [--max-seconds S] [--json PATH]

`latency` submits N distinct time-history jobs (a_p_alpha_g = base + i·1e-6, so
none is a cache hit) with ?wait=10, from C threads each with its own
keep-alive connection, and measures each request from sending it to reading
the whole response (the finished job with its result inline). It compares
that with the compute time the result reports (numerics.wall_time_s):
service overhead = client latency − compute time. It also splits the
server's part using the job's timestamps (created_at, started_at,
finished_at; microsecond resolution), and prints the round trip of
GET /healthz on the same kind of connection as a floor: what this Python
client and loopback HTTP cost on their own.
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import sys
import threading
import time
from datetime import datetime

HOST = "127.0.0.1"
WAIT_S = 10
AMPLITUDE_STEP = 1e-6


def spec(a_alpha_g: float) -> dict:
    return {
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine", "omega_ratio": 5, "a_p_alpha_g": a_alpha_g},
        "formulation": "nonlinear",
    }


def loadavg() -> str:
    try:
        return "{:.2f} {:.2f} {:.2f}".format(*os.getloadavg())
    except OSError:
        return "n/a"


def ts(text: str | None) -> float | None:
    """RFC 3339 (as the service writes it) to seconds since the epoch."""
    if not text:
        return None
    try:
        return datetime.fromisoformat(text.replace("Z", "+00:00")).timestamp()
    except ValueError:
        return None


def pct(sorted_values: list[float], q: float) -> float:
    """Nearest-rank percentile of an ascending list (q in 0..100)."""
    if not sorted_values:
        return float("nan")
    k = max(0, min(len(sorted_values) - 1, int(-(-q * len(sorted_values) // 100)) - 1))
    return sorted_values[k]


def ms(x: float) -> str:
    return f"{x * 1e3:8.3f}"


def summary_line(name: str, values: list[float]) -> str:
    v = sorted(values)
    if not v:
        return f"  {name:<34} (no samples)"
    mean = sum(v) / len(v)
    return (
        f"  {name:<34} p50 {ms(pct(v, 50))}  p90 {ms(pct(v, 90))}  p99 {ms(pct(v, 99))}"
        f"  max {ms(v[-1])}  mean {ms(mean)}  ms"
    )


# --------------------------------------------------------------------------
# ready / submit


def cmd_ready(port: int, timeout: float) -> int:
    deadline = time.monotonic() + timeout
    last = "no answer"
    while time.monotonic() < deadline:
        try:
            conn = http.client.HTTPConnection(HOST, port, timeout=3)
            conn.request("GET", "/readyz")
            resp = conn.getresponse()
            body = resp.read()
            conn.close()
            if resp.status == 200:
                print(f"ready: {body.decode(errors='replace').strip()}")
                return 0
            last = f"HTTP {resp.status}: {body[:200]!r}"
        except OSError as e:
            last = str(e)
        time.sleep(0.1)
    print(f"not ready after {timeout:.0f} s: {last}", file=sys.stderr)
    return 1


def cmd_submit(port: int, a_alpha_g: float) -> int:
    conn = http.client.HTTPConnection(HOST, port, timeout=WAIT_S + 20)
    body = json.dumps(spec(a_alpha_g))
    conn.request("POST", f"/v1/jobs?wait={WAIT_S}", body=body,
                 headers={"Content-Type": "application/json"})
    resp = conn.getresponse()
    raw = resp.read()
    conn.close()
    try:
        doc = json.loads(raw)
    except ValueError:
        doc = {}
    if resp.status != 200 or doc.get("status") != "succeeded" or "result" not in doc:
        print(f"submit failed: HTTP {resp.status}: {raw[:500]!r}", file=sys.stderr)
        return 1
    print(doc["id"])
    return 0


# --------------------------------------------------------------------------
# latency


class Sample:
    __slots__ = ("latency", "compute", "queue", "run", "cached", "status", "job_status")

    def __init__(self) -> None:
        self.latency = 0.0
        self.compute: float | None = None
        self.queue: float | None = None
        self.run: float | None = None
        self.cached: bool | None = None
        self.status = 0
        self.job_status = ""


class Worker(threading.Thread):
    def __init__(self, port: int, amplitudes: list[float], deadline: float) -> None:
        super().__init__(daemon=True)
        self.port = port
        self.amplitudes = amplitudes
        self.deadline = deadline
        self.samples: list[Sample] = []
        self.errors: list[str] = []
        self.bad: list[str] = []  # non-200 or unexpected documents
        self.reconnects = 0

    def connect(self) -> http.client.HTTPConnection:
        return http.client.HTTPConnection(HOST, self.port, timeout=WAIT_S + 20)

    def run(self) -> None:
        conn = self.connect()
        for a in self.amplitudes:
            if time.monotonic() >= self.deadline:
                break
            body = json.dumps(spec(a)).encode()
            s = Sample()
            t0 = time.perf_counter()
            try:
                conn.request("POST", f"/v1/jobs?wait={WAIT_S}", body=body,
                             headers={"Content-Type": "application/json"})
                resp = conn.getresponse()
                raw = resp.read()
                s.latency = time.perf_counter() - t0
                s.status = resp.status
            except (OSError, http.client.HTTPException) as e:
                self.errors.append(f"a={a!r}: {type(e).__name__}: {e}")
                conn.close()
                conn = self.connect()
                self.reconnects += 1
                continue
            if resp.getheader("Connection", "").lower() == "close":
                conn.close()
                conn = self.connect()
                self.reconnects += 1
            try:
                doc = json.loads(raw)
            except ValueError:
                doc = {}
            s.job_status = str(doc.get("status", ""))
            s.cached = doc.get("cached")
            if s.status != 200 or s.job_status != "succeeded" or "result" not in doc:
                self.bad.append(f"a={a!r}: HTTP {s.status} status={s.job_status!r}: {raw[:300]!r}")
            else:
                numerics = (doc.get("result") or {}).get("numerics") or {}
                wt = numerics.get("wall_time_s")
                s.compute = float(wt) if isinstance(wt, (int, float)) else None
                c, st, f = ts(doc.get("created_at")), ts(doc.get("started_at")), ts(doc.get("finished_at"))
                if c is not None and st is not None and f is not None:
                    s.queue = st - c
                    s.run = f - st
            self.samples.append(s)
        conn.close()


def client_floor(port: int, n: int = 200) -> list[float]:
    """Round trips of GET /healthz on one keep-alive connection: what this
    client and HTTP on loopback cost with no job, store or compute at all."""
    conn = http.client.HTTPConnection(HOST, port, timeout=5)
    out = []
    deadline = time.monotonic() + 10
    for _ in range(n):
        if time.monotonic() >= deadline:
            break
        t0 = time.perf_counter()
        conn.request("GET", "/healthz")
        resp = conn.getresponse()
        resp.read()
        if resp.status == 200:
            out.append(time.perf_counter() - t0)
    conn.close()
    return out


def run_batch(port: int, amplitudes: list[float], concurrency: int, max_seconds: float):
    deadline = time.monotonic() + max_seconds
    shares = [amplitudes[i::concurrency] for i in range(concurrency)]
    workers = [Worker(port, share, deadline) for share in shares]
    t0 = time.perf_counter()
    for w in workers:
        w.start()
    for w in workers:
        # Each request is bounded by the socket timeout, so this join ends.
        w.join(max_seconds + WAIT_S + 30)
    elapsed = time.perf_counter() - t0
    return workers, elapsed


def cmd_latency(args: argparse.Namespace) -> int:
    n, c = args.n, max(1, args.concurrency)
    print(f"POST /v1/jobs?wait={WAIT_S}: {n} distinct time-history jobs, concurrency {c}, "
          f"a_p_alpha_g = {args.base} + i*{AMPLITUDE_STEP:g}; load average {loadavg()}")
    if args.warmup > 0:
        warm = [args.base + 0.5 + i * AMPLITUDE_STEP for i in range(args.warmup)]
        run_batch(args.port, warm, c, 30)
    floor = client_floor(args.port)
    amplitudes = [args.base + i * AMPLITUDE_STEP for i in range(n)]
    workers, elapsed = run_batch(args.port, amplitudes, c, args.max_seconds)

    samples = [s for w in workers for s in w.samples]
    errors = [e for w in workers for e in w.errors]
    bad = [b for w in workers for b in w.bad]
    ok = [s for s in samples if s.compute is not None]
    done = len(samples) + len(errors)
    cache_hits = sum(1 for s in samples if s.cached)
    reconnects = sum(w.reconnects for w in workers)
    statuses: dict[int, int] = {}
    for s in samples:
        statuses[s.status] = statuses.get(s.status, 0) + 1

    print(f"  requests sent {done} of {n} in {elapsed:.2f} s ({done / elapsed:.1f} jobs/s)"
          + ("  [STOPPED AT --max-seconds]" if done < n else ""))
    print(f"  HTTP statuses {dict(sorted(statuses.items()))}; transport errors {len(errors)}; "
          f"unexpected answers {len(bad)}; cache hits {cache_hits}; reconnects {reconnects}")
    for line in (errors + bad)[:5]:
        print(f"    ! {line}")

    lat = [s.latency for s in ok]
    comp = [s.compute for s in ok]
    over = [s.latency - s.compute for s in ok]
    print(summary_line("floor: GET /healthz (no job)", floor))
    print(summary_line("client latency", lat))
    print(summary_line("compute (numerics.wall_time_s)", comp))
    print(summary_line("overhead = latency - compute", over))
    timed = [s for s in ok if s.queue is not None]
    if timed:
        print(summary_line("server: created -> started", [s.queue for s in timed]))
        print(summary_line("server: started -> finished", [s.run for s in timed]))
        print(summary_line("rest: latency - (finished-created)",
                           [s.latency - s.queue - s.run for s in timed]))
    lat_s, over_s = sorted(lat), sorted(over)
    if ok:
        p99, o50, o99 = pct(lat_s, 99), pct(over_s, 50), pct(over_s, 99)
        print(f"  RESULT concurrency={c}: latency p50 {pct(lat_s, 50) * 1e3:.3f} ms, "
              f"p99 {p99 * 1e3:.3f} ms (target <= 20 ms: {'met' if p99 <= 0.020 else 'MISSED'}); "
              f"overhead p50 {o50 * 1e3:.3f} ms, p99 {o99 * 1e3:.3f} ms "
              f"(target <= 2 ms: p50 {'met' if o50 <= 0.002 else 'MISSED'}, "
              f"p99 {'met' if o99 <= 0.002 else 'MISSED'})")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({
                "n": n, "concurrency": c, "elapsed_s": elapsed, "statuses": statuses,
                "errors": errors, "unexpected": bad, "cache_hits": cache_hits,
                "samples": [{"latency_s": s.latency, "compute_s": s.compute,
                             "queue_s": s.queue, "run_s": s.run, "status": s.status}
                            for s in samples],
            }, fh)
    return 0 if ok and not errors and not bad and not cache_hits and done == n else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--port", type=int, required=True, help="port of the server on 127.0.0.1")
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("ready", help="wait until GET /readyz answers 200")
    r.add_argument("--timeout", type=float, default=30.0)
    s = sub.add_parser("submit", help="submit one job with ?wait and print its id")
    s.add_argument("--a-alpha-g", type=float, default=4.0)
    lt = sub.add_parser("latency", help="POST ?wait latency of distinct jobs")
    lt.add_argument("--n", type=int, default=2000, help="jobs (at most 100000)")
    lt.add_argument("--concurrency", type=int, default=1, help="client threads (at most 64)")
    lt.add_argument("--base", type=float, default=3.0, help="first a_p_alpha_g")
    lt.add_argument("--warmup", type=int, default=50, help="untimed jobs first (distinct too)")
    lt.add_argument("--max-seconds", type=float, default=180.0,
                    help="stop sending after this long")
    lt.add_argument("--json", help="also write every sample as JSON")
    args = ap.parse_args()
    if not 0 < args.port < 65536:
        ap.error("--port must be 1..65535")
    if args.cmd == "ready":
        return cmd_ready(args.port, args.timeout)
    if args.cmd == "submit":
        return cmd_submit(args.port, args.a_alpha_g)
    if not 1 <= args.n <= 100_000 or not 1 <= args.concurrency <= 64 or args.warmup > 10_000:
        ap.error("--n must be 1..100000, --concurrency 1..64, --warmup at most 10000")
    return cmd_latency(args)


if __name__ == "__main__":
    sys.exit(main())
