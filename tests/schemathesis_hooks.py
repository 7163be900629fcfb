"""Schemathesis hooks of tests/schemathesis.sh: oversized and deeply nested
input in the traffic generated for POST /v1/jobs and POST /v1/records.

One job spec in MUTATE_EVERY, and one record file in a quarter as many (the
requests chosen by a hash of each, so that a run with a fixed seed sends the
same requests), is changed just before it is sent (`before_call`). A job
spec gets one of:

- a string of a megabyte (10^6 characters) in place of one of its strings
  (or of the whole body when it holds none);
- an unknown key of a megabyte in one of its objects;
- an array of 10^6 numbers (3 MB, beyond the 1 MiB body limit) or of 10^5
  (within it) in place of one of its arrays or numbers;
- one of its values wrapped in JSON_DEPTH levels of arrays, or of objects
  (beyond the 128 levels the service's parser reads; schemathesis hashes
  bodies of at most 255 levels, so 10,000 levels of a job spec are left to
  tests/api/bad_input.rs);
- a query value of 10,000 characters.

A record file, sent with `unit` and `dt` so that the file itself is judged,
gets one of: a megabyte of letters; a megabyte on one line; a header line of
a megabyte above a few samples; 10^6 + 1 samples one per line (one more than
the most a record holds, within max_record_bytes); JSON whose `acc` is nested
10,000 deep; JSON with a key of a megabyte; or else a query value of 10,000
characters.

Schemathesis keeps every request body in its report (events.ndjson): each
change to a long string or array is made at most HEAVY_PER_KIND times per
operation, the nesting and query changes as often as they come. Ten million
numbers, 20 MB, are left to tests/api/bad_input.rs.

Schemathesis checks a changed request against the schema again, so its
positive and negative checks judge what was sent, and `not_a_server_error`
covers it as any other. The check below adds that a changed request is
answered either 2xx (the change is within the schema and the service's
limits) or by a 4xx `application/problem+json` of at most MAX_PROBLEM_BYTES
naming what is wrong (`pointer`, `parameter`, `header` or `limit`). At the
end of the run, a table of what was sent and how it was answered goes to
standard error.

Environment: TOPPLE_MUTATE_EVERY (default 12) changes one job spec in that
many (and one record file in a quarter as many); 0 changes none.
"""

import atexit
import collections
import copy
import hashlib
import json
import os
import sys
import threading

import schemathesis
from schemathesis.core import NotSet


MUTATE_EVERY = int(os.environ.get("TOPPLE_MUTATE_EVERY", "12"))
MB = 1_000_000
DEPTH = 10_000
JSON_DEPTH = 200
MAX_PROBLEM_BYTES = 2000
# Changes to a long string or array are made this many times per operation
# and kind at most.
HEAVY_PER_KIND = 3

JOBS = ("POST", "/v1/jobs")
RECORDS = ("POST", "/v1/records")

# case id -> (what was done to it, where)
CHANGED: dict[str, tuple[str, str]] = {}
# (operation, what, status) -> count
SEEN: collections.Counter = collections.Counter()
# (operation, kind) -> changes to a long string or array made
HEAVY: collections.Counter = collections.Counter()
LOCK = threading.Lock()


def _operation(case):
    """The method sent and the path of the operation."""
    return (case.method.upper(), case.operation.path)


def _digest(case) -> int:
    text = json.dumps([case.query, case.body], sort_keys=True, default=repr)
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "big")


def _json(body) -> bool:
    """Whether `body` is a JSON value (negative cases may send raw bytes)."""
    try:
        json.dumps(body)
    except (TypeError, ValueError):
        return False
    return True


def _nodes(value, path=()):
    """(path, value) of every node of a JSON value, depth first."""
    yield path, value
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _nodes(item, path + (key,))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from _nodes(item, path + (index,))


def _set(body, path, value):
    """`body` with the node at `path` set to `value`."""
    if not path:
        return value
    node = body
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return body


def _pointer(path) -> str:
    return "".join(f"/{key}" for key in path) or "the body"


def _nest(value, objects: bool):
    for _ in range(JSON_DEPTH):
        value = {"a": value} if objects else [value]
    return value


def _pick(items, digest):
    return items[(digest >> 8) % len(items)] if items else None


def _heavy(operation, kind) -> bool:
    """Whether a change to a long string or array of `kind` may be made again."""
    with LOCK:
        if HEAVY[(operation, kind)] >= HEAVY_PER_KIND:
            return False
        HEAVY[(operation, kind)] += 1
        return True


