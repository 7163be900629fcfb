#!/usr/bin/env python3
"""Mixed-load check of the topple HTTP service.

Starts `topple serve` on a free loopback port with a new SQLite database in a
temporary directory (or attaches to a running server with --url), then sends
--jobs job submissions (default 10,000) from --clients concurrent asyncio
clients (default 64) on keep-alive connections. The mix:

* mostly small time histories with varied block, pulse, formulation, solver and
  outputs, so most are distinct; about one in nine is drawn from a small pool
  of "hot" specs, some written in other units (a_p_g, a_p, omega_p) or with the
  defaults spelled out, which must all hit the cache;
* small overturning spectra and friction spectra;
* about 15 % of valid submissions with ?wait=N (N up to 5 s);
* a few invalid requests (bad field values, malformed JSON, non-UTF-8 body,
  unknown kind or field, bad ?wait=, a body over 1 MiB), each with the exact
  4xx the README documents;
* a few DELETEs of a client's own jobs, half of them followed by a
  resubmission of the same spec (which must queue the job again);
* interleaved GET /v1/jobs/{id} polls, result fetches (JSON and CSV), list
  calls that follow next_cursor, health probes and unknown-id probes.

A 429 answer is retried after its Retry-After delay (at least that long); 429s
are counted. After the load, every accepted job is polled until it is terminal
(--drain-timeout), the whole listing is walked, and every succeeded job's result
is fetched.

Checks (the exit status is 1 if any fails):

* every response is 2xx, 4xx or 429: no 5xx, no connection error, no timeout;
* every response has the status its request calls for (e.g. 422 for an invalid
  spec, 200 or 202 for a valid one, 200 for a poll of an accepted id);
* no lost job: every accepted id is found by GET and in the listing and
  reaches a terminal state;
* every succeeded job has a fetchable JSON result; a 200 submission carries it;
* a ?wait=N submission is answered within N s (plus --wait-slack);
* only jobs the clients deleted end canceled, and a job resubmitted after its
  cancellation runs again;
* all submissions of one hot spec (in whatever units) get one key and one id;
* with a server this script started: /metrics agrees with the clients' counts
  (cache hits, jobs by status, empty queue), the log has no ERROR line, and
  SIGTERM stops the server with status 0.

Jobs that fail (a computation may fail on a valid spec) are listed as
warnings with their error and spec; they do not change the exit status.

The server's resident memory (VmRSS in /proc/PID/status) is sampled every
100 ms and its peak reported with VmHWM read at the end (with --url, only when
--pid names the server process).

Run (needs aiohttp, listed in bench/requirements.txt):

    python3 -m venv /tmp/bench-venv
    /tmp/bench-venv/bin/pip install -r bench/requirements.txt
    /tmp/bench-venv/bin/python bench/load_mixed.py                   # target/release/topple
    /tmp/bench-venv/bin/python bench/load_mixed.py --binary PATH --json-out summary.json
    /tmp/bench-venv/bin/python bench/load_mixed.py --url http://127.0.0.1:8080 --pid PID

The binary is copied to the temporary directory before it starts, so a rebuild
of target/ during the run changes nothing. The temporary directory (database
and server log) is removed at the end unless a check failed or --keep-tmp is
given.
"""

from __future__ import annotations

import argparse
import asyncio
import email.utils
import json
import math
import os
import random
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from datetime import datetime

import aiohttp

TERMINAL = ("succeeded", "failed", "canceled")
STATUSES = ("queued", "running") + TERMINAL
KINDS = ("time_history", "spectrum", "friction_spectrum")
PULSES = ("one_sine", "one_cosine", "cn")
G = 9.81

# Shares of the submissions (the rest are distinct time histories).
INVALID_SHARE = 0.02
SPECTRUM_SHARE = 0.04
FRICTION_SHARE = 0.04
HOT_SHARE = 0.11
HOT_POOL = 40
# Per valid submission.
WAIT_SHARE = 0.15
WAIT_VALUES = (0, 0.5, 1, 2, 5)
DELETE_SHARE = {"time_history": 0.01, "spectrum": 0.15, "friction_spectrum": 0.05}
RESUBMIT_AFTER_DELETE = 0.5
POLLS = (0, 0, 1, 1, 2)
# Per operation, whatever it submits.
LIST_SHARE = 0.03
RESULT_SHARE = 0.10
PROBE_SHARE = 0.01

MAX_SHOWN_ANOMALIES = 20
TEXT_LIMIT = 2000


# --------------------------------------------------------------------------
# The workload


@dataclass
class Op:
    """One submission and what its client does after it."""

    index: int
    kind: str  # a job kind, or "invalid"
    body: bytes
    query: str = ""
    expect: tuple[int, ...] = (200, 202)
    label: str = ""  # the invalid case, or the hot group "hot-N"
    polls: int = 0
    delete: bool = False
    resubmit: bool = False
    list_call: bool = False
    fetch_result: bool = False
    probe: bool = False


def r4(x: float) -> float:
    return round(x, 4)


def random_block(rng: random.Random, decimals: int = 4) -> dict:
    block = {
        "alpha": round(rng.uniform(0.05, 0.4), decimals),
        "p": round(rng.uniform(1.0, 5.0), decimals),
    }
    if rng.random() < 0.8:
        block["eta"] = round(rng.uniform(0.5, 0.95), decimals)
    if rng.random() < 0.2:
        block["mu"] = round(rng.uniform(0.2, 0.9), 3)
    return block


def random_family(rng: random.Random) -> dict:
    pulse = {"type": rng.choice(PULSES)}
    if pulse["type"] == "cn":
        pulse["n"] = rng.randint(1, 3)
    return pulse


