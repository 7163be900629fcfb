#!/usr/bin/env python3
"""Chaos benchmark of the topple HTTP service.

Drives a real `topple serve` (release build) with a mixed load from 32 client
threads while it injects faults, then checks that nothing acknowledged was
lost, stuck or computed wrongly. Two phases, each on a fresh database:

* sqlite:   kill -9 of the server twice (restarted at once on the same
            database), and a full disk: the database directory is a tmpfs
            (--tmpfs-mb, large enough for the phase's results), filled with a
            filler file until ENOSPC, held (--hold), then freed;
* postgres: kill -9 twice, and a restart of the database: a private cluster
            (initdb in the temporary directory, on a free port) stopped for a
            few seconds mid-load, then started; the server is not restarted
            and must recover by itself.

The client mix, per thread and loop: about 50 % POST /v1/jobs (time histories
with a 2,000-sample series, every spec distinct; every --spectrum-every-th
submission a small linear spectrum), 30 % GET /v1/jobs/{id} of one of the
thread's acknowledged jobs, 10 % GET of a succeeded job's result (JSON or
CSV), 10 % GET /v1/jobs?limit=50; 20-50 ms between requests. A client with
--max-inflight unfinished jobs polls the oldest of them instead of submitting
another, so that the queue stays short and the drain measures recovery, not
a backlog (with --max-inflight 0, 32 clients submit about four times what two
workers compute, and the queue grows until 429). A 429, 503 or 507 is
followed by a pause of its Retry-After (at most 1 s). A POST answered 2xx is
acknowledged: its id and spec are recorded. Connection errors (refused, reset,
timed out) are counted apart from HTTP answers.

After the load (--seconds), the drain waits (--drain seconds at most) until
every acknowledged job is final (succeeded, failed, canceled). Then:

* lost:  acknowledged ids that GET /v1/jobs/{id} answers 404, or that the
         full listing does not contain;
* stuck: acknowledged jobs still queued or running after the drain;
* wrong: sampled succeeded jobs (--sample time histories, every spectrum up
         to --sample) whose result differs from `topple run -` of the same
         spec, run offline (physics fields to 1e-9 relative; numerics and
         engine ignored);
* failed jobs, with their error messages;
* 5xx answers by code (503 and 507 are the expected answers under faults),
  and 503/507 answers without Retry-After;
* the server's peak resident memory: VmRSS of every server process sampled
  every 100 ms, and VmHWM read before each kill and before the stop.

Needs root for the faults (mount, runuser); a fault that cannot be injected is
skipped with a loud message, and the postgres phase is skipped without
PostgreSQL binaries under /usr/lib/postgresql.

The exit status is 1 if anything was lost, stuck or wrong, or if any 5xx
other than 503/507 (or a 503/507 without Retry-After) was answered.

    python3 bench/chaos.py                       # both phases, 60 s of load each
    python3 bench/chaos.py --phases sqlite --seconds 30 --json
    python3 bench/chaos.py --bin /path/to/topple --keep-tmp

The binary (target/release/topple, built with `cargo build --release` if
missing, or --bin) is copied to the temporary directory first, so a rebuild
of target/ during the run changes nothing. Server logs, the databases and the
PostgreSQL log are in that directory, printed at the start; it is removed at
the end unless a check failed or --keep-tmp is given.
"""

from __future__ import annotations

import argparse
import collections
import errno
import http.client
import json
import math
import os
import random
import re
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FINAL = ("succeeded", "failed", "canceled")
TH_FIELDS = (
    "overturned",
    "mode",
    "impact_count",
    "rocking_start",
    "overturn_time",
    "rest_time",
    "peak_theta_over_alpha",
    "peak_friction_demand",
)
REL_TOL = 1e-9


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)


