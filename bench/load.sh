#!/usr/bin/env bash
# Load benchmark of the topple HTTP service (see bench/README.md).
#
#   bash bench/load.sh
#
# Builds the release binary and the load client (examples/load.rs), starts
# `topple serve` on a free 127.0.0.1 port with a fresh SQLite database in a
# temporary directory and 2 workers, then:
#   (a) with wrk, 64 connections, side by side in rounds: GET /healthz, and of
#       one finished job its status, its result (JSON) and its result as CSV;
#   (b) POST /v1/jobs?wait=10 of distinct small time-history jobs, from 1, 4
#       and 16 clients, on SQLite and on PostgreSQL (a private database on
#       127.0.0.1:5432, made and dropped here): the service overhead (client
#       latency minus the compute time the result reports) p50/p99, distinct
#       jobs/s and the server's CPU time per job, for this binary and for the
#       one built from the revision OLD_REV, side by side in alternating
#       rounds (a fresh server and database for each); medians over the
#       rounds and their ratios;
#   (c) SIGTERM, and the server must exit 0 within a few seconds.
#
# Environment (all optional):
#   WRK_SECONDS=10 WRK_CONNECTIONS=64 WRK_THREADS=2 READ_ROUNDS=3 (0 skips (a))
#   ROUNDS=3 SEQ_N=1000 CONC_N=3000 CLIENTS="1 4 16" STORES="sqlite postgres"
#   OLD_REV=e23c234 OLD_BIN=path (else built in a worktree of OLD_REV under
#     OLD_DIR=../topple-OLD_REV with its own target; OLD_BIN=none skips it)
#   PG_URL=postgres://postgres@127.0.0.1:5432 (the server; a database is made on it)
#   PY_LATENCY_N=0: also the Python client's sequential latency (bench/post_wait_latency.py)
#   WORKERS=2 SHUTDOWN_LIMIT=5
#   TOPPLE_BIN=path: benchmark this binary instead of building target/release/topple
# Every request goes to 127.0.0.1; every loop is bounded in count and time.
set -euo pipefail
cd "$(dirname "$0")/.."

WRK_SECONDS=${WRK_SECONDS:-10}
WRK_CONNECTIONS=${WRK_CONNECTIONS:-64}
WRK_THREADS=${WRK_THREADS:-2}
READ_ROUNDS=${READ_ROUNDS:-3}
ROUNDS=${ROUNDS:-3}
SEQ_N=${SEQ_N:-1000}
CONC_N=${CONC_N:-3000}
CLIENTS=${CLIENTS:-"1 4 16"}
STORES=${STORES:-"sqlite postgres"}
OLD_REV=${OLD_REV:-e23c234}
PG_URL=${PG_URL:-postgres://postgres@127.0.0.1:5432}
PY_LATENCY_N=${PY_LATENCY_N:-0}
WORKERS=${WORKERS:-2}
SHUTDOWN_LIMIT=${SHUTDOWN_LIMIT:-5}

loadavg() { cut -d' ' -f1-3 /proc/loadavg; }
started=$(date +%s)
status=0
echo "== topple load benchmark: $(nproc) cores; load average at start: $(loadavg)" \
  "(other work on the machine skews timings)"

if ! command -v wrk >/dev/null 2>&1; then
  echo "wrk not found: installing it (Debian package)"
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y wrk >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y wrk >/dev/null; }
  else
    sudo apt-get install -y wrk >/dev/null
  fi
fi

if [ -n "${TOPPLE_BIN:-}" ]; then
  echo "== binary: $TOPPLE_BIN (TOPPLE_BIN; not building it)"
  cargo build --release --quiet --example load
else
  echo "== building: cargo build --release (and the load client, examples/load.rs)"
  cargo build --release --quiet --bin topple --example load
fi
if [ -z "${OLD_BIN:-}" ]; then
  OLD_DIR=${OLD_DIR:-"$(pwd)/../topple-$OLD_REV"}
  if [ ! -d "$OLD_DIR" ]; then
    echo "== $OLD_REV: git worktree add --detach $OLD_DIR $OLD_REV"
    git worktree add --detach "$OLD_DIR" "$OLD_REV" >/dev/null
  fi
  echo "== building $OLD_REV in $OLD_DIR (its own target)"
  (cd "$OLD_DIR" && cargo build --release --quiet --bin topple)
  OLD_BIN="$OLD_DIR/target/release/topple"
fi