def time_history(rng: random.Random) -> dict:
    """A distinct, small time history."""
    block = random_block(rng)
    pulse = random_family(rng)
    pulse["omega_ratio"] = r4(rng.uniform(0.5, 10.0))
    amplitude = r4(rng.uniform(0.5, 8.0))
    if rng.random() < 0.2:
        pulse["a_p_g"] = r4(amplitude * block["alpha"])
    else:
        pulse["a_p_alpha_g"] = amplitude
    formulation = rng.choice(("nonlinear", "nonlinear", "linear"))
    spec = {"kind": "time_history", "block": block, "pulse": pulse, "formulation": formulation}
    u = rng.random()
    if formulation == "nonlinear" and u < 0.15:
        spec["solver"] = {"method": "dopri5", "rtol": 1e-8, "atol": 1e-10}
    elif formulation == "linear" and u < 0.15:
        spec["solver"] = {"method": "dop853"}
    if rng.random() < 0.25:
        spec["outputs"] = {"series": rng.choice((10, 50, 200))}
    elif rng.random() < 0.1:
        spec["outputs"] = {"impacts": False, "reactions": False}
    return spec


def hot_specs(rng: random.Random) -> list[dict]:
    """The pool of repeated time histories: two decimals, so that every unit
    conversion below is exact to far more than the 12 digits the cache key keeps."""
    pool = []
    for _ in range(HOT_POOL):
        block = {
            "alpha": round(rng.uniform(0.1, 0.4), 2),
            "p": round(rng.uniform(1.0, 5.0), 2),
            "eta": round(rng.uniform(0.5, 0.95), 2),
        }
        pulse = random_family(rng)
        pulse["omega_ratio"] = round(rng.uniform(0.5, 10.0), 2)
        pulse["a_p_alpha_g"] = round(rng.uniform(0.5, 8.0), 2)
        pool.append({"kind": "time_history", "block": block, "pulse": pulse, "formulation": "nonlinear"})
    return pool


def hot_variant(spec: dict, rng: random.Random) -> dict:
    """The same job as `spec`, possibly written differently."""
    s = json.loads(json.dumps(spec))
    block, pulse = s["block"], s["pulse"]
    u = rng.random()
    if u < 0.15:
        pulse["a_p_g"] = pulse.pop("a_p_alpha_g") * block["alpha"]
    elif u < 0.3:
        pulse["a_p"] = pulse.pop("a_p_alpha_g") * block["alpha"] * G
    elif u < 0.4:
        pulse["omega_p"] = pulse.pop("omega_ratio") * block["p"]
    elif u < 0.5:
        block["g"] = G
        s["solver"] = {"method": "dop853", "rtol": 1e-10, "atol": 1e-12}
        s["outputs"] = {"impacts": True, "reactions": True, "max_free_impacts": 1000}
    elif u < 0.6:
        del s["formulation"]
    if rng.random() < 0.3:
        s = dict(reversed(list(s.items())))
    return s


def spectrum(rng: random.Random) -> dict:
    spec = {
        "kind": "spectrum",
        "block": random_block(rng),
        "pulse": random_family(rng),
        "formulation": rng.choice(("nonlinear", "linear")),
        "a_max_alpha_g": rng.choice((6, 10, 20)),
        "tolerance": rng.choice((1e-3, 1e-4)),
    }
    lo = r4(rng.uniform(0.25, 3.0))
    u = rng.random()
    if u < 0.6:
        spec["omega_ratio"] = {"from": lo, "to": r4(lo + rng.uniform(0.5, 7.0)), "steps": rng.randint(1, 4)}
    elif u < 0.8:
        spec["omega_ratio"] = sorted(r4(rng.uniform(0.25, 10.0)) for _ in range(rng.randint(1, 3)))
    else:
        spec["omega_ratio"] = lo
    return spec


def friction(rng: random.Random) -> dict:
    spec = {
        "kind": "friction_spectrum",
        "block": random_block(rng),
        "pulse": random_family(rng),
        "formulation": rng.choice(("nonlinear", "linear")),
        "omega_ratio": r4(rng.uniform(0.5, 10.0)),
    }
    lo = r4(rng.uniform(1.1, 3.0))
    if rng.random() < 0.7:
        spec["a_alpha_g"] = {"from": lo, "to": r4(lo + rng.uniform(1.0, 8.0)), "steps": rng.randint(2, 8)}
    else:
        spec["a_alpha_g"] = [lo, r4(lo + 1.5), r4(lo + 4.0)]
    return spec


def invalid(rng: random.Random) -> tuple[str, bytes, str, int]:
    """An invalid submission: (label, body, query, the status it must get)."""
    base = time_history(rng)
    case = rng.choices(
        (
            "bad_alpha",
            "unknown_kind",
            "malformed_json",
            "two_frequencies",
            "exact_nonlinear",
            "zero_steps",
            "unknown_field",
            "not_object",
            "missing_amplitudes",
            "cn_zero",
            "negative_wait",
            "non_utf8",
            "oversized",
        ),
        weights=(3, 2, 3, 2, 2, 2, 2, 1, 2, 1, 2, 1, 0.3),
    )[0]
    if case == "bad_alpha":
        base["block"]["alpha"] = r4(rng.uniform(1.58, 3.0))
        return case, dump(base), "", 422
    if case == "unknown_kind":
        base["kind"] = "time_histories"
        return case, dump(base), "", 422
    if case == "malformed_json":
        return case, dump(base)[: rng.randint(1, 40)], "", 400
    if case == "two_frequencies":
        base["pulse"]["omega_p"] = 3.0
        return case, dump(base), "", 422
    if case == "exact_nonlinear":
        base["formulation"] = "nonlinear"
        base["solver"] = {"method": "exact"}
        return case, dump(base), "", 422
    if case == "zero_steps":
        s = spectrum(rng)
        s["omega_ratio"] = {"from": 1.0, "to": 2.0, "steps": 0}
        return case, dump(s), "", 422
    if case == "unknown_field":
        base["colour"] = "red"
        return case, dump(base), "", 422
    if case == "not_object":
        return case, b"[1, 2, 3]", "", 422
    if case == "missing_amplitudes":
        s = friction(rng)
        del s["a_alpha_g"]
        return case, dump(s), "", 422
    if case == "cn_zero":
        base["pulse"] = {"type": "cn", "n": 0, "omega_ratio": 3.0, "a_p_alpha_g": 2.0}
        return case, dump(base), "", 422
    if case == "negative_wait":
        return case, dump(base), "?wait=-1", 400
    if case == "non_utf8":
        return case, b'{"kind": "\xff\xfe"}', "", 400
    return case, b" " * (1 << 20) + dump(base), "", 413


