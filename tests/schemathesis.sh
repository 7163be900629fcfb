#!/usr/bin/env bash
# Property-based tests of the HTTP API with schemathesis.
#
# Every operation of the committed openapi.yaml is exercised against a fresh
# `topple serve` (SQLite in a temporary directory) with all of schemathesis's
# checks: no server errors; status codes, content types, headers and bodies of
# the responses as documented; schema-valid requests accepted and
# schema-violating ones (negative data) rejected; unsupported methods answered
# 405; stateful sequences through the links between operations. The hooks of
# tests/schemathesis_hooks.py put strings of a megabyte, arrays of 10^7
# numbers and JSON nested 10,000 deep into a share of the job specs and record
# files sent, and check their refusals (4xx problem+json of at most 2,000
# bytes naming what is wrong). Records uploaded before the run (the files of
# specs/records/) give the record operations ids that exist.
#
# Usage:
#   tests/schemathesis.sh [extra `schemathesis run` options...]
#
# Environment:
#   TOPPLE_BIN                    binary under test; when unset, `cargo build
#                                 --release` builds target/release/topple
#   SCHEMATHESIS_MAX_EXAMPLES     test cases per operation and phase (default 100)
#   SCHEMATHESIS_SEED             random seed (default 1, so that runs repeat;
#                                 "random" for a new one each run)
#   SCHEMATHESIS_REQUEST_TIMEOUT  seconds one request may take (default 30: the debug build draws the figure of a long record in over 10 s)
#   SCHEMATHESIS_TIME_LIMIT       seconds the whole schemathesis run may take
#                                 (default 900; exit status 124 past it)
#   SCHEMATHESIS_CONFIG           a schemathesis.toml to apply (default:
#                                 tests/schemathesis.toml; `none` for none)
#   SCHEMATHESIS_HOOKS            a hooks module (default:
#                                 tests/schemathesis_hooks.py; `none` for none)
#   TOPPLE_MUTATE_EVERY           the hooks change one job spec or record file
#                                 in this many (default 4; 0 for none)
#   SCHEMATHESIS_REPORT_DIR       where junit.xml, events.ndjson (every request and
#                                 response) and server.log go (default
#                                 target/schemathesis-report)
#   PYTHON                        interpreter for the venv, >= 3.11 (default
#                                 python3.11, else python3)
#
# The venv is target/schemathesis-venv, with exactly the versions of
# tests/requirements-schemathesis.txt; it is reused while that file is
# unchanged. The server runs with --max-wait 1, so POST /v1/jobs?wait= answers
# within about a second.
#
# Exit status: 0 when schemathesis finds nothing and the server logged no
# panic; non-zero otherwise.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

max_examples=${SCHEMATHESIS_MAX_EXAMPLES:-100}
seed=${SCHEMATHESIS_SEED:-1}
request_timeout=${SCHEMATHESIS_REQUEST_TIMEOUT:-30}
time_limit=${SCHEMATHESIS_TIME_LIMIT:-900}
report_dir=${SCHEMATHESIS_REPORT_DIR:-$root/target/schemathesis-report}
venv=$root/target/schemathesis-venv
requirements=$root/tests/requirements-schemathesis.txt
spec=$root/openapi.yaml

log() { echo "schemathesis.sh: $*" >&2; }
die() { log "$*"; exit 2; }

# --- Python and the venv ---------------------------------------------------
python=${PYTHON:-}
if [[ -z $python ]]; then
  if command -v python3.11 >/dev/null 2>&1; then python=python3.11; else python=python3; fi
fi
command -v "$python" >/dev/null 2>&1 || die "no Python interpreter ($python); set PYTHON"
"$python" -c 'import sys; sys.exit(sys.version_info < (3, 11))' ||
  die "$python is older than 3.11, which schemathesis needs; set PYTHON"

want=$("$python" -c 'import hashlib, sys; print(hashlib.sha256(open(sys.argv[1], "rb").read()).hexdigest())' "$requirements")
stamp=$venv/.requirements.sha256
if [[ ! -x $venv/bin/schemathesis || "$(cat "$stamp" 2>/dev/null)" != "$want" ]] ||
  ! "$venv/bin/python" -c '' 2>/dev/null; then
  log "installing schemathesis into ${venv#"$root"/}"
  if ! "$venv/bin/python" -c '' 2>/dev/null; then
    "$python" -m venv --clear "$venv"
  fi
  "$venv/bin/python" -m pip install --disable-pip-version-check --no-input -q -r "$requirements"
  echo "$want" >"$stamp"
fi
py=$venv/bin/python

# --- The binary ------------------------------------------------------------
if [[ -n ${TOPPLE_BIN:-} ]]; then
  bin=$TOPPLE_BIN
else
  cargo build --release --bin topple
  bin=$root/target/release/topple
fi
[[ -x $bin ]] || die "not an executable: $bin"

# --- The server ------------------------------------------------------------
work=$(mktemp -d "${TMPDIR:-/tmp}/topple-schemathesis.XXXXXX")
server_pid=
schemathesis_pid=
server_log=$work/server.log

stop_server() {
  [[ -n $server_pid ]] || return 0
  if kill -0 "$server_pid" 2>/dev/null; then
    kill -TERM "$server_pid" 2>/dev/null || true
    for _ in $(seq 1 50); do
      kill -0 "$server_pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -KILL "$server_pid" 2>/dev/null || true
  fi
  wait "$server_pid" 2>/dev/null || true
  server_pid=
}

