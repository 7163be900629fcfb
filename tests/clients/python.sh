#!/usr/bin/env bash
# A Python client generated from openapi.yaml by openapi-python-client (no
# warnings), use_client.py type-checked with mypy --strict against it, then run
# against a live `topple serve`. Tools pinned in requirements.txt, installed in
# target/clients-venv (Python registry).
#
#   TOPPLE_BIN=target/debug/topple tests/clients/python.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${TOPPLE_BIN:-$root/target/debug/topple}
work=$root/target/clients-python
venv=$root/target/clients-venv
req=$root/tests/clients/requirements.txt
if ! cmp -s "$req" "$venv/.installed" 2>/dev/null; then
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$req"
  cp "$req" "$venv/.installed"
fi
rm -rf "$work"
mkdir -p "$work"
out=$(PATH="$venv/bin:$PATH" "$venv/bin/openapi-python-client" generate \
  --path "$root/openapi.yaml" --config "$root/tests/clients/python-client.yaml" \
  --meta none --output-path "$work/topple_client" 2>&1)
if grep -qi "warning" <<<"$out"; then
  echo "$out" >&2
  echo "python.sh: openapi-python-client warned" >&2
  exit 1
fi
cp "$root/tests/clients/use_client.py" "$work/"
cp "$root/tests/clients/mypy.ini" "$work/"
(cd "$work" && "$venv/bin/mypy" --config-file mypy.ini --strict use_client.py)

port=$("$venv/bin/python" -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
db=$(mktemp -d)
"$bin" serve --addr "127.0.0.1:$port" --database "sqlite://$db/topple.db" >"$db/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null; wait $server 2>/dev/null; rm -rf "$db"' EXIT
for _ in $(seq 1 100); do
  "$venv/bin/python" -c "import urllib.request,sys; urllib.request.urlopen('http://127.0.0.1:$port/readyz', timeout=1)" 2>/dev/null && break
  sleep 0.1
done
(cd "$work" && "$venv/bin/python" use_client.py "http://127.0.0.1:$port" "$root/specs")
echo "python.sh: the generated client drove every kind"