WORK=$(mktemp -d "${TMPDIR:-/tmp}/topple-load.XXXXXX")
# The binaries are copied so that a concurrent rebuild of target/ changes nothing here.
cp "${TOPPLE_BIN:-target/release/topple}" "$WORK/topple"
cp target/release/examples/load "$WORK/load"
[ "$OLD_BIN" = none ] || cp "$OLD_BIN" "$WORK/topple-old"
PORT=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
CLIENT=(python3 bench/post_wait_latency.py --port "$PORT")
SERVER_PID=

PG_DB=
# shellcheck disable=SC2329  # invoked by the EXIT trap
cleanup() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -KILL "$SERVER_PID" 2>/dev/null || true
  fi
  if [ -n "$PG_DB" ]; then
    psql "$PG_URL/postgres" -qc "DROP DATABASE IF EXISTS $PG_DB" >/dev/null 2>&1 || true
  fi
  rm -rf "$WORK"
}
trap cleanup EXIT

echo "== serving on 127.0.0.1:$PORT, database sqlite://$WORK/x.db, $WORKERS workers (log: server.log)"
"$WORK/topple" serve --addr "127.0.0.1:$PORT" --database "sqlite://$WORK/x.db" \
  --workers "$WORKERS" >"$WORK/server.log" 2>&1 &
SERVER_PID=$!
if ! "${CLIENT[@]}" ready --timeout 30; then
  echo "server did not become ready; its log:" >&2
  tail -n 50 "$WORK/server.log" >&2
  exit 1
fi

# ---------------------------------------------------------------- (a)
if [ "$READ_ROUNDS" -gt 0 ]; then
echo
echo "== (a) reads of one finished job beside GET /healthz: wrk -t$WRK_THREADS -c$WRK_CONNECTIONS" \
  "-d${WRK_SECONDS}s each, $READ_ROUNDS rounds in turn"
JOB_ID=$("${CLIENT[@]}" submit --a-alpha-g 4)
BASE="http://127.0.0.1:$PORT"
# name and path of each read, in the order of each round
READS=(
  "healthz /healthz"
  "status /v1/jobs/$JOB_ID"
  "result /v1/jobs/$JOB_ID/result"
  "csv /v1/jobs/$JOB_ID/result?format=csv"
)
for entry in "${READS[@]}"; do
  read -r name path <<<"$entry"
  code=$(curl -s -o "$WORK/$name.body" -w '%{http_code}' --max-time 5 "$BASE$path" || true)
  echo "job $JOB_ID; GET $path -> HTTP $code, $(wc -c <"$WORK/$name.body") bytes"
  [ "$code" = 200 ] || status=1
done
: >"$WORK/reads.txt"
for round in $(seq 1 "$READ_ROUNDS"); do
  for entry in "${READS[@]}"; do
    read -r name path <<<"$entry"
    wrk -t"$WRK_THREADS" -c"$WRK_CONNECTIONS" -d"${WRK_SECONDS}s" --timeout 5s --latency "$BASE$path" \
      >"$WORK/wrk-$name-$round.txt"
    rps=$(awk '/^Requests\/sec:/ {print $2}' "$WORK/wrk-$name-$round.txt")
    non2xx=$(awk '/Non-2xx or 3xx responses:/ {print $NF}' "$WORK/wrk-$name-$round.txt")
    sockerr=$(grep -E '^ +Socket errors:' "$WORK/wrk-$name-$round.txt" || true)
    p50=$(awk '/^ +50%/ {print $2}' "$WORK/wrk-$name-$round.txt")
    p99=$(awk '/^ +99%/ {print $2}' "$WORK/wrk-$name-$round.txt")
    printf '  round %s %-8s %10s req/s  p50 %-8s p99 %-8s non-2xx %s; %s\n' "$round" "$name" \
      "${rps:-?}" "${p50:-?}" "${p99:-?}" "${non2xx:-0}" "${sockerr:-no socket errors}"
    echo "$name ${rps:-0} ${p99:-?}" >>"$WORK/reads.txt"
    [ -z "$non2xx" ] && [ -z "$sockerr" ] || status=1
  done
done
# The median of the rounds of each read, and its ratio to /healthz's.
awk -v rounds="$READ_ROUNDS" -v average="$(loadavg)" '
  function median(name,   n, i, j, t, v) {
    n = 0
    for (i = 1; i <= count[name]; i++) v[++n] = rate[name, i]
    for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (v[j] < v[i]) { t = v[i]; v[i] = v[j]; v[j] = t }
    return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
  }
  { count[$1]++; rate[$1, count[$1]] = $2; if (!($1 in seen)) { seen[$1] = 1; order[++names] = $1 } }
  END {
    base = median("healthz")
    for (k = 1; k <= names; k++) {
      m = median(order[k])
      printf "RESULT (a) %-8s %9.0f req/s (median of %d rounds), %.2f x /healthz\n", order[k], m, rounds, (base > 0 ? m / base : 0)
    }
    r = (base > 0 ? median("result") / base : 0)
    printf "RESULT (a) result / healthz = %.2f (target >= 0.80: %s) | load average %s\n", r, (r >= 0.8 ? "met" : "MISSED"), average
  }' "$WORK/reads.txt"