def dump(spec) -> bytes:
    return json.dumps(spec).encode()


def make_plan(jobs: int, seed: int) -> list[Op]:
    rng = random.Random(seed)
    pool = hot_specs(rng)
    plan = []
    for i in range(jobs):
        u = rng.random()
        if u < INVALID_SHARE:
            label, body, query, status = invalid(rng)
            op = Op(i, "invalid", body, query, (status,), label)
        else:
            label = ""
            if u < INVALID_SHARE + SPECTRUM_SHARE:
                spec = spectrum(rng)
            elif u < INVALID_SHARE + SPECTRUM_SHARE + FRICTION_SHARE:
                spec = friction(rng)
            elif u < INVALID_SHARE + SPECTRUM_SHARE + FRICTION_SHARE + HOT_SHARE:
                h = rng.randrange(HOT_POOL)
                spec, label = hot_variant(pool[h], rng), f"hot-{h}"
            else:
                spec = time_history(rng)
            op = Op(i, spec["kind"], dump(spec), label=label)
            if rng.random() < WAIT_SHARE:
                op.query = f"?wait={rng.choice(WAIT_VALUES)}"
            else:
                op.polls = rng.choice(POLLS)
            # Hot jobs are shared by every client: only distinct jobs are deleted.
            if not label and rng.random() < DELETE_SHARE[op.kind]:
                op.delete = True
                op.resubmit = rng.random() < RESUBMIT_AFTER_DELETE
        op.list_call = rng.random() < LIST_SHARE
        op.fetch_result = rng.random() < RESULT_SHARE
        op.probe = rng.random() < PROBE_SHARE
        plan.append(op)
    return plan


# --------------------------------------------------------------------------
# Bookkeeping


@dataclass
class Reply:
    status: int
    body: bytes
    headers: dict
    elapsed: float  # s, of the final attempt

    def json(self):
        try:
            return json.loads(self.body)
        except ValueError:
            return None


@dataclass
class JobInfo:
    kind: str
    label: str
    deleted_at: float | None = None  # when a DELETE answered 200 (canceled)
    resubmitted_at: float | None = None  # when it was submitted again after that


@dataclass
class Stats:
    requests: int = 0
    by_status: dict = field(default_factory=dict)
    latency: dict = field(default_factory=dict)
    submissions: int = 0
    accepted: int = 0
    cached: int = 0
    rejected_4xx: int = 0
    http_429: int = 0
    retry_after_missing: int = 0
    deletes: int = 0
    deleted_canceled: int = 0
    delete_conflicts: int = 0
    resubmitted: int = 0
    slowest: dict = field(default_factory=dict)  # category -> (seconds, request)
    anomalies: list = field(default_factory=list)
    warnings: list = field(default_factory=list)


def percentile_ms(values: list[float], q: float) -> float | None:
    """The nearest-rank q-quantile of durations in seconds, in ms."""
    if not values:
        return None
    s = sorted(values)
    return round(1000 * s[min(len(s) - 1, max(0, math.ceil(q * len(s)) - 1))], 2)


def text(b: bytes) -> str:
    t = b.decode("utf-8", "replace")
    return t if len(t) <= TEXT_LIMIT else f"{t[:TEXT_LIMIT]}… ({len(b)} bytes)"


def seconds_between(start: str | None, end: str | None) -> float | None:
    """Seconds from one RFC 3339 timestamp to another, or None."""
    try:
        a, b = (datetime.fromisoformat(t.replace("Z", "+00:00")) for t in (start, end))
    except (AttributeError, TypeError, ValueError):
        return None
    return round((b - a).total_seconds(), 3)


def retry_after(headers: dict) -> float | None:
    value = headers.get("retry-after")
    if value is None:
        return None
    try:
        return max(0.0, float(value))
    except ValueError:
        pass
    try:
        when = email.utils.parsedate_to_datetime(value).timestamp()
        return max(0.0, when - time.time())
    except (TypeError, ValueError):
        return None


