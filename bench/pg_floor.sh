#!/usr/bin/env bash
# What a small job's statements cost PostgreSQL alone: the floor under the
# service's sequential overhead on PostgreSQL.
#
# A small job computed in its request (src/service/inline.rs) makes one
# statement on PostgreSQL: the store of the finished job, which reads its
# admission first (the tenant's own job and the computation for the key, the
# tenant's live jobs and the queue's length, under the service's default
# limits: no quota, a queue of 10,000; src/store/store_done_postgres.sql),
# committed with a flush of the WAL. This script runs exactly that statement
# with pgbench (prepared, one client over TCP as the service connects, then
# four) on a scratch database that `topple serve` has migrated, with a
# result body of about 10 kB (300 MD5 digests: about what lz4 makes of a
# time history's result) and of 33 bytes, and prints pgbench's latency.
# With SEPARATE=1 the admission also runs as a statement of its own before
# the store (`ADMISSION` in src/store/sql.rs), as the service sent it until
# the store read it: the cost of that extra round trip to the database.
#
# Run: bash bench/pg_floor.sh   (PGHOST/PGUSER as for psql; default
# 127.0.0.1, postgres; TOPPLE_BIN defaults to target/release/topple;
# SECONDS_EACH=8 SEPARATE=0)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${TOPPLE_BIN:-target/release/topple}
export PGHOST=${PGHOST:-127.0.0.1} PGUSER=${PGUSER:-postgres}
DB=topple_pg_floor
EACH=${SECONDS_EACH:-8}
SEPARATE=${SEPARATE:-0}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"; psql -q -c "DROP DATABASE IF EXISTS $DB" >/dev/null 2>&1 || true' EXIT

psql -q -c "DROP DATABASE IF EXISTS $DB" -c "CREATE DATABASE $DB" >/dev/null
# The service's own schema: its migrations, run by a brief `serve`.
PORT=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
RUST_LOG=warn "$BIN" serve --addr "127.0.0.1:$PORT" \
  --database "postgres://$PGUSER@$PGHOST/$DB" >"$WORK/serve.log" 2>&1 &
SERVE=$!
for _ in $(seq 100); do
  curl -fs -o /dev/null "http://127.0.0.1:$PORT/readyz" && break
  sleep 0.1
done
kill "$SERVE"; wait "$SERVE" 2>/dev/null || true

# The statement(s) as the service sends them, with pgbench's variable :n
# for the key (md5 of it) and id.
python3 - "$WORK" "$SEPARATE" <<'EOF'
import re, sys
work, separate = sys.argv[1], sys.argv[2] == "1"
store = open("src/store/store_done_postgres.sql").read()
store = " ".join(l for l in store.split("\n") if not l.strip().startswith("--"))
sql = open("src/store/sql.rs").read()
i = sql.index('pub const ADMISSION: &str = ')
admission = re.findall(r'"((?:[^"\\]|\\.)*)"', sql[i:i + 800], re.S)[0]
admission = " ".join(admission.replace("\\\n", " ").split())
key, tenant = "md5(:n::text)", "'default'"
admission = admission.replace("$2", key).replace("$1", tenant)
def body(digests):
    return f"(SELECT string_agg(md5(:n::text || g::text), ',') FROM generate_series(1, {digests}) g)"
# Longest parameter names first: $1 is a prefix of $10..$15.
values = {"$15": "10000", "$14": "NULL", "$13": "0", "$12": None, "$11": "'w#request'",
          "$10": "'{}'", "$9": tenant, "$8": "now()", "$7": "now()", "$6": "now()",
          "$5": "'{}'", "$4": "'{}'", "$3": "'time_history'", "$2": key, "$1": key}
for name, digests in (("large", 300), ("small", 1)):
    s = store
    for k, v in values.items():
        s = s.replace(k, v if v is not None else body(digests))
    with open(f"{work}/{name}.pgb", "w") as f:
        f.write("\\set n random(1, 2000000000)\n")
        if separate:
            f.write(admission + ";\n")
        f.write(" ".join(s.split()) + ";\n")
EOF

for body in large small; do
  for clients in 1 4; do
    out=$(pgbench -n -r -M prepared -c "$clients" -j "$clients" -T "$EACH" -f "$WORK/$body.pgb" "$DB" 2>&1)
    tps=$(echo "$out" | sed -nE 's/^tps = ([0-9.]+).*/\1/p')
    lat=$(echo "$out" | sed -nE 's/^latency average = ([0-9.]+) ms/\1/p')
    adm=$(echo "$out" | grep -E '^ +[0-9.]+ +[0-9]+ +SELECT \(SELECT' | awk '{print $1}' || true)
    sto=$(echo "$out" | grep -E '^ +[0-9.]+ +[0-9]+ +WITH admission' | awk '{print $1}' || true)
    printf 'body %-5s clients %d: %7.0f jobs/s, %s ms a job (store %s ms, admission apart %s ms)\n' \
      "$body" "$clients" "$tps" "$lat" "$sto" "${adm:--}"
  done
done
