#!/usr/bin/env bash
# A TypeScript client's types generated from openapi.yaml (openapi-typescript),
# and reads.ts type-checked against them with tsc --strict --noEmit; so are
# the web page's modules, JavaScript with JSDoc types (src/api/page/tsconfig.json:
# checkJs, strict).
# Then `redocly lint` (recommended rules) of openapi.yaml: zero errors.
# Installs the pinned tools under target/clients-node (npm registry).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=$root/target/clients-node
mkdir -p "$work"
cp "$root/tests/clients/package.json" "$work/package.json"
if ! cmp -s "$root/tests/clients/package.json" "$work/.installed" 2>/dev/null; then
  (cd "$work" && npm install --no-audit --no-fund --loglevel=error >/dev/null)
  cp "$root/tests/clients/package.json" "$work/.installed"
fi
"$work/node_modules/.bin/openapi-typescript" "$root/openapi.yaml" -o "$work/api.d.ts" >/dev/null
cp "$root/tests/clients/reads.ts" "$work/reads.ts"
"$work/node_modules/.bin/tsc" --strict --noEmit --target es2022 --module es2022 \
  --moduleResolution bundler --skipLibCheck "$work/reads.ts"
echo "typescript.sh: the generated types check (tsc --strict)"
# The page's modules (src/api/page/*.js) against the same types: its
# tsconfig.json maps "topple-api" to target/clients-node/api.d.ts.
"$work/node_modules/.bin/tsc" -p "$root/src/api/page/tsconfig.json"
echo "typescript.sh: the page's modules check (tsc --checkJs --strict)"
# The description itself: redocly's recommended rules, no errors allowed.
REDOCLY_TELEMETRY=off REDOCLY_SUPPRESS_UPDATE_NOTICE=true "$work/node_modules/.bin/redocly" lint --format=summary "$root/openapi.yaml"