class Load:
    """The shared HTTP client, counters and job table."""

    def __init__(self, base: str, session: aiohttp.ClientSession, args):
        self.base = base
        self.session = session
        self.args = args
        self.stats = Stats()
        self.jobs: dict[str, JobInfo] = {}
        self.hot: dict[str, dict] = {}  # label -> {"keys": set, "ids": set, "bodies": [first few]}

    def anomaly(self, what: str, method: str, path: str, body: bytes | None, reply: Reply | None, **extra):
        entry = {"what": what, "request": f"{method} {path}"}
        if body is not None:
            entry["request_body"] = text(body)
        if reply is not None:
            entry["status"] = reply.status
            entry["response_headers"] = reply.headers
            entry["response_body"] = text(reply.body)
        entry.update(extra)
        self.stats.anomalies.append(entry)

    async def request(
        self, method: str, path: str, category: str, expect: tuple[int, ...], body: bytes | None = None, wait: float = 0
    ) -> Reply | None:
        """Sends one request, retrying after every 429; None on a transport error.

        The latency recorded is that of the final attempt; each 429 is counted.
        """
        st = self.stats
        give_up = time.monotonic() + self.args.retry_limit
        headers = {"content-type": "application/json"} if body is not None else {}
        timeout = aiohttp.ClientTimeout(total=self.args.request_timeout + wait)
        while True:
            t0 = time.perf_counter()
            try:
                async with self.session.request(
                    method, self.base + path, data=body, headers=headers, timeout=timeout
                ) as r:
                    reply = Reply(
                        r.status, await r.read(), {k.lower(): v for k, v in r.headers.items()}, time.perf_counter() - t0
                    )
            except (TimeoutError, aiohttp.ClientError) as e:
                st.requests += 1
                st.by_status["transport error"] = st.by_status.get("transport error", 0) + 1
                self.anomaly(
                    f"transport error: {type(e).__name__}: {e}",
                    method,
                    path,
                    body,
                    None,
                    after_s=round(time.perf_counter() - t0, 3),
                )
                return None
            dt = reply.elapsed
            st.requests += 1
            st.by_status[reply.status] = st.by_status.get(reply.status, 0) + 1
            if reply.status == 429:
                st.http_429 += 1
                delay = retry_after(reply.headers)
                if delay is None:
                    st.retry_after_missing += 1
                    delay = 1.0
                if time.monotonic() + delay > give_up:
                    self.anomaly("429 retried past --retry-limit", method, path, body, reply)
                    return None
                # At least the delay asked for, spread a little so that retries do not arrive together.
                await asyncio.sleep(delay * (1 + 0.1 * random.random()))
                continue
            st.latency.setdefault(category, []).append(dt)
            if dt > st.slowest.get(category, (0.0, ""))[0]:
                st.slowest[category] = (dt, f"{method} {path} -> {reply.status}")
            if not (200 <= reply.status < 300 or 400 <= reply.status < 500):
                self.anomaly(f"HTTP {reply.status}", method, path, body, reply)
            elif reply.status not in expect:
                self.anomaly(f"expected {' or '.join(map(str, expect))}", method, path, body, reply)
            return reply

    # ---- submissions

    async def submit(self, op: Op, body: bytes, query: str) -> str | None:
        """POSTs a job; returns its id when accepted."""
        st = self.stats
        wait = float(query.split("=", 1)[1]) if query.startswith("?wait=") else 0.0
        category = "submit (invalid)" if op.kind == "invalid" else ("submit ?wait" if query else "submit")
        path = "/v1/jobs" + query
        reply = await self.request("POST", path, category, op.expect, body, wait)
        if reply is None:
            return None
        st.submissions += 1
        if 400 <= reply.status < 500:
            st.rejected_4xx += 1
        if op.kind == "invalid" or reply.status not in (200, 202):
            return None
        doc = reply.json()
        if not isinstance(doc, dict) or not isinstance(doc.get("id"), str):
            self.anomaly("accepted submission without an id", "POST", path, body, reply)
            return None
        st.accepted += 1
        job_id = doc["id"]
        if doc.get("cached") is True:
            st.cached += 1
        if reply.headers.get("location") != f"/v1/jobs/{job_id}":
            self.anomaly("Location header does not name the job", "POST", path, body, reply)
        if doc.get("kind") != op.kind or doc.get("status") not in STATUSES:
            self.anomaly("accepted job with a wrong kind or status", "POST", path, body, reply)
        if reply.status == 200 and (doc.get("status") != "succeeded" or not isinstance(doc.get("result"), dict)):
            self.anomaly("200 submission without a succeeded job and its result", "POST", path, body, reply)
        if query and reply.elapsed > wait + self.args.wait_slack:
            # The job's own timestamps show, independently of the client's clock, whether
            # the answer waited for a job that finished after the deadline.
            self.anomaly(
                f"?wait={wait:g} answered after {reply.elapsed:.2f} s",
                "POST",
                path,
                body,
                reply,
                job_status=doc.get("status"),
                job_created_to_finished_s=seconds_between(doc.get("created_at"), doc.get("finished_at")),
            )
        self.jobs.setdefault(job_id, JobInfo(op.kind, op.label))
        if op.label.startswith("hot-"):
            group = self.hot.setdefault(op.label, {"keys": set(), "ids": set(), "bodies": []})
            group["keys"].add(doc.get("key"))
            group["ids"].add(job_id)
            if len(group["bodies"]) < 4:
                group["bodies"].append(text(body))
        return job_id

    async def delete(self, op: Op, job_id: str):
        st = self.stats
        path = f"/v1/jobs/{job_id}"
        reply = await self.request("DELETE", path, "delete", (200, 409))
        st.deletes += 1
        if reply is None:
            return
        if reply.status == 409:
            st.delete_conflicts += 1
            return
        if reply.status != 200:
            return
        doc = reply.json()
        if not isinstance(doc, dict) or doc.get("status") != "canceled":
            self.anomaly("DELETE answered 200 without status canceled", "DELETE", path, None, reply)
            return
        st.deleted_canceled += 1
        self.jobs[job_id].deleted_at = time.monotonic()
        if op.resubmit:
            again = await self.submit(op, op.body, "")
            st.resubmitted += 1
            if again is not None:
                self.jobs[again].resubmitted_at = time.monotonic()

    # ---- reads

    async def poll(self, job_id: str, rng: random.Random):
        path = f"/v1/jobs/{job_id}"
        reply = await self.request("GET", path, "poll", (200,))
        if reply is None or reply.status != 200:
            return
        doc = reply.json()
        if (
            not isinstance(doc, dict)
            or doc.get("id") != job_id
            or doc.get("status") not in STATUSES
            or not isinstance(doc.get("progress"), (int, float))
            or not 0.0 <= doc["progress"] <= 1.0
        ):
            self.anomaly("malformed job document", "GET", path, None, reply)
            return
        if doc["status"] == "succeeded" and rng.random() < 0.3:
            await self.result(job_id, rng, must_exist=True)

    async def result(self, job_id: str, rng: random.Random, must_exist: bool = False):
        kind = self.jobs[job_id].kind
        csv = kind != "time_history" and rng.random() < 0.3
        path = f"/v1/jobs/{job_id}/result" + ("?format=csv" if csv else "")
        reply = await self.request("GET", path, "result", (200,) if must_exist else (200, 409))
        if reply is None or reply.status != 200:
            return
        if csv:
            if not reply.headers.get("content-type", "").startswith("text/csv") or b"," not in reply.body:
                self.anomaly("CSV result is not CSV", "GET", path, None, reply)
        elif not isinstance(reply.json(), dict):
            self.anomaly("result is not a JSON object", "GET", path, None, reply)

    async def list_jobs(self, rng: random.Random):
        limit = rng.choice((1, 5, 20, 50, 100))
        params = [f"limit={limit}"]
        status = kind = None
        if rng.random() < 0.3:
            status = rng.choice(STATUSES)
            params.append(f"status={status}")
        if rng.random() < 0.3:
            kind = rng.choice(KINDS)
            params.append(f"kind={kind}")
        cursor, previous = None, None
        for _ in range(rng.randint(1, 3)):
            path = "/v1/jobs?" + "&".join(params + ([f"cursor={cursor}"] if cursor else []))
            reply = await self.request("GET", path, "list", (200,))
            if reply is None or reply.status != 200:
                return
            page = reply.json()
            if not isinstance(page, dict) or not isinstance(page.get("jobs"), list):
                self.anomaly("malformed page", "GET", path, None, reply)
                return
            ids = [j.get("id") for j in page["jobs"]]
            ok = (
                len(ids) <= limit
                and all(isinstance(i, str) for i in ids)
                and ids == sorted(ids, reverse=True)
                and (previous is None or not ids or ids[0] < previous)
                and all(status is None or j.get("status") == status for j in page["jobs"])
                and all(kind is None or j.get("kind") == kind for j in page["jobs"])
            )
            if not ok:
                self.anomaly("page not newest first, over its limit, or not filtered", "GET", path, None, reply)
                return
            cursor = page.get("next_cursor")
            if not cursor:
                return
            previous = ids[-1] if ids else previous

    async def probe(self, rng: random.Random):
        u = rng.random()
        if u < 0.4:
            await self.request("GET", rng.choice(("/healthz", "/readyz")), "probe", (200,))
        elif u < 0.6:
            await self.request("GET", "/metrics", "probe", (200,))
        elif u < 0.8:
            await self.request("GET", "/v1/jobs/00000000-0000-7000-8000-000000000000", "probe", (404,))
        else:
            await self.request("GET", "/v1/jobs/not-a-job", "probe", (400,))

    # ---- the load phase

    async def client(self, cid: int, plan: list[Op], counter):
        rng = random.Random(self.args.seed * 7919 + cid)
        own: list[str] = []
        for i in counter:
            op = plan[i]
            job_id = await self.submit(op, op.body, op.query)
            if job_id is not None:
                own.append(job_id)
                if op.delete:
                    await asyncio.sleep(rng.uniform(0.0, 0.3))
                    await self.delete(op, job_id)
                for k in range(op.polls):
                    await self.poll(job_id if k == 0 else rng.choice(own[-20:]), rng)
            if op.fetch_result and own:
                await self.result(rng.choice(own[-50:]), rng)
            if op.list_call:
                await self.list_jobs(rng)
            if op.probe:
                await self.probe(rng)

    # ---- after the load

    async def drain(self, timeout: float) -> tuple[dict, set, set]:
        """Polls every accepted job until it is terminal: (final documents, 404s, still pending)."""
        final: dict[str, dict] = {}
        missing: set[str] = set()
        pending = set(self.jobs)
        deadline = time.monotonic() + timeout
        gate = asyncio.Semaphore(self.args.clients)

        async def look(job_id):
            async with gate:
                path = f"/v1/jobs/{job_id}"
                reply = await self.request("GET", path, "drain poll", (200,))
                if reply is None:
                    return
                if reply.status == 404:
                    missing.add(job_id)
                    pending.discard(job_id)
                elif reply.status == 200:
                    doc = reply.json()
                    if isinstance(doc, dict) and doc.get("status") in TERMINAL:
                        final[job_id] = doc
                        pending.discard(job_id)

        pause = 0.5
        while pending and time.monotonic() < deadline:
            await asyncio.gather(*(look(j) for j in list(pending)))
            if pending:
                await asyncio.sleep(pause)
                pause = min(5.0, pause * 1.5)
        return final, missing, pending

    async def listed_ids(self) -> set[str]:
        seen: set[str] = set()
        cursor = None
        while True:
            path = "/v1/jobs?limit=500" + (f"&cursor={cursor}" if cursor else "")
            reply = await self.request("GET", path, "list", (200,))
            if reply is None or reply.status != 200:
                return seen
            page = reply.json()
            if not isinstance(page, dict) or not isinstance(page.get("jobs"), list):
                self.anomaly("malformed page", "GET", path, None, reply)
                return seen
            seen.update(j.get("id") for j in page["jobs"])
            cursor = page.get("next_cursor")
            if not cursor:
                return seen

    async def fetch_results(self, ids: list[str]) -> int:
        gate = asyncio.Semaphore(self.args.clients)
        fetched = 0

        async def one(job_id):
            nonlocal fetched
            async with gate:
                path = f"/v1/jobs/{job_id}/result"
                reply = await self.request("GET", path, "result", (200,))
                if reply is None or reply.status != 200:
                    return
                doc = reply.json()
                if not isinstance(doc, dict) or doc.get("spec", {}).get("kind") != self.jobs[job_id].kind:
                    self.anomaly("result is not the job's result document", "GET", path, None, reply)
                    return
                fetched += 1

        await asyncio.gather(*(one(j) for j in ids))
        return fetched

    async def metrics(self) -> dict:
        reply = await self.request("GET", "/metrics", "probe", (200,))
        out = {}
        if reply is None or reply.status != 200:
            return out
        for line in reply.body.decode().splitlines():
            m = re.match(r"^(topple_jobs\{status=\"(\w+)\"\}|topple_cache_hits_total|topple_queue_depth) (\S+)$", line)
            if m:
                out[m.group(2) or m.group(1)] = float(m.group(3))
        return out