def loud(msg: str) -> None:
    bar = "!" * 72
    print(f"{bar}\n!! {msg}\n{bar}", flush=True)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def proc_status(pid: int, field: str) -> int | None:
    """A field of /proc/PID/status in kB (VmRSS, VmHWM), None if gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except (OSError, ValueError):
        return None
    return None


# ---------------------------------------------------------------------------
# HTTP


def conn_error_kind(exc: BaseException) -> str:
    if isinstance(exc, ConnectionRefusedError):
        return "refused"
    if isinstance(exc, (ConnectionResetError, BrokenPipeError, ConnectionAbortedError)):
        return "reset"
    if isinstance(exc, (socket.timeout, TimeoutError)):
        return "timeout"
    if isinstance(exc, (http.client.RemoteDisconnected, http.client.IncompleteRead)):
        return "reset"
    if isinstance(exc, OSError) and exc.errno == errno.ECONNREFUSED:
        return "refused"
    if isinstance(exc, OSError) and exc.errno in (errno.ECONNRESET, errno.EPIPE):
        return "reset"
    return type(exc).__name__


class Client:
    """One keep-alive connection, reopened after any transport error."""

    def __init__(self, port: int, timeout: float = 30.0):
        self.port = port
        self.timeout = timeout
        self.conn: http.client.HTTPConnection | None = None

    def close(self) -> None:
        if self.conn is not None:
            try:
                self.conn.close()
            except OSError:
                pass
            self.conn = None

    def request(self, method: str, path: str, body: bytes | None = None, headers=None):
        """(status, headers dict lower-cased, body bytes); raises on transport errors."""
        if self.conn is None:
            self.conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=self.timeout)
        h = {"Accept-Encoding": "identity"}
        if body is not None:
            h["Content-Type"] = "application/json"
        if headers:
            h.update(headers)
        try:
            self.conn.request(method, path, body=body, headers=h)
            resp = self.conn.getresponse()
            data = resp.read()
            hdrs = {k.lower(): v for k, v in resp.getheaders()}
            if resp.getheader("connection", "").lower() == "close":
                self.close()
            return resp.status, hdrs, data
        except BaseException:
            self.close()
            raise


def get_json(port: int, path: str, timeout: float = 10.0):
    c = Client(port, timeout)
    try:
        status, _, data = c.request("GET", path)
        try:
            return status, json.loads(data) if data else None
        except ValueError:
            return status, None
    finally:
        c.close()


def get_status(port: int, path: str, timeout: float = 5.0) -> int:
    try:
        return get_json(port, path, timeout)[0]
    except (OSError, http.client.HTTPException):
        return 0


# ---------------------------------------------------------------------------
# Server processes and memory


class Memory:
    """Samples VmRSS of the watched server processes every 100 ms."""

    def __init__(self):
        self.lock = threading.Lock()
        self.pids: set[int] = set()
        self.peak_rss_kb = 0
        self.peak_hwm_kb = 0
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, name="rss", daemon=True)
        self.thread.start()

    def watch(self, pid: int) -> None:
        with self.lock:
            self.pids.add(pid)

    def unwatch(self, pid: int) -> None:
        with self.lock:
            self.pids.discard(pid)

    def hwm(self, pid: int) -> None:
        v = proc_status(pid, "VmHWM")
        if v is not None:
            with self.lock:
                self.peak_hwm_kb = max(self.peak_hwm_kb, v)

    def reset(self) -> tuple[int, int]:
        with self.lock:
            out = (self.peak_rss_kb, self.peak_hwm_kb)
            self.peak_rss_kb = self.peak_hwm_kb = 0
            return out

    def run(self) -> None:
        while not self.stop.wait(0.1):
            with self.lock:
                pids = list(self.pids)
            for pid in pids:
                v = proc_status(pid, "VmRSS")
                if v is not None:
                    with self.lock:
                        self.peak_rss_kb = max(self.peak_rss_kb, v)


class Server:
    """`topple serve` on a fixed port and database, restartable."""

    def __init__(self, binary: str, port: int, database: str, logpath: str, memory: Memory,
                 workers: int):
        self.binary = binary
        self.port = port
        self.database = database
        self.logpath = logpath
        self.memory = memory
        self.workers = workers
        self.proc: subprocess.Popen | None = None
        self.starts = 0
        self.ready_times: list[float] = []

    def start(self) -> float:
        """Starts the server and waits for /readyz 200; returns the seconds it took."""
        t0 = time.monotonic()
        for attempt in range(5):
            self.starts += 1
            with open(self.logpath, "ab") as f:
                f.write(f"==== chaos: start #{self.starts} at {time.strftime('%H:%M:%S')} ====\n".encode())
                f.flush()
                self.proc = subprocess.Popen(
                    [self.binary, "serve", "--addr", f"127.0.0.1:{self.port}",
                     "--database", self.database, "--workers", str(self.workers)],
                    stdout=f, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                    env={**os.environ, "RUST_LOG": os.environ.get("RUST_LOG", "info")},
                )
            self.memory.watch(self.proc.pid)
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                if self.proc.poll() is not None:
                    break
                if get_status(self.port, "/readyz", 2.0) == 200:
                    took = time.monotonic() - t0
                    self.ready_times.append(took)
                    return took
                time.sleep(0.05)
            code = self.proc.poll()
            self.memory.unwatch(self.proc.pid)
            if code is None:
                self.proc.kill()
                self.proc.wait()
                raise RuntimeError(f"server not ready within 60 s (log: {self.logpath})")
            log(f"server exited with status {code} at start (attempt {attempt + 1}); "
                f"starting again (log: {self.logpath})")
            time.sleep(0.5)
        raise RuntimeError(f"server would not start (log: {self.logpath})")

    def kill9(self) -> None:
        assert self.proc is not None
        self.memory.hwm(self.proc.pid)
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait()
        self.memory.unwatch(self.proc.pid)

    def stop(self, grace: float = 30.0) -> int | None:
        """SIGTERM; the exit status (None if it had to be killed)."""
        if self.proc is None or self.proc.poll() is not None:
            return self.proc.poll() if self.proc else None
        self.memory.hwm(self.proc.pid)
        self.proc.send_signal(signal.SIGTERM)
        try:
            code = self.proc.wait(grace)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            code = None
        self.memory.unwatch(self.proc.pid)
        return code

    def ensure_dead(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


# ---------------------------------------------------------------------------
# Faults' infrastructure


class Tmpfs:
    def __init__(self, path: str, mib: int):
        self.path = path
        self.mib = mib
        self.mounted = False

    def mount(self) -> str | None:
        """None when mounted, else why not."""
        if os.geteuid() != 0:
            return "not root"
        os.makedirs(self.path, exist_ok=True)
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={self.mib}m", "tmpfs", self.path],
                           capture_output=True, text=True)
        if r.returncode != 0:
            return f"mount failed: {r.stderr.strip()}"
        self.mounted = True
        return None

    def unmount(self) -> None:
        if self.mounted:
            subprocess.run(["umount", "-l", self.path], capture_output=True)
            self.mounted = False


def fill(path: str) -> int:
    """Writes `path` until the file system is full (ENOSPC); returns its size."""
    block = b"\0" * (1 << 20)
    size = 0
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    try:
        for chunk in (block, block[: 64 << 10], block[:4096], block[:512], block[:1]):
            while True:
                try:
                    n = os.write(fd, chunk)
                except OSError as e:
                    if e.errno in (errno.ENOSPC, errno.EFBIG, errno.EDQUOT):
                        break
                    raise
                size += n
                if n < len(chunk):
                    break
    finally:
        os.close(fd)
    return size


class Cluster:
    """A private PostgreSQL cluster on a free port, run as the postgres user."""

    def __init__(self, base: str):
        self.dir = os.path.join(base, "pg")
        self.data = os.path.join(self.dir, "data")
        self.logfile = os.path.join(self.dir, "postgres.log")
        self.port = free_port()
        self.bin = None
        self.running = False
        found = sorted(
            os.path.join("/usr/lib/postgresql", v, "bin")
            for v in (os.listdir("/usr/lib/postgresql") if os.path.isdir("/usr/lib/postgresql") else [])
            if os.path.exists(os.path.join("/usr/lib/postgresql", v, "bin", "initdb"))
        )
        if found:
            self.bin = found[-1]

    def as_postgres(self, program: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
        return subprocess.run(["runuser", "-u", "postgres", "--", os.path.join(self.bin, program), *args],
                              capture_output=True, text=True, timeout=timeout)

    def create(self) -> str | None:
        """None when created and started, else why not."""
        if os.geteuid() != 0:
            return "not root"
        if self.bin is None:
            return "no PostgreSQL binaries under /usr/lib/postgresql/*/bin"
        if shutil.which("runuser") is None:
            return "no runuser"
        os.makedirs(self.dir, exist_ok=True)
        r = subprocess.run(["chown", "-R", "postgres:postgres", self.dir], capture_output=True, text=True)
        if r.returncode != 0:
            return f"chown failed: {r.stderr.strip()}"
        r = self.as_postgres("initdb", "-D", self.data, "-A", "trust", "-U", "postgres", "--no-sync")
        if r.returncode != 0:
            return f"initdb failed: {r.stderr.strip()[-500:]}"
        if not self.start():
            return f"pg_ctl start failed (log: {self.logfile})"
        return None

    def start(self) -> bool:
        opts = f"-p {self.port} -k {self.dir} -c listen_addresses=127.0.0.1 -c fsync=off"
        r = self.as_postgres("pg_ctl", "-D", self.data, "-o", opts, "-l", self.logfile, "-w", "start")
        self.running = r.returncode == 0
        return self.running

    def stop(self) -> bool:
        r = self.as_postgres("pg_ctl", "-D", self.data, "-m", "fast", "-w", "stop")
        ok = r.returncode == 0
        if ok:
            self.running = False
        return ok

    def url(self) -> str:
        return f"postgres://postgres@127.0.0.1:{self.port}/postgres"


# ---------------------------------------------------------------------------
# Load


class Stats:
    def __init__(self):
        self.lock = threading.Lock()
        self.requests = collections.Counter()  # by endpoint
        self.codes = collections.Counter()  # (endpoint, code)
        self.conn_errors = collections.Counter()  # kind
        self.no_retry_after = collections.Counter()  # code
        self.bad_bodies: list[str] = []
        self.not_found_during_load: set[str] = set()

    def snapshot(self) -> collections.Counter:
        with self.lock:
            return self.codes.copy()

    def code(self, endpoint: str, status: int) -> None:
        with self.lock:
            self.requests[endpoint] += 1
            self.codes[(endpoint, status)] += 1

    def error(self, endpoint: str, kind: str) -> None:
        with self.lock:
            self.requests[endpoint] += 1
            self.conn_errors[kind] += 1

    def bad(self, what: str) -> None:
        with self.lock:
            if len(self.bad_bodies) < 50:
                self.bad_bodies.append(what)
            self.codes[("bad_body", 0)] += 1


class Job:
    __slots__ = ("id", "spec", "kind", "status", "acked_at")

    def __init__(self, id_: str, spec: dict, status: str):
        self.id = id_
        self.spec = spec
        self.kind = spec["kind"]
        self.status = status
        self.acked_at = time.monotonic()


class Load:
    def __init__(self, port: int, clients: int, spectrum_every: int, seed: int, max_inflight: int):
        self.port = port
        self.clients = clients
        self.max_inflight = max_inflight
        self.spectrum_every = spectrum_every
        self.stats = Stats()
        self.stop = threading.Event()
        self.seq_lock = threading.Lock()
        self.seq = 0
        self.jobs_lock = threading.Lock()
        self.jobs: dict[str, Job] = {}
        self.duplicate_ids = 0
        self.per_client: list[list[Job]] = [[] for _ in range(clients)]
        self.seed = seed
        self.threads = [threading.Thread(target=self.client, args=(i,), name=f"client-{i}", daemon=True)
                        for i in range(clients)]

    def start(self) -> None:
        for t in self.threads:
            t.start()

    def finish(self) -> None:
        self.stop.set()
        for t in self.threads:
            t.join(60)

    def acks_between(self, t0: float, t1: float) -> tuple[int, float | None]:
        """POSTs acknowledged in [t0, t1), and the seconds from t1 to the first one after."""
        with self.jobs_lock:
            times = [j.acked_at for j in self.jobs.values()]
        during = sum(1 for t in times if t0 <= t < t1)
        after = [t for t in times if t >= t1]
        return during, (round(min(after) - t1, 3) if after else None)

    def next_spec(self) -> dict:
        with self.seq_lock:
            self.seq += 1
            n = self.seq
        # Weyl sequences: every n gives a distinct (R, A), spread over the ranges.
        u = (n * 0.6180339887498949) % 1.0
        v = (n * 0.7548776662466927) % 1.0
        if self.spectrum_every and n % self.spectrum_every == 0:
            r1 = round(1.0 + 4.0 * u, 9)
            return {
                "kind": "spectrum",
                "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_sine"},
                "formulation": "linear",
                "omega_ratio": {"from": r1, "to": round(r1 + 2.0, 9), "steps": 6},
                "a_max_alpha_g": 8,
            }
        return {
            "kind": "time_history",
            "block": {"alpha": 0.2, "p": 2.0},
            "pulse": {"type": "one_sine", "omega_ratio": round(1.5 + 6.5 * u, 9),
                      "a_p_alpha_g": round(1.2 + 4.8 * v, 9)},
            "outputs": {"series": 2000},
        }

    def pause_for(self, hdrs: dict, rng: random.Random) -> None:
        try:
            ra = float(hdrs.get("retry-after", "0"))
        except ValueError:
            ra = 0.0
        time.sleep(min(max(ra, 0.05), 1.0) * rng.uniform(0.8, 1.0))

    def client(self, index: int) -> None:
        rng = random.Random(self.seed * 1000 + index)
        c = Client(self.port)
        mine = self.per_client[index]
        st = self.stats
        while not self.stop.is_set():
            r = rng.random()
            endpoint = "?"
            try:
                if (r < 0.5 or not mine) and self.max_inflight:
                    # A client with max_inflight unfinished jobs polls the
                    # oldest of them instead of submitting another.
                    waiting = [j for j in mine[-4 * self.max_inflight - 50:] if j.status not in FINAL]
                    if len(waiting) >= self.max_inflight:
                        r = 0.5
                        endpoint = "status"
                        j = waiting[0]
                        status, hdrs, body = c.request("GET", f"/v1/jobs/{j.id}")
                        st.code(endpoint, status)
                        if status == 200:
                            try:
                                j.status = json.loads(body)["status"]
                            except (ValueError, KeyError, TypeError):
                                st.bad(f"GET job {status}: {body[:200]!r}")
                        elif status == 404:
                            with st.lock:
                                st.not_found_during_load.add(j.id)
                        elif status in (503, 507):
                            if "retry-after" not in hdrs:
                                with st.lock:
                                    st.no_retry_after[status] += 1
                            self.pause_for(hdrs, rng)
                        time.sleep(rng.uniform(0.02, 0.05))
                        continue
                if r < 0.5 or not mine:
                    endpoint = "post"
                    spec = self.next_spec()
                    status, hdrs, body = c.request("POST", "/v1/jobs", json.dumps(spec).encode())
                    st.code(endpoint, status)
                    if status in (200, 202):
                        try:
                            job = json.loads(body)
                            jid = job["id"]
                        except (ValueError, KeyError, TypeError):
                            st.bad(f"POST {status}: {body[:200]!r}")
                            continue
                        j = Job(jid, spec, job.get("status", "?"))
                        with self.jobs_lock:
                            if jid in self.jobs:
                                self.duplicate_ids += 1
                            self.jobs[jid] = j
                        mine.append(j)
                    elif status in (429, 503, 507):
                        if status != 429 and "retry-after" not in hdrs:
                            with st.lock:
                                st.no_retry_after[status] += 1
                        self.pause_for(hdrs, rng)
                elif r < 0.8:
                    endpoint = "status"
                    j = rng.choice(mine)
                    status, hdrs, body = c.request("GET", f"/v1/jobs/{j.id}")
                    st.code(endpoint, status)
                    if status == 200:
                        try:
                            j.status = json.loads(body)["status"]
                        except (ValueError, KeyError, TypeError):
                            st.bad(f"GET job {status}: {body[:200]!r}")
                    elif status == 404:
                        with st.lock:
                            st.not_found_during_load.add(j.id)
                    elif status in (503, 507):
                        if "retry-after" not in hdrs:
                            with st.lock:
                                st.no_retry_after[status] += 1
                        self.pause_for(hdrs, rng)
                elif r < 0.9:
                    done = [j for j in mine[-200:] if j.status == "succeeded"]
                    if not done:
                        continue
                    j = rng.choice(done)
                    csv = rng.random() < 0.5
                    endpoint = "result_csv" if csv else "result"
                    path = f"/v1/jobs/{j.id}/result" + ("?format=csv" if csv else "")
                    status, hdrs, body = c.request("GET", path)
                    st.code(endpoint, status)
                    if status == 200:
                        if csv:
                            if not body[:200].split(b"\n", 1)[0].count(b","):
                                st.bad(f"CSV of {j.id}: {body[:100]!r}")
                        else:
                            try:
                                if json.loads(body).get("kind") != j.kind:
                                    st.bad(f"result of {j.id}: wrong kind")
                            except ValueError:
                                st.bad(f"result of {j.id}: not JSON: {body[:100]!r}")
                    elif status in (503, 507):
                        if "retry-after" not in hdrs:
                            with st.lock:
                                st.no_retry_after[status] += 1
                        self.pause_for(hdrs, rng)
                else:
                    endpoint = "list"
                    status, hdrs, body = c.request("GET", "/v1/jobs?limit=50")
                    st.code(endpoint, status)
                    if status == 200:
                        try:
                            if not isinstance(json.loads(body).get("jobs"), list):
                                st.bad(f"listing: no jobs array: {body[:100]!r}")
                        except ValueError:
                            st.bad(f"listing: not JSON: {body[:100]!r}")
                    elif status in (503, 507):
                        if "retry-after" not in hdrs:
                            with st.lock:
                                st.no_retry_after[status] += 1
                        self.pause_for(hdrs, rng)
            except (OSError, http.client.HTTPException) as e:
                st.error(endpoint, conn_error_kind(e))
                time.sleep(rng.uniform(0.05, 0.1))
                continue
            time.sleep(rng.uniform(0.02, 0.05))
        c.close()


# ---------------------------------------------------------------------------
# Checks


def close(a, b) -> bool:
    if isinstance(a, bool) or isinstance(b, bool) or a is None or b is None or isinstance(a, str):
        return a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if math.isnan(a) or math.isnan(b):
            return math.isnan(a) and math.isnan(b)
        return abs(a - b) <= REL_TOL * max(abs(a), abs(b), 1e-300) or a == b
    return a == b


def compare(kind: str, got: dict, want: dict) -> list[str]:
    """Differences in the physics fields; empty when they agree."""
    diffs = []
    if kind == "time_history":
        for f in TH_FIELDS:
            if not close(got.get(f), want.get(f)):
                diffs.append(f"{f}: {got.get(f)!r} != {want.get(f)!r}")
    else:
        gs, ws = got.get("spectrum") or [], want.get("spectrum") or []
        if len(gs) != len(ws):
            return [f"spectrum length {len(gs)} != {len(ws)}"]
        for i, (g, w) in enumerate(zip(gs, ws)):
            if not close(g.get("min_overturn_alpha_g"), w.get("min_overturn_alpha_g")):
                diffs.append(f"spectrum[{i}].min_overturn_alpha_g: "
                             f"{g.get('min_overturn_alpha_g')!r} != {w.get('min_overturn_alpha_g')!r}")
            gt = [t.get("a_alpha_g") for t in g.get("transitions") or []]
            wt = [t.get("a_alpha_g") for t in w.get("transitions") or []]
            if len(gt) != len(wt) or not all(close(x, y) for x, y in zip(gt, wt)):
                diffs.append(f"spectrum[{i}].transitions a_alpha_g: {gt} != {wt}")
    return diffs


def run_offline(binary: str, spec: dict) -> dict:
    r = subprocess.run([binary, "run", "-"], input=json.dumps(spec), capture_output=True, text=True,
                       timeout=300, env={**os.environ, "RAYON_NUM_THREADS": "1"})
    if r.returncode != 0:
        raise RuntimeError(f"topple run exited {r.returncode}: {r.stderr.strip()[:300]}")
    return json.loads(r.stdout)


def parallel(fn, items, threads: int = 8):
    """fn over items on a few threads; results in order."""
    out = [None] * len(items)
    it = iter(range(len(items)))
    lock = threading.Lock()

    def work():
        while True:
            with lock:
                try:
                    i = next(it)
                except StopIteration:
                    return
            out[i] = fn(items[i])

    ts = [threading.Thread(target=work, daemon=True) for _ in range(threads)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    return out


def poll_job(port: int, jid: str):
    """(HTTP status or 0 on a transport error, job JSON or None)."""
    for attempt in range(5):
        try:
            return get_json(port, f"/v1/jobs/{jid}", 15.0)
        except (OSError, http.client.HTTPException):
            time.sleep(0.2 * (attempt + 1))
    return 0, None


def drain(port: int, jobs: dict[str, Job], limit: float) -> tuple[dict[str, tuple[int, dict | None]], float]:
    """Polls every acknowledged job until all are final or `limit` seconds pass."""
    t0 = time.monotonic()
    seen: dict[str, tuple[int, dict | None]] = {}
    pending = list(jobs)
    while True:
        answers = parallel(lambda jid: poll_job(port, jid), pending)
        nxt = []
        for jid, (status, body) in zip(pending, answers):
            seen[jid] = (status, body)
            if status == 200 and body and body.get("status") in FINAL:
                jobs[jid].status = body["status"]
                continue
            if status == 404:
                continue  # lost: no point waiting for it
            nxt.append(jid)
        pending = nxt
        took = time.monotonic() - t0
        if not pending or took > limit:
            return seen, took
        time.sleep(1.0)


def listing_ids(port: int) -> tuple[set[str] | None, str]:
    ids: set[str] = set()
    cursor = ""
    pages = 0
    while True:
        path = "/v1/jobs?limit=500" + (f"&cursor={cursor}" if cursor else "")
        try:
            status, body = get_json(port, path, 30.0)
        except (OSError, http.client.HTTPException) as e:
            return None, f"listing failed: {e!r}"
        if status != 200 or not body:
            return None, f"listing answered {status}"
        ids.update(j["id"] for j in body.get("jobs", []))
        cursor = body.get("next_cursor") or ""
        pages += 1
        if not cursor or pages > 10000:
            return ids, f"{pages} pages"


def summarise_log(path: str) -> tuple[collections.Counter, list[str]]:
    levels = collections.Counter()
    samples: dict[str, str] = {}
    pat = re.compile(r"\b(ERROR|WARN)\b")
    try:
        with open(path, errors="replace") as f:
            for line in f:
                m = pat.search(line)
                if not m:
                    continue
                levels[m.group(1)] += 1
                # one example per distinct message (numbers and ids blanked)
                key = re.sub(r"[0-9a-f]{8}-[0-9a-f-]{27}|\d+(\.\d+)?", "#", line[m.start():])[:160]
                samples.setdefault(key, line.rstrip()[:400])
    except OSError:
        pass
    return levels, list(samples.values())


# ---------------------------------------------------------------------------
# Phases


class Phase:
    def __init__(self, name: str):
        self.name = name
        self.events: list[str] = []
        self.t0 = time.monotonic()
        self.skipped_faults: list[str] = []
        self.warnings: list[str] = []
        self.result: dict = {}

    def event(self, msg: str) -> None:
        line = f"t={time.monotonic() - self.t0:6.1f}s  {msg}"
        self.events.append(line)
        log(f"[{self.name}] {msg}")


def run_phase(name: str, args, binary: str, tmp: str, memory: Memory, cleanups: list) -> dict:
    ph = Phase(name)
    pdir = os.path.join(tmp, name)
    os.makedirs(pdir, exist_ok=True)
    logpath = os.path.join(pdir, "server.log")
    port = free_port()
    tmpfs = None
    cluster = None
    memory.reset()

    if name == "sqlite":
        dbdir = os.path.join(pdir, "db")
        os.makedirs(dbdir, exist_ok=True)
        tmpfs = Tmpfs(dbdir, args.tmpfs_mb)
        why = tmpfs.mount()
        if why:
            loud(f"SKIPPED fault: disk full ({why}); the sqlite phase runs on the ordinary disk")
            ph.skipped_faults.append(f"disk full: {why}")
            tmpfs = None
        else:
            cleanups.append(tmpfs.unmount)
            ph.event(f"tmpfs of {args.tmpfs_mb} MiB mounted on {dbdir}")
        dbfile = os.path.join(dbdir, "topple.db")
        database = f"sqlite://{dbfile}"
    else:
        cluster = Cluster(pdir)
        why = cluster.create()
        if why:
            loud(f"SKIPPED phase postgres: no private cluster ({why})")
            return {"phase": name, "skipped": why}
        cleanups.append(lambda: cluster.running and cluster.stop())
        ph.event(f"private PostgreSQL cluster on port {cluster.port} ({cluster.dir})")
        database = cluster.url()

    server = Server(binary, port, database, logpath, memory, args.workers)
    cleanups.append(server.ensure_dead)
    took = server.start()
    ph.event(f"server up on 127.0.0.1:{port} in {took:.2f} s (log: {logpath})")

    S = args.seconds
    schedule = [(0.2 * S, "kill"), (0.45 * S, "kill")]
    schedule.append((0.7 * S, "diskfull" if name == "sqlite" else "dbrestart"))
    faults: dict = {"kill9": [], "disk_full": None, "db_restart": None}
    windows: dict = {}  # fault -> (start, end) of the episode, on the monotonic clock

    load = Load(port, args.clients, args.spectrum_every, args.seed + (0 if name == "sqlite" else 1),
                args.max_inflight)
    load.start()
    ph.event(f"load started: {args.clients} clients for {S:.0f} s")
    start = time.monotonic()
    for at, what in schedule:
        delay = start + at - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        if what == "kill":
            pid = server.proc.pid
            server.kill9()
            took = server.start()
            faults["kill9"].append(round(took, 2))
            ph.event(f"kill -9 of pid {pid}; restarted (pid {server.proc.pid}) and ready in {took:.2f} s")
        elif what == "diskfull":
            if tmpfs is None:
                continue
            filler = os.path.join(tmpfs.path, "filler")
            before = load.stats.snapshot()
            size = fill(filler)
            full_at = time.monotonic()
            ph.event(f"disk full: filler of {size / 2**20:.1f} MiB written until ENOSPC")
            time.sleep(args.hold)
            ready_during = get_status(port, "/readyz")
            os.remove(filler)
            freed = time.monotonic()
            ph.event(f"filler removed after {args.hold:.0f} s (/readyz answered {ready_during} while full)")
            recovered = None
            while time.monotonic() - freed < 60:
                if get_status(port, "/readyz", 2.0) == 200:
                    recovered = time.monotonic() - freed
                    break
                time.sleep(0.1)
            delta = load.stats.snapshot() - before
            n507 = sum(v for (e, c), v in delta.items() if c == 507)
            n503 = sum(v for (e, c), v in delta.items() if c == 503)
            windows["disk_full"] = (full_at, freed)
            faults["disk_full"] = {"filler_mib": round(size / 2**20, 1), "readyz_while_full": ready_during,
                                   "ready_after_s": None if recovered is None else round(recovered, 2),
                                   "507_during": n507, "503_during": n503}
            ph.event(f"ready again {recovered if recovered is None else round(recovered, 2)} s after the "
                     f"filler went; {n507} x 507 and {n503} x 503 meanwhile")
        elif what == "dbrestart":
            before = load.stats.snapshot()
            t_stop = time.monotonic()
            ok = cluster.stop()
            down_at = time.monotonic()
            ph.event(f"PostgreSQL stopped ({'ok' if ok else 'FAILED'}, {time.monotonic() - t_stop:.1f} s)")
            time.sleep(args.hold)
            ready_during = get_status(port, "/readyz")
            t_start = time.monotonic()
            ok = cluster.start()
            ph.event(f"PostgreSQL started ({'ok' if ok else 'FAILED'}, {time.monotonic() - t_start:.1f} s; "
                     f"/readyz answered {ready_during} while it was down)")
            back = time.monotonic()
            recovered = None
            while time.monotonic() - back < 60:
                if get_status(port, "/readyz", 2.0) == 200:
                    recovered = time.monotonic() - back
                    break
                time.sleep(0.1)
            delta = load.stats.snapshot() - before
            n503 = sum(v for (e, c), v in delta.items() if c == 503)
            windows["db_restart"] = (down_at, back)
            faults["db_restart"] = {"readyz_while_down": ready_during,
                                    "ready_after_s": None if recovered is None else round(recovered, 2),
                                    "503_during": n503}
            ph.event(f"server ready again {recovered if recovered is None else round(recovered, 2)} s after "
                     f"PostgreSQL came back; {n503} x 503 meanwhile")
    delay = start + S - time.monotonic()
    if delay > 0:
        time.sleep(delay)
    load.finish()
    load_s = time.monotonic() - start
    for fault, (t0, t1) in windows.items():
        during, first = load.acks_between(t0, t1)
        faults[fault]["2xx_posts_during"] = during
        faults[fault]["first_2xx_post_after_s"] = first
        ph.event(f"{fault.replace('_', ' ')}: {during} POSTs answered 2xx during the episode; the first "
                 f"after it {first} s after its end")
    if tmpfs is not None:
        fs = os.statvfs(tmpfs.path)
        free = fs.f_bavail / max(fs.f_blocks, 1)
        if free < 0.15:
            loud(f"the tmpfs is {100 * (1 - free):.0f} % full at the end of the load: the database itself "
                 f"fills it; raise --tmpfs-mb (now {args.tmpfs_mb}) or the drain will find a full disk")
            ph.warnings.append(f"the tmpfs was {100 * (1 - free):.0f} % full at the end of the load")
    ph.event(f"load stopped after {load_s:.1f} s: {len(load.jobs)} jobs acknowledged; draining")

    jobs = load.jobs
    seen, drain_s = drain(port, jobs, args.drain)
    ph.event(f"drain over in {drain_s:.1f} s")
    lost = sorted(j for j, (s, _) in seen.items() if s == 404)
    unanswered = sorted(j for j, (s, _) in seen.items() if s not in (200, 404))
    stuck = sorted(j for j, (s, b) in seen.items() if s == 200 and (not b or b.get("status") not in FINAL))
    listed, listing_note = listing_ids(port)
    absent = [] if listed is None else sorted(j for j in jobs if j not in listed and j not in lost)
    by_status = collections.Counter(b.get("status") for s, b in seen.values() if s == 200 and b)
    failed_msgs = collections.Counter(
        str(b.get("error"))[:200] for s, b in seen.values() if s == 200 and b and b.get("status") == "failed")

    # Wrong results: a sample of succeeded jobs against an offline run.
    rng = random.Random(args.seed)
    ok_th = [j for j in jobs.values() if j.status == "succeeded" and j.kind == "time_history"]
    ok_sp = [j for j in jobs.values() if j.status == "succeeded" and j.kind == "spectrum"]
    sample = rng.sample(ok_th, min(args.sample, len(ok_th))) + rng.sample(ok_sp, min(args.sample, len(ok_sp)))

    def check(j: Job):
        try:
            c = Client(port, 60)
            status, _, body = c.request("GET", f"/v1/jobs/{j.id}/result")
            c.close()
            if status != 200:
                return j.id, [f"GET result answered {status}"], True
            got = json.loads(body)
            want = run_offline(binary, j.spec)
            return j.id, compare(j.kind, got, want), False
        except Exception as e:  # noqa: BLE001 - reported, not hidden
            return j.id, [f"check failed: {e!r}"], True

    checks = parallel(check, sample, threads=2)
    wrong = [(jid, d) for jid, d, unfetched in checks if d and not unfetched]
    unchecked = [(jid, d) for jid, d, unfetched in checks if unfetched]
    ph.event(f"{len(sample)} results compared with offline runs: {len(wrong)} wrong, {len(unchecked)} not checked")

    peak_rss, peak_hwm = memory.reset()
    exit_code = server.stop()
    p2, h2 = memory.reset()
    peak_rss, peak_hwm = max(peak_rss, p2), max(peak_hwm, h2)
    ph.event(f"server stopped with SIGTERM: exit status {exit_code}")

    integrity = None
    db_bytes = None
    if name == "sqlite":
        try:
            with sqlite3.connect(f"file:{dbfile}?mode=ro", uri=True, timeout=30) as db:
                integrity = ", ".join(r[0] for r in db.execute("PRAGMA integrity_check").fetchall())[:200]
        except sqlite3.Error as e:
            integrity = f"could not run: {e}"
        ph.event(f"PRAGMA integrity_check: {integrity}")
        db_bytes = sum(os.path.getsize(os.path.join(dbdir, f)) for f in os.listdir(dbdir)
                       if f.startswith("topple.db"))
        if tmpfs is not None:
            tmpfs.unmount()
    elif cluster is not None:
        cluster.stop()
        db_bytes = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(cluster.data) for f in fs
                       if os.path.isfile(os.path.join(d, f)))

    st = load.stats
    fivexx = collections.Counter()
    for (e, c), v in st.codes.items():
        if 500 <= c <= 599:
            fivexx[c] += v
    fivexx_by_endpoint = {f"{e} {c}": v for (e, c), v in sorted(st.codes.items()) if 500 <= c <= 599}
    codes = collections.Counter()
    for (e, c), v in st.codes.items():
        if e != "bad_body":
            codes[c] += v
    levels, samples = summarise_log(logpath)
    unexpected_5xx = sum(v for c, v in fivexx.items() if c not in (503, 507))
    result = {
        "phase": name,
        "load_seconds": round(load_s, 1),
        "requests": sum(st.requests.values()),
        "requests_by_endpoint": dict(st.requests),
        "acknowledged": len(jobs),
        "acknowledged_by_kind": dict(collections.Counter(j.kind for j in jobs.values())),
        "final_by_status": {k or "?": v for k, v in by_status.items()},
        "lost": len(lost) + len(absent),
        "lost_404": len(lost),
        "absent_from_listing": len(absent),
        "unanswered_at_end": len(unanswered),
        "stuck": len(stuck) + len(unanswered),
        "wrong": len(wrong),
        "checked": len(sample) - len(unchecked),
        "unchecked": len(unchecked),
        "failed": by_status.get("failed", 0),
        "failed_errors": dict(failed_msgs.most_common(10)),
        "http_codes": {str(k): v for k, v in sorted(codes.items())},
        "5xx": {str(k): v for k, v in sorted(fivexx.items())},
        "5xx_by_endpoint": fivexx_by_endpoint,
        "503": fivexx.get(503, 0),
        "507": fivexx.get(507, 0),
        "unexpected_5xx": unexpected_5xx,
        "429": codes.get(429, 0),
        "no_retry_after": dict(st.no_retry_after),
        "connection_errors": dict(st.conn_errors),
        "bad_bodies": len(st.bad_bodies),
        "duplicate_ids": load.duplicate_ids,
        "404_during_load": len(st.not_found_during_load),
        "peak_rss_mib": round(peak_rss / 1024, 1),
        "peak_hwm_mib": round(peak_hwm / 1024, 1),
        "server_starts": server.starts,
        "kill9_ready_s": faults["kill9"],
        "disk_full": faults["disk_full"],
        "db_restart": faults["db_restart"],
        "skipped_faults": ph.skipped_faults,
        "warnings": ph.warnings,
        "drain_seconds": round(drain_s, 1),
        "sigterm_exit": exit_code,
        "integrity_check": integrity,
        "database_mib": None if db_bytes is None else round(db_bytes / 2**20, 1),
        "log": logpath,
        "log_levels": dict(levels),
    }
    result["_details"] = {
        "lost_ids": (lost + absent)[:20],
        "stuck_ids": [(j, (seen[j][1] or {}).get("status"), seen[j][0]) for j in (stuck + unanswered)[:20]],
        "404_during_load_ids": sorted(st.not_found_during_load)[:20],
        "wrong": wrong[:10],
        "unchecked": unchecked[:10],
        "bad_bodies": st.bad_bodies[:10],
        "log_samples": samples[:15],
        "events": ph.events,
        "listing": listing_note,
    }
    return result


def print_phase(r: dict) -> None:
    name = r["phase"]
    print()
    print(f"=== phase {name} " + "=" * (60 - len(name)))
    if r.get("skipped"):
        print(f"  SKIPPED: {r['skipped']}")
        return
    d = r["_details"]
    for e in d["events"]:
        print(f"  {e}")
    print()
    rows = [
        ("load", f"{r['load_seconds']} s, {r['requests']} requests "
                 f"({', '.join(f'{k} {v}' for k, v in sorted(r['requests_by_endpoint'].items()))})"),
        ("acknowledged jobs", f"{r['acknowledged']} "
                              f"({', '.join(f'{k} {v}' for k, v in sorted(r['acknowledged_by_kind'].items()))})"),
        ("final statuses", ", ".join(f"{k} {v}" for k, v in sorted(r["final_by_status"].items()))),
        ("lost", f"{r['lost']} (404: {r['lost_404']}, absent from the listing: {r['absent_from_listing']}; "
                 f"listing walked: {d['listing']})"),
        ("stuck", f"{r['stuck']} (not final after the drain of {r['drain_seconds']} s; "
                  f"unanswered: {r['unanswered_at_end']})"),
        ("wrong", f"{r['wrong']} of {r['checked']} compared with `topple run -`"
                  + (f" ({r['unchecked']} could not be checked)" if r["unchecked"] else "")),
        ("failed jobs", str(r["failed"])),
        ("HTTP answers", ", ".join(f"{k}: {v}" for k, v in r["http_codes"].items())),
        ("5xx by code", ", ".join(f"{k}: {v}" for k, v in r["5xx"].items()) or "none"),
        ("  503 / 507 (expected)", f"{r['503']} / {r['507']}"),
        ("  other 5xx", str(r["unexpected_5xx"])),
        ("  without Retry-After", ", ".join(f"{k}: {v}" for k, v in r["no_retry_after"].items()) or "none"),
        ("429 (queue full)", str(r["429"])),
        ("connection errors", ", ".join(f"{k}: {v}" for k, v in sorted(r["connection_errors"].items())) or "none"),
        ("malformed bodies", str(r["bad_bodies"])),
        ("404 during the load", str(r["404_during_load"])),
        ("peak RSS", f"{r['peak_rss_mib']} MiB sampled, {r['peak_hwm_mib']} MiB VmHWM "
                     f"({r['server_starts']} server processes)"),
        ("kill -9 → ready", ", ".join(f"{x} s" for x in r["kill9_ready_s"]) or "-"),
    ]
    if r["disk_full"]:
        df = r["disk_full"]
        rows.append(("disk full", f"filler {df['filler_mib']} MiB, /readyz {df['readyz_while_full']} while full, "
                                  f"ready {df['ready_after_s']} s after freeing, first POST 2xx after "
                                  f"{df['first_2xx_post_after_s']} s; 507: {df['507_during']}, "
                                  f"503: {df['503_during']}; 2xx POSTs while full: {df['2xx_posts_during']}"))
    if r["db_restart"]:
        dr = r["db_restart"]
        rows.append(("database restart", f"/readyz {dr['readyz_while_down']} while down, ready "
                                         f"{dr['ready_after_s']} s after it came back, first POST 2xx after "
                                         f"{dr['first_2xx_post_after_s']} s; 503: {dr['503_during']}; "
                                         f"2xx POSTs while down: {dr['2xx_posts_during']}"))
    for s in r["skipped_faults"]:
        rows.append(("SKIPPED fault", s))
    for s in r["warnings"]:
        rows.append(("WARNING", s))
    rows.append(("SIGTERM exit status", str(r["sigterm_exit"])))
    if r["database_mib"] is not None:
        rows.append(("database size", f"{r['database_mib']} MiB at the end"))
    if r["integrity_check"] is not None:
        rows.append(("integrity_check", r["integrity_check"]))
    rows.append(("server log", f"{r['log']} ({', '.join(f'{k} {v}' for k, v in r['log_levels'].items()) or 'no WARN/ERROR'})"))
    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{w}}  {v}")
    if r["failed_errors"]:
        print("  failed jobs' errors:")
        for msg, n in r["failed_errors"].items():
            print(f"    {n} x {msg}")
    if r["5xx_by_endpoint"]:
        print("  5xx by endpoint: " + ", ".join(f"{k}: {v}" for k, v in r["5xx_by_endpoint"].items()))
    for key, title in (("lost_ids", "lost"), ("stuck_ids", "stuck"), ("404_during_load_ids", "404 during load"),
                       ("wrong", "wrong"), ("unchecked", "not checked"), ("bad_bodies", "malformed")):
        if d[key]:
            print(f"  {title}:")
            for x in d[key]:
                print(f"    {x}")
    if d["log_samples"]:
        print("  WARN/ERROR lines in the server log (one per distinct message):")
        for line in d["log_samples"]:
            print(f"    {line}")


# ---------------------------------------------------------------------------


def build(binary: str | None, tmp: str) -> str:
    src = binary or os.path.join(REPO, "target", "release", "topple")
    if binary is None and not os.path.exists(src):
        log("building: cargo build --release")
        subprocess.run(["cargo", "build", "--release"], cwd=REPO, check=True)
    if not os.access(src, os.X_OK):
        sys.exit(f"chaos: no executable {src}")
    dst = os.path.join(tmp, "topple")
    shutil.copy2(src, dst)
    return dst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", help="the topple binary (default: target/release/topple, built if missing)")
    ap.add_argument("--phases", default="sqlite,postgres", help="comma-separated: sqlite, postgres")
    ap.add_argument("--seconds", type=float, default=60, help="load per phase (default 60)")
    ap.add_argument("--clients", type=int, default=32, help="client threads (default 32)")
    ap.add_argument("--workers", type=int, default=2, help="the server's --workers (default 2)")
    ap.add_argument("--drain", type=float, default=180, help="longest wait for final statuses (default 180 s)")
    ap.add_argument("--hold", type=float, default=5, help="seconds the disk stays full / the database down")
    ap.add_argument("--tmpfs-mb", type=int, default=4096,
                    help="size of the SQLite database's tmpfs in MiB (default 4096: a time history's "
                         "result is about 180 kB)")
    ap.add_argument("--max-inflight", type=int, default=4,
                    help="unfinished jobs a client may have before it polls instead of submitting "
                         "(default 4; 0: no bound, the queue grows as fast as clients submit)")
    ap.add_argument("--sample", type=int, default=30, help="results compared offline per kind and phase")
    ap.add_argument("--spectrum-every", type=int, default=250, help="every N-th submission is a spectrum")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", action="store_true", help="also print one JSON line with the figures")
    ap.add_argument("--keep-tmp", action="store_true", help="keep the temporary directory")
    args = ap.parse_args()
    phases = [p.strip() for p in args.phases.split(",") if p.strip()]
    for p in phases:
        if p not in ("sqlite", "postgres"):
            ap.error(f"unknown phase {p!r}")

    if os.geteuid() != 0:
        loud("not root: every fault but kill -9 is SKIPPED (mount and a private PostgreSQL need root)")

    tmp = tempfile.mkdtemp(prefix="topple-chaos-")
    os.chmod(tmp, 0o755)  # the postgres user must reach its cluster's directory
    log(f"temporary directory (server logs, databases): {tmp}")
    cleanups: list = []
    memory = Memory()
    results = []
    t_all = time.monotonic()
    failed = True

    def on_term(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, on_term)
    try:
        binary = build(args.bin, tmp)
        log(f"binary: {binary} (copied from {args.bin or 'target/release/topple'})")
        try:
            la = open("/proc/loadavg").read().split()[:3]
            log(f"load average at start: {' '.join(la)}")
        except OSError:
            pass
        for name in phases:
            results.append(run_phase(name, args, binary, tmp, memory, cleanups))
        total = time.monotonic() - t_all
        for r in results:
            print_phase(r)
        bad = []
        for r in results:
            if r.get("skipped"):
                continue
            for key in ("lost", "stuck", "wrong", "unexpected_5xx"):
                if r[key]:
                    bad.append(f"{r['phase']}: {key} {r[key]}")
            if r["no_retry_after"]:
                bad.append(f"{r['phase']}: 503/507 without Retry-After {r['no_retry_after']}")
        print()
        print(f"total time {total:.0f} s; " + ("FAILED: " + "; ".join(bad) if bad else "OK: nothing lost, "
              "stuck or wrong; no 5xx but 503/507"))
        if args.json:
            slim = [{k: v for k, v in r.items() if k != "_details"} for r in results]
            print(json.dumps({"ok": not bad, "seconds": round(total, 1), "phases": slim}, separators=(",", ":")))
        failed = bool(bad)
        return 1 if bad else 0
    except KeyboardInterrupt:
        log("interrupted: cleaning up")
        return 130
    finally:
        memory.stop.set()
        for fn in reversed(cleanups):
            try:
                fn()
            except Exception as e:  # noqa: BLE001 - cleanup goes on
                log(f"cleanup: {e!r}")
        if args.keep_tmp or failed:
            log(f"kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