def _change_spec(case, digest) -> tuple[str, str] | None:
    """Changes the job spec of `case`; says what it did."""
    body = copy.deepcopy(case.body)
    nodes = list(_nodes(body))
    choice = (digest >> 4) % 7
    if choice in (0, 1, 2, 3) and not _heavy(JOBS, choice):
        choice = 4 + (digest >> 20) % 3
    if choice == 0:
        path = _pick([p for p, v in nodes if isinstance(v, str)], digest)
        if path is None:
            case.body = "x" * MB
            return "a string of 10^6 characters", "the body"
        case.body = _set(body, path, "x" * MB)
        return "a string of 10^6 characters", _pointer(path)
    if choice == 1:
        path = _pick([p for p, v in nodes if isinstance(v, dict)], digest)
        if path is None:
            case.body = {"k" * MB: body}
            return "a key of 10^6 characters", "the body"
        node = body
        for key in path:
            node = node[key]
        node["k" * MB] = 1
        case.body = body
        return "a key of 10^6 characters", _pointer(path)
    if choice in (2, 3):
        many = MB if choice == 2 else 100_000
        arrays = [p for p, v in nodes if isinstance(v, list)]
        numbers = [p for p, v in nodes if isinstance(v, (int, float)) and not isinstance(v, bool)]
        path = _pick(arrays or numbers, digest)
        numbers_list = [0, 1] * (many // 2)
        if path is None:
            case.body = numbers_list
            return f"an array of {many} numbers", "the body"
        case.body = _set(body, path, numbers_list)
        return f"an array of {many} numbers", _pointer(path)
    if choice in (4, 5):
        objects = choice == 5
        path = _pick([p for p, _ in nodes], digest)
        node = body
        for key in path:
            node = node[key]
        case.body = _set(body, path, _nest(node, objects))
        kind = "objects" if objects else "arrays"
        return f"nested in {JSON_DEPTH} {kind}", _pointer(path)
    return _change_query(case, digest)


def _change_record(case, digest) -> tuple[str, str] | None:
    """Changes the record file of `case`; says what it did."""
    choice = (digest >> 4) % 7
    if choice in (0, 1, 2, 3, 5) and not _heavy(RECORDS, choice):
        choice = 4 + 2 * ((digest >> 20) % 2)
    if choice < 6:
        case.query = {"unit": "g", "dt": 0.01}
    if choice == 0:
        case.body = "x" * MB
        return "a file of 10^6 letters", "the body"
    if choice == 1:
        case.body = "0.1 " * (MB // 4)
        return "a file of one line of 10^6 characters", "the body"
    if choice == 2:
        case.body = "# " + "h" * MB + "\n0.1\n-0.2\n0.05\n-0.01\n"
        return "a header line of 10^6 characters above four samples", "the body"
    if choice == 3:
        case.body = "0\n1\n" * (MB // 2) + "0\n"
        return "a file of 10^6 + 1 samples, one per line", "the body"
    if choice == 4:
        inner = "[" * DEPTH + "]" * DEPTH if digest & 1 else '{"a":' * DEPTH + "1" + "}" * DEPTH
        case.body = '{"dt": 0.01, "unit": "g", "acc": ' + inner + "}"
        return f"a JSON record nested {DEPTH} deep", "/acc"
    if choice == 5:
        case.body = '{"' + "k" * MB + '": 1, "dt": 0.01, "unit": "g", "acc": [0.1, -0.2]}'
        return "a JSON record with a key of 10^6 characters", "the body"
    return _change_query(case, digest)


def _change_query(case, digest) -> tuple[str, str] | None:
    names = sorted(case.query or {})
    name = _pick(names, digest)
    if name is None:
        return None
    query = dict(case.query)
    query[name] = "q" * 10_000
    case.query = query
    return "a query value of 10^4 characters", f"query parameter {name}"


@schemathesis.hook
def before_call(context, case, kwargs):
    if MUTATE_EVERY <= 0:
        return
    operation = _operation(case)
    if operation not in (JOBS, RECORDS) or case.id in CHANGED:
        return
    digest = _digest(case)
    every = MUTATE_EVERY if operation == JOBS else max(1, MUTATE_EVERY // 4)
    if digest % every:
        return
    if isinstance(case.body, NotSet) or case.body is None:
        change = _change_query(case, digest)
    elif operation == JOBS:
        change = _change_spec(case, digest) if _json(case.body) else _change_query(case, digest)
    elif isinstance(case.body, str):
        change = _change_record(case, digest)
    else:
        change = _change_query(case, digest)
    if change is not None:
        CHANGED[case.id] = change


def _header(response, name):
    value = response.headers.get(name)
    if isinstance(value, list):
        value = value[0] if value else None
    return value or ""


@schemathesis.check
def oversized_input_is_refused_in_a_bounded_problem(ctx, response, case):
    change = CHANGED.get(case.id)
    if change is None:
        return None
    kind, where = change
    what = f"{kind} at {where}"
    status = response.status_code
    with LOCK:
        SEEN[(" ".join(_operation(case)), kind, status)] += 1
    if status >= 500:
        raise AssertionError(f"{what}: answered {status}")
    if status < 400:
        return None
    content_type = _header(response, "content-type")
    body = response.content or b""
    if not content_type.startswith("application/problem+json"):
        raise AssertionError(
            f"{what}: answered {status} as {content_type!r} ({len(body)} bytes), "
            "not as application/problem+json")
    if len(body) > MAX_PROBLEM_BYTES:
        raise AssertionError(
            f"{what}: a problem of {len(body)} bytes, more than {MAX_PROBLEM_BYTES}: "
            f"{body[:300]!r}…")
    problem = json.loads(body)
    if problem.get("status") != status:
        raise AssertionError(f"{what}: answered {status}, the problem says {problem.get('status')}")
    if not any(problem.get(key) is not None for key in ("pointer", "parameter", "header", "limit")):
        raise AssertionError(f"{what}: the problem names nothing at fault: {problem}")
    if status == 413 and problem.get("limit") not in ("max_body_bytes", "max_record_bytes"):
        raise AssertionError(f"{what}: a 413 naming no body limit: {problem}")
    return None


@atexit.register
def _summary():
    if not SEEN:
        return
    print("\nschemathesis_hooks: changed requests and their answers", file=sys.stderr)
    for (label, what, status), count in sorted(SEEN.items()):
        print(f"  {count:4d} × {status}  {label}: {what}", file=sys.stderr)