# --------------------------------------------------------------------------
# The server


class RssSampler(threading.Thread):
    """Samples VmRSS of a process every `interval` seconds."""

    def __init__(self, pid: int, interval: float = 0.1):
        super().__init__(daemon=True)
        self.pid, self.interval = pid, interval
        self.done = threading.Event()
        self.samples = 0
        self.first_kb = self.peak_kb = self.last_kb = None

    def read(self) -> dict:
        out = {}
        try:
            with open(f"/proc/{self.pid}/status") as f:
                for line in f:
                    if line.startswith(("VmRSS:", "VmHWM:")):
                        out[line.split(":")[0]] = int(line.split()[1])
        except OSError:
            pass
        return out

    def run(self):
        while True:
            rss = self.read().get("VmRSS")
            if rss is not None:
                self.samples += 1
                self.first_kb = rss if self.first_kb is None else self.first_kb
                self.peak_kb = max(self.peak_kb or 0, rss)
                self.last_kb = rss
            if self.done.wait(self.interval):
                return


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


async def wait_ready(base: str, proc: subprocess.Popen | None, limit: float = 30.0):
    deadline = time.monotonic() + limit
    async with aiohttp.ClientSession() as s:
        while time.monotonic() < deadline:
            if proc is not None and proc.poll() is not None:
                sys.exit(f"the server exited with status {proc.returncode} before it was ready")
            try:
                async with s.get(base + "/readyz", timeout=aiohttp.ClientTimeout(total=2)) as r:
                    if r.status == 200:
                        return
            except (TimeoutError, aiohttp.ClientError):
                pass
            await asyncio.sleep(0.05)
    sys.exit(f"{base}/readyz did not answer 200 within {limit:.0f} s")