fi

# ---------------------------------------------------------------- (b)
echo
echo "== (b) POST /v1/jobs?wait=10, distinct small jobs (no cache hits): clients $CLIENTS;" \
  "$SEQ_N jobs sequentially, $CONC_N concurrently; stores: $STORES; $ROUNDS rounds," \
  "this binary (new) and $OLD_REV (old) in turn, each on a fresh server and database"
if [ "$PY_LATENCY_N" -gt 0 ]; then
  "${CLIENT[@]}" latency --n "$PY_LATENCY_N" --concurrency 1 --base 3.0 --max-seconds 180 || status=1
fi

# Starts binary $1 on store $2 (a fresh database) as B_PID on B_PORT.
start_bench_server() {
  local bin=$1 store=$2 url
  B_PORT=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  if [ "$store" = postgres ]; then
    PG_DB="topple_load_$$"
    psql "$PG_URL/postgres" -qc "DROP DATABASE IF EXISTS $PG_DB" >/dev/null 2>&1
    psql "$PG_URL/postgres" -qc "CREATE DATABASE $PG_DB" >/dev/null
    url="$PG_URL/$PG_DB"
  else
    rm -f "$WORK"/b.db*
    url="sqlite://$WORK/b.db"
  fi
  "$bin" serve --addr "127.0.0.1:$B_PORT" --database "$url" --workers "$WORKERS" \
    >>"$WORK/bench-server.log" 2>&1 &
  B_PID=$!
  python3 bench/post_wait_latency.py --port "$B_PORT" ready --timeout 30 >/dev/null
}

# Stops the benchmark server: SIGTERM, then it must exit 0 in SHUTDOWN_LIMIT s.
stop_bench_server() {
  local rc=0 deadline=$(( $(date +%s) + SHUTDOWN_LIMIT ))
  kill -TERM "$B_PID"
  while kill -0 "$B_PID" 2>/dev/null && [ "$(date +%s)" -le "$deadline" ]; do sleep 0.05; done
  if kill -0 "$B_PID" 2>/dev/null; then
    echo "  the server still ran ${SHUTDOWN_LIMIT} s after SIGTERM: killed" >&2
    kill -KILL "$B_PID" 2>/dev/null || true
    status=1
  fi
  wait "$B_PID" 2>/dev/null || rc=$?
  [ "$rc" = 0 ] || { echo "  the server exited $rc" >&2; status=1; }
  if [ -n "$PG_DB" ]; then
    psql "$PG_URL/postgres" -qc "DROP DATABASE IF EXISTS $PG_DB" >/dev/null 2>&1 || true
    PG_DB=
  fi
}

: >"$WORK/runs.jsonl"
for store in $STORES; do
  if [ "$store" = postgres ] && ! psql "$PG_URL/postgres" -qtAc 'SELECT 1' >/dev/null 2>&1; then
    echo "  PostgreSQL at $PG_URL does not answer: skipping it" >&2
    status=1
    continue
  fi
  for round in $(seq 1 "$ROUNDS"); do
    # Alternating order: old first in odd rounds, new first in even ones.
    if [ "$OLD_BIN" = none ]; then order="new"
    elif [ $((round % 2)) = 1 ]; then order="old new"
    else order="new old"; fi
    for which in $order; do
      bin="$WORK/topple"; [ "$which" = old ] && bin="$WORK/topple-old"
      start_bench_server "$bin" "$store"
      for c in $CLIENTS; do
        n=$CONC_N; [ "$c" = 1 ] && n=$SEQ_N
        out=$("$WORK/load" --port "$B_PORT" --n "$n" --concurrency "$c" --base "$((3 + c)).0" \
          --server-pid "$B_PID" --label "$store round $round $which") || status=1
        grep -v '^RESULT ' <<<"$out" | sed 's/^/  /'
        line=$(grep '^RESULT ' <<<"$out") || continue
        python3 -c 'import json, sys; d = json.loads(sys.argv[1]); d.update(store=sys.argv[2], round=int(sys.argv[3]), which=sys.argv[4], load=sys.argv[5]); print(json.dumps(d))' \
          "${line#RESULT }" "$store" "$round" "$which" "$(loadavg)" >>"$WORK/runs.jsonl"
      done
      stop_bench_server
    done
  done