cleanup() {
  local rc=$?
  if [[ -n $schemathesis_pid ]]; then
    kill -TERM "$schemathesis_pid" 2>/dev/null || true
    wait "$schemathesis_pid" 2>/dev/null || true
  fi
  stop_server
  rm -rf "$work"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

free_port() {
  "$py" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# 0 when GET $1 answers 200.
probe() {
  "$py" -c 'import sys, urllib.request; sys.exit(urllib.request.urlopen(sys.argv[1], timeout=2).status != 200)' "$1" 2>/dev/null
}

base=
for attempt in 1 2 3; do
  port=$(free_port)
  "$bin" serve \
    --addr "127.0.0.1:$port" \
    --database "sqlite://$work/topple.db" \
    --max-wait 1 \
    --shutdown-grace 1 \
    >"$server_log" 2>&1 &
  server_pid=$!
  for _ in $(seq 1 300); do
    kill -0 "$server_pid" 2>/dev/null || break
    if probe "http://127.0.0.1:$port/readyz"; then
      base=http://127.0.0.1:$port
      break
    fi
    sleep 0.2
  done
  [[ -n $base ]] && break
  stop_server
  # Another process may have taken the port between choosing and binding it.
  grep -qi 'address already in use' "$server_log" || break
  log "port $port was taken; attempt $((attempt + 1))"
done
if [[ -z $base ]]; then
  tail -n 50 "$server_log" >&2 || true
  die "the server did not become ready"
fi
log "server $bin at $base"

if ! "$py" - "$base/openapi.yaml" "$spec" <<'EOF'; then
import sys, urllib.request
served = urllib.request.urlopen(sys.argv[1], timeout=5).read()
sys.exit(served != open(sys.argv[2], "rb").read())
EOF
  log "note: the server's /openapi.yaml differs from openapi.yaml (the committed one is tested)"
fi

# Records that exist: the record operations are tested on ids of records as
# well as on ids of none.
"$py" - "$base" "$root"/specs/records/*.at2 <<'EOF' || die "the records of specs/records/ were not stored"
import sys, urllib.request
base = sys.argv[1]
files = [open(path, "rb").read() for path in sys.argv[2:]]
# And a short one of its own.
files.append(b"time_s,acc_g\n" + b"".join(b"%.2f,%.4f\n" % (k * 0.01, 0.2 * (-1) ** k * (1 - k / 50))
                                          for k in range(50)))
for body in files:
    request = urllib.request.Request(f"{base}/v1/records", data=body, method="POST",
                                     headers={"Content-Type": "text/plain"})
    with urllib.request.urlopen(request, timeout=30) as response:
        assert response.status in (200, 201), response.status
EOF

# --- schemathesis ----------------------------------------------------------
config=${SCHEMATHESIS_CONFIG:-tests/schemathesis.toml}
if [[ $config == none ]]; then
  # An empty configuration, so that no schemathesis.toml around is picked up.
  config=$work/schemathesis.toml
  : >"$config"
else
  config=$(cd "$(dirname "$config")" && pwd)/$(basename "$config")
fi
seed_args=()
[[ $seed == random ]] || seed_args=(--seed "$seed")
hooks=${SCHEMATHESIS_HOOKS:-$root/tests/schemathesis_hooks.py}
[[ $hooks == none ]] && hooks=
mkdir -p "$report_dir"
report_dir=$(cd "$report_dir" && pwd)

# From the temporary directory, since schemathesis and hypothesis keep caches
# in the working directory; in the background, so that a signal to this script
# ends the run at once (see cleanup).
rc=0
(
  cd "$work"
  exec env NO_COLOR=1 SCHEMATHESIS_HOOKS="$hooks" timeout -k 10 "$time_limit" "$venv/bin/schemathesis" --no-color \
    --config-file "$config" \
    run "$spec" \
    --url "$base" \
    --checks all \
    --mode all \
    --phases examples,coverage,fuzzing,stateful \
    --max-examples "$max_examples" \
    "${seed_args[@]}" \
    --request-timeout "$request_timeout" \
    --continue-on-failure \
    --generation-database none \
    --report junit,ndjson \
    --report-junit-path "$report_dir/junit.xml" \
    --report-ndjson-path "$report_dir/events.ndjson" \
    "$@"
) &
schemathesis_pid=$!
wait "$schemathesis_pid" || rc=$?
schemathesis_pid=
[[ $rc -eq 124 ]] && log "schemathesis exceeded SCHEMATHESIS_TIME_LIMIT=${time_limit}s"

# --- The request schema and the server on the catalogue of bad inputs -----
if kill -0 "$server_pid" 2>/dev/null; then
  log "request schema and server against the catalogue of bad inputs"
  "$py" "$root/tests/contract/request_agreement.py" "$base" || rc=1
fi

# --- The server's side -----------------------------------------------------
if ! kill -0 "$server_pid" 2>/dev/null; then
  log "the server exited during the run"
  [[ $rc -ne 0 ]] || rc=1
fi
stop_server
cp "$server_log" "$report_dir/server.log"
if grep -q 'panicked at' "$server_log"; then
  log "the server panicked (full log: $report_dir/server.log):"
  awk '/panicked at/ { at = $0; sub(/.*panicked at /, "", at); getline message; print at " " message }' \
    "$server_log" | sort | uniq -c | sort -rn | head -n 20 >&2
  [[ $rc -ne 0 ]] || rc=1
fi

# --- Result documents against the described schemas ------------------------
# Every kind of result, as computed, is a JobResult of the served description,
# and the schemas refuse wrong types in typed fields.
log "result documents against components/schemas/JobResult"
"$py" "$root/tests/contract/validate_results.py" "$bin" || rc=1
exit "$rc"