def start_server(args, tmp: str) -> tuple[subprocess.Popen, str, str]:
    if not os.path.isfile(args.binary):
        sys.exit(f"no binary at {args.binary}: run `cargo build --release` or pass --binary PATH")
    binary = os.path.join(tmp, "topple")
    shutil.copy2(args.binary, binary)
    port = free_port()
    cmd = [binary, "serve", "--addr", f"127.0.0.1:{port}", "--database", f"sqlite://{tmp}/topple.db"]
    if args.workers:
        cmd += ["--workers", str(args.workers)]
    log_path = os.path.join(tmp, "server.log")
    with open(log_path, "wb") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
    return proc, f"http://127.0.0.1:{port}", log_path


def stop_server(proc: subprocess.Popen, limit: float = 30.0) -> tuple[int | None, float]:
    t0 = time.perf_counter()
    proc.send_signal(signal.SIGTERM)
    try:
        code = proc.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        code = None
    return code, time.perf_counter() - t0


def log_levels(path: str) -> tuple[int, int, list[str]]:
    warn = error = 0
    shown = []
    with open(path, errors="replace") as f:
        for line in f:
            if " WARN " in line or '"level":"WARN"' in line:
                warn += 1
            elif " ERROR " in line or '"level":"ERROR"' in line:
                error += 1
                if len(shown) < 10:
                    shown.append(line.rstrip())
    return warn, error, shown


# --------------------------------------------------------------------------
# The run


