#!/usr/bin/env bash
# Load benchmark of the topple HTTP service (see bench/README.md).
#
#   bash bench/load.sh
#
# Builds the release binary, starts `topple serve` on a free 127.0.0.1 port
# with a fresh SQLite database in a temporary directory and 2 workers, then:
#   (a) with wrk, 64 connections, side by side in rounds: GET /healthz, and of
#       one finished job its status, its result (JSON) and its result as CSV;
#   (b) POST /v1/jobs?wait=10 of distinct time-history jobs, sequentially
#       (and with 4 concurrent clients): client latency against the compute
#       time the result reports;
#   (c) SIGTERM, and the server must exit 0 within a few seconds.
#
# Environment (all optional):
#   WRK_SECONDS=10 WRK_CONNECTIONS=64 WRK_THREADS=2 READ_ROUNDS=3
#   LATENCY_N=2000 CONCURRENT_N=2000 CONCURRENCY=4 (CONCURRENT_N=0 skips it)
#   WORKERS=2 SHUTDOWN_LIMIT=5
#   TOPPLE_BIN=path: benchmark this binary instead of building target/release/topple
# Every request goes to 127.0.0.1; every loop is bounded in count and time.
set -euo pipefail
cd "$(dirname "$0")/.."

WRK_SECONDS=${WRK_SECONDS:-10}
WRK_CONNECTIONS=${WRK_CONNECTIONS:-64}
WRK_THREADS=${WRK_THREADS:-2}
READ_ROUNDS=${READ_ROUNDS:-3}
LATENCY_N=${LATENCY_N:-2000}
CONCURRENT_N=${CONCURRENT_N:-2000}
CONCURRENCY=${CONCURRENCY:-4}
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
  echo "== binary: $TOPPLE_BIN (TOPPLE_BIN; not building)"
else
  echo "== building: cargo build --release"
  cargo build --release --quiet
fi

WORK=$(mktemp -d "${TMPDIR:-/tmp}/topple-load.XXXXXX")
# The binary is copied so that a concurrent rebuild of target/ changes nothing here.
cp "${TOPPLE_BIN:-target/release/topple}" "$WORK/topple"
PORT=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
CLIENT=(python3 bench/post_wait_latency.py --port "$PORT")
SERVER_PID=

# shellcheck disable=SC2329  # invoked by the EXIT trap
cleanup() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -KILL "$SERVER_PID" 2>/dev/null || true
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

# ---------------------------------------------------------------- (b)
echo
echo "== (b) POST /v1/jobs?wait=10, distinct jobs (no cache hits)"
"${CLIENT[@]}" latency --n "$LATENCY_N" --concurrency 1 --base 3.0 --max-seconds 180 || status=1
if [ "$CONCURRENT_N" -gt 0 ]; then
  echo
  "${CLIENT[@]}" latency --n "$CONCURRENT_N" --concurrency "$CONCURRENCY" --base 3.01 \
    --max-seconds 180 || status=1
fi

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