done
python3 - "$WORK/runs.jsonl" "$(loadavg)" <<'PY'
import json, statistics, sys
runs = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
def med(rows, key):
    v = [r[key] for r in rows if r.get(key) is not None]
    return statistics.median(v) if v else float("nan")
loads = sorted(float(r["load"].split()[0]) for r in runs)
print(f"RESULT (b) medians over rounds; 1-minute load average during the runs: "
      f"{loads[0] if loads else 0:.2f}..{loads[-1] if loads else 0:.2f}, now {sys.argv[2]}")
print(f"RESULT (b) {'store':8} {'clients':>7} {'version':7} {'overhead p50':>12} {'p99':>8} {'jobs/s':>8} {'CPU/job':>8} {'client CPU/job':>14}")
keys = sorted({(r["store"], r["concurrency"]) for r in runs}, key=lambda k: (k[0] != "sqlite", k[1]))
for store, c in keys:
    cell = {}
    for which in ("old", "new"):
        rows = [r for r in runs if r["store"] == store and r["concurrency"] == c and r["which"] == which]
        if not rows:
            continue
        cell[which] = {k: med(rows, k) for k in ("overhead_p50_ms", "overhead_p99_ms", "jobs_per_s", "server_cpu_ms_per_job", "client_cpu_ms_per_job")}
        m = cell[which]
        print(f"RESULT (b) {store:8} {c:7d} {which:7} {m['overhead_p50_ms']:9.3f} ms {m['overhead_p99_ms']:8.3f} "
              f"{m['jobs_per_s']:8.0f} {m['server_cpu_ms_per_job']:5.3f} ms {m['client_cpu_ms_per_job']:11.3f} ms  ({len(rows)} rounds)")
    if "old" in cell and "new" in cell:
        o, n = cell["old"], cell["new"]
        r = lambda k, inv=False: (n[k] / o[k] if inv else o[k] / n[k]) if o[k] and n[k] else float("nan")
        print(f"RESULT (b) {store:8} {c:7d} old/new: overhead p50 {r('overhead_p50_ms'):.1f}x, p99 {r('overhead_p99_ms'):.1f}x, "
              f"jobs/s {r('jobs_per_s', True):.1f}x, CPU/job {r('server_cpu_ms_per_job'):.1f}x")
for store in sorted({r["store"] for r in runs}):
    for c, key, limit in ((1, "overhead_p50_ms", 1.0), (4, "overhead_p50_ms", 4.0)):
        rows = [r for r in runs if r["store"] == store and r["concurrency"] == c and r["which"] == "new"]
        if rows:
            m = med(rows, key)
            print(f"RESULT (b) target {store} {c} client(s) overhead p50 {m:.3f} ms <= {limit} ms: {'met' if m <= limit else 'MISSED'}")
    rows = [r for r in runs if r["store"] == store and r["which"] == "new"]
    if rows:
        best = max(med([r for r in rows if r["concurrency"] == c], "jobs_per_s") for c in {r["concurrency"] for r in rows})
        print(f"RESULT (b) target {store} distinct jobs/s {best:.0f} >= 1000: {'met' if best >= 1000 else 'MISSED'}")
PY

# ---------------------------------------------------------------- (c)
echo
echo "== (c) SIGTERM: the server must exit 0 within ${SHUTDOWN_LIMIT} s"
t0=$(date +%s.%N)
kill -TERM "$SERVER_PID"
deadline=$(( $(date +%s) + SHUTDOWN_LIMIT ))
while kill -0 "$SERVER_PID" 2>/dev/null && [ "$(date +%s)" -le "$deadline" ]; do
  sleep 0.05
done
if kill -0 "$SERVER_PID" 2>/dev/null; then
  echo "RESULT (c): still running ${SHUTDOWN_LIMIT} s after SIGTERM: killing it" >&2
  kill -KILL "$SERVER_PID" 2>/dev/null || true
  wait "$SERVER_PID" 2>/dev/null || true
  status=1
else
  rc=0
  wait "$SERVER_PID" || rc=$?
  t1=$(date +%s.%N)
  echo "RESULT (c): exit status $rc after $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }') s"
  [ "$rc" = 0 ] || status=1
fi
SERVER_PID=

# ---------------------------------------------------------------- log
warn=$(grep -c -E ' (WARN|ERROR) ' "$WORK/server.log" || true)
echo
echo "== server log: $(wc -l <"$WORK/server.log") lines, $warn WARN/ERROR"
grep -E ' (WARN|ERROR) ' "$WORK/server.log" | head -n 10 || true
tail -n 3 "$WORK/server.log"
[ "$warn" = 0 ] || status=1

echo
echo "== done in $(( $(date +%s) - started )) s; load average at end: $(loadavg); exit $status"
exit "$status"