async def run(args) -> dict:
    plan = make_plan(args.jobs, args.seed)
    tmp = None
    proc = None
    if args.url:
        base, pid = args.url.rstrip("/"), args.pid
    else:
        tmp = tempfile.mkdtemp(prefix="topple-load-mixed-")
        proc, base, log_path = start_server(args, tmp)
        pid = proc.pid
    summary: dict = {"server": base, "jobs": args.jobs, "clients": args.clients, "seed": args.seed}
    failed_checks: list[str] = []
    try:
        await wait_ready(base, proc)
        sampler = RssSampler(pid) if pid else None
        if sampler:
            sampler.start()
        print(
            f"server {base} (pid {pid or 'unknown'}); {args.jobs} submissions from {args.clients} clients; "
            f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
            flush=True,
        )
        mix: dict[str, int] = {}
        for op in plan:
            name = (
                op.kind
                + (" (hot)" if op.label.startswith("hot-") else "")
                + (" ?wait" if op.query.startswith("?wait=") and op.kind != "invalid" else "")
            )
            mix[name] = mix.get(name, 0) + 1
        summary["mix"] = dict(sorted(mix.items()))
        connector = aiohttp.TCPConnector(limit=args.clients)
        async with aiohttp.ClientSession(connector=connector) as session:
            load = Load(base, session, args)
            counter = iter(range(len(plan)))
            t0 = time.perf_counter()
            await asyncio.gather(*(load.client(c, plan, counter) for c in range(args.clients)))
            t_load = time.perf_counter() - t0
            load_requests = load.stats.requests
            print(f"load phase: {t_load:.1f} s, {load_requests} requests; draining…", flush=True)

            t1 = time.perf_counter()
            final, missing, pending = await load.drain(args.drain_timeout)
            t_drain = time.perf_counter() - t1
            listed = await load.listed_ids()
            succeeded = [j for j, d in final.items() if d["status"] == "succeeded"]
            fetched = await load.fetch_results(succeeded)
            metrics = await load.metrics()
            t_total = time.perf_counter() - t0

        st = load.stats
        rss = {}
        if sampler:
            hwm = sampler.read().get("VmHWM")
            sampler.done.set()
            sampler.join()
            rss = {
                "samples": sampler.samples,
                "first_kb": sampler.first_kb,
                "peak_kb": sampler.peak_kb,
                "last_kb": sampler.last_kb,
                "vmhwm_kb": hwm,
            }

        # ---- checks on the jobs
        final_status: dict[str, int] = {}
        for d in final.values():
            final_status[d["status"]] = final_status.get(d["status"], 0) + 1
        for job_id in sorted(missing):
            load.anomaly("lost job: an accepted id answers 404", "GET", f"/v1/jobs/{job_id}", None, None)
        for job_id in sorted(pending):
            load.anomaly(
                f"job not terminal after --drain-timeout {args.drain_timeout:.0f} s",
                "GET",
                f"/v1/jobs/{job_id}",
                None,
                None,
            )
        unlisted = sorted(set(load.jobs) - listed)
        for job_id in unlisted[:50]:
            load.anomaly(
                "accepted job missing from GET /v1/jobs",
                "GET",
                "/v1/jobs?limit=500 (all pages)",
                None,
                None,
                job_id=job_id,
            )
        for job_id, d in sorted(final.items()):
            info = load.jobs[job_id]
            if d["status"] == "failed":
                # A computation may fail on a valid spec (reported, not a service fault).
                st.warnings.append({"what": "job failed", "id": job_id, "error": d.get("error"), "spec": d.get("spec")})
            elif d["status"] == "canceled" and (info.deleted_at is None or info.resubmitted_at is not None):
                why = (
                    "resubmitted after its cancellation, yet canceled"
                    if info.deleted_at
                    else "canceled without a DELETE"
                )
                load.anomaly(why, "GET", f"/v1/jobs/{job_id}", None, None, job=d)
        for label, g in sorted(load.hot.items()):
            if len(g["keys"]) != 1 or len(g["ids"]) != 1:
                load.anomaly(
                    f"one spec, several cache keys or ids ({label})",
                    "POST",
                    "/v1/jobs",
                    None,
                    None,
                    keys=sorted(map(str, g["keys"])),
                    ids=sorted(g["ids"]),
                    bodies=g["bodies"],
                )

        # ---- checks on the server
        server = {"metrics": metrics}
        if proc is not None:
            counts = {s: int(metrics.get(s, -1)) for s in STATUSES}
            expect = {s: final_status.get(s, 0) for s in STATUSES}
            if counts != expect:
                failed_checks.append(f"/metrics topple_jobs {counts} differ from the jobs seen {expect}")
            if int(metrics.get("topple_cache_hits_total", -1)) != st.cached:
                failed_checks.append(
                    f"/metrics topple_cache_hits_total {metrics.get('topple_cache_hits_total')} "
                    f"!= cached submissions {st.cached}"
                )
            if metrics.get("topple_queue_depth", -1) != 0:
                failed_checks.append(f"/metrics topple_queue_depth {metrics.get('topple_queue_depth')} after the drain")
            if proc.poll() is not None:
                failed_checks.append(f"the server exited during the run with status {proc.returncode}")
            for key, name in (("db_bytes", "topple.db"), ("db_wal_bytes", "topple.db-wal")):
                path = os.path.join(tmp, name)
                server[key] = os.path.getsize(path) if os.path.exists(path) else None
            code, took = stop_server(proc)
            proc = None
            warn, error, error_lines = log_levels(log_path)
            server.update(
                {
                    "exit_status": code,
                    "shutdown_s": round(took, 3),
                    "log_warn": warn,
                    "log_error": error,
                    "log": log_path,
                }
            )
            if code != 0:
                failed_checks.append(f"SIGTERM: the server exited with {code} after {took:.1f} s")
            if error:
                failed_checks.append(f"{error} ERROR lines in the server log, e.g. {error_lines[0]}")
                server["log_error_lines"] = error_lines

        if st.anomalies:
            failed_checks.insert(0, f"{len(st.anomalies)} anomalous requests or jobs (see anomalies)")

        lat = {}
        for cat, values in sorted(st.latency.items()):
            lat[cat] = {
                "n": len(values),
                "p50_ms": percentile_ms(values, 0.5),
                "p99_ms": percentile_ms(values, 0.99),
                "max_ms": round(1000 * max(values), 2),
                "slowest": st.slowest[cat][1],
            }
        all_submits = [v for c in ("submit", "submit ?wait", "submit (invalid)") for v in st.latency.get(c, [])]
        summary.update(
            {
                "submissions": st.submissions,
                "accepted": st.accepted,
                "cached": st.cached,
                "rejected_4xx": st.rejected_4xx,
                "http_429": st.http_429,
                "http_429_without_retry_after": st.retry_after_missing,
                "distinct_jobs": len(load.jobs),
                "final_status": final_status,
                "canceled": final_status.get("canceled", 0),
                "failed": final_status.get("failed", 0),
                "deletes": {
                    "sent": st.deletes,
                    "canceled": st.deleted_canceled,
                    "already_finished_409": st.delete_conflicts,
                    "resubmitted_after_cancel": st.resubmitted,
                },
                "lost": len(missing) + len(pending) + len(unlisted),
                "results_fetched": fetched,
                "requests": st.requests,
                "requests_by_status": {str(k): v for k, v in sorted(st.by_status.items(), key=lambda kv: str(kv[0]))},
                "load_s": round(t_load, 3),
                "drain_s": round(t_drain, 3),
                "total_s": round(t_total, 3),
                "throughput_req_per_s": round(load_requests / t_load, 1),
                "submissions_per_s": round(st.submissions / t_load, 1),
                "latency_ms": {
                    "submissions": {"p50": percentile_ms(all_submits, 0.5), "p99": percentile_ms(all_submits, 0.99)},
                    "polls": {"p50": lat.get("poll", {}).get("p50_ms"), "p99": lat.get("poll", {}).get("p99_ms")},
                    "by_category": lat,
                },
                "rss": rss,
                "server_checks": server,
                "load_average_end": [round(x, 2) for x in os.getloadavg()],
                "failed_checks": failed_checks,
                "anomalies": st.anomalies,
                "warnings": st.warnings,
            }
        )
        return summary
    finally:
        if proc is not None:
            stop_server(proc)
        if tmp is not None:
            if args.keep_tmp or failed_checks or summary.get("failed_checks") is None:
                print(f"kept {tmp} (database and server log)", file=sys.stderr)
            else:
                shutil.rmtree(tmp, ignore_errors=True)


def mib(kb: int | None) -> str:
    return f"{kb / 1024:.1f} MiB" if kb else "n/a"


def report(s: dict):
    lat = s["latency_ms"]
    print()
    print(f"mix                 {', '.join(f'{k}: {v}' for k, v in s['mix'].items())}")
    print(f"submissions         {s['submissions']}")
    print(f"accepted            {s['accepted']} ({s['distinct_jobs']} distinct jobs)")
    print(f"cached              {s['cached']}")
    print(f"rejected 4xx        {s['rejected_4xx']}")
    print(f"429s                {s['http_429']} ({s['http_429_without_retry_after']} without Retry-After)")
    d = s["deletes"]
    print(
        f"deletes             {d['sent']} sent, {d['canceled']} canceled, "
        f"{d['already_finished_409']} already finished, {d['resubmitted_after_cancel']} resubmitted after cancel"
    )
    print(f"final status        {', '.join(f'{k}: {v}' for k, v in sorted(s['final_status'].items())) or 'none'}")
    print(f"canceled / failed   {s['canceled']} / {s['failed']}")
    print(f"lost                {s['lost']}")
    print(f"results fetched     {s['results_fetched']}")
    print(f"requests            {s['requests']} ({', '.join(f'{k}: {v}' for k, v in s['requests_by_status'].items())})")
    print(f"time                load {s['load_s']:.1f} s, drain {s['drain_s']:.1f} s, total {s['total_s']:.1f} s")
    print(
        f"throughput          {s['throughput_req_per_s']:.0f} req/s, "
        f"{s['submissions_per_s']:.0f} submissions/s (load phase)"
    )
    for name in ("submissions", "polls"):
        q = lat[name]
        shown = f"p50 {q['p50']} ms, p99 {q['p99']} ms" if q["p50"] is not None else "none"
        print(f"latency {name:12s}{shown}")
    for cat, v in lat["by_category"].items():
        print(
            f"  {cat:18s}{v['n']:7d}  p50 {v['p50_ms']:8.2f} ms  p99 {v['p99_ms']:8.2f} ms  "
            f"max {v['max_ms']:8.2f} ms  ({v['slowest']})"
        )
    r = s["rss"]
    if r:
        print(
            f"server RSS          start {mib(r['first_kb'])}, peak {mib(r['peak_kb'])} (VmHWM {mib(r['vmhwm_kb'])}), "
            f"end {mib(r['last_kb'])}; {r['samples']} samples"
        )
    else:
        print("server RSS          not sampled (give --pid with --url)")
    sc = s["server_checks"]
    if "exit_status" in sc:
        print(
            f"server              exit {sc['exit_status']} {sc['shutdown_s']:.2f} s after SIGTERM; "
            f"log: {sc['log_warn']} WARN, {sc['log_error']} ERROR lines"
        )
    if sc.get("db_bytes") is not None:
        wal = (sc.get("db_wal_bytes") or 0) / 2**20
        print(f"database            {sc['db_bytes'] / 2**20:.1f} MiB, WAL {wal:.1f} MiB (before SIGTERM)")
    print(f"load average (end)  {' '.join(map(str, s['load_average_end']))}")
    for w in s["warnings"][:MAX_SHOWN_ANOMALIES]:
        print("WARNING", json.dumps(w, ensure_ascii=False))
    for a in s["anomalies"][:MAX_SHOWN_ANOMALIES]:
        print("ANOMALY", json.dumps(a, ensure_ascii=False))
    if len(s["anomalies"]) > MAX_SHOWN_ANOMALIES:
        print(f"… and {len(s['anomalies']) - MAX_SHOWN_ANOMALIES} more anomalies (all in --json-out)")
    for c in s["failed_checks"]:
        print("FAILED:", c)
    print("PASS" if not s["failed_checks"] else "FAIL")


def main():
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--binary", default="target/release/topple", help="topple binary to start (default %(default)s)")
    ap.add_argument("--url", help="attach to this running server instead of starting one")
    ap.add_argument("--pid", type=int, help="with --url: the server's process id, for the memory samples")
    ap.add_argument("--workers", type=int, help="--workers of the started server (default: its own default)")
    ap.add_argument("--jobs", type=int, default=10_000, help="submissions (default %(default)s)")
    ap.add_argument("--clients", type=int, default=64, help="concurrent clients (default %(default)s)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the workload (default %(default)s)")
    ap.add_argument(
        "--drain-timeout", type=float, default=600, help="s to wait for every job to finish (default %(default)s)"
    )
    ap.add_argument(
        "--request-timeout", type=float, default=60, help="s per request, beyond its ?wait= (default %(default)s)"
    )
    ap.add_argument(
        "--wait-slack", type=float, default=2, help="s a ?wait=N answer may take beyond N (default %(default)s)"
    )
    ap.add_argument(
        "--retry-limit", type=float, default=300, help="s to keep retrying after 429s (default %(default)s)"
    )
    ap.add_argument("--json-out", help="also write the summary to this file")
    ap.add_argument("--keep-tmp", action="store_true", help="keep the temporary directory (database, server log)")
    args = ap.parse_args()
    if args.jobs < 1 or args.clients < 1:
        ap.error("--jobs and --clients must be positive")
    summary = asyncio.run(run(args))
    report(summary)
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump(summary, f, indent=2, ensure_ascii=False)
    sys.exit(1 if summary["failed_checks"] else 0)


if __name__ == "__main__":
    main()
