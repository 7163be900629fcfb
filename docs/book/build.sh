#!/usr/bin/env bash
# Builds the book (docs/book) into target/book and checks it: any warning of
# mdbook or its KaTeX preprocessor fails the build, every link between pages
# and to an anchor must land, and nothing may be fetched from another origin
# (docs/book/check.py).
#
# Installs what it needs under target/tools when missing, from the ordinary
# registries: mdbook and mdbook-katex with `cargo install --locked` (crates.io),
# KaTeX's style sheet and fonts with `npm pack` (the npm registry; the same
# KaTeX version mdbook-katex renders with), served with the book.
#
# Usage: bash docs/book/build.sh      (from anywhere; run by .ci/run)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"

MDBOOK_VERSION=0.5.4
MDBOOK_KATEX_VERSION=0.10.0
KATEX_VERSION=0.16.4 # what mdbook-katex 0.10.0 embeds (katex crate 0.4.6)

tools=$root/target/tools
export PATH=$tools/bin:$PATH
log() { echo "book: $*" >&2; }

installed() { "$1" --version 2>/dev/null | grep -q "$2"; }
if ! installed mdbook "v$MDBOOK_VERSION"; then
  log "installing mdbook $MDBOOK_VERSION under target/tools"
  cargo install mdbook --locked --version "$MDBOOK_VERSION" --root "$tools" --quiet
fi
if ! installed mdbook-katex "$MDBOOK_KATEX_VERSION"; then
  log "installing mdbook-katex $MDBOOK_KATEX_VERSION under target/tools"
  cargo install mdbook-katex --locked --version "$MDBOOK_KATEX_VERSION" --root "$tools" --quiet
fi

katex=$tools/katex-$KATEX_VERSION
if [ ! -f "$katex/package/dist/katex.min.css" ]; then
  if ! command -v npm >/dev/null 2>&1; then
    [ "$(id -u)" -eq 0 ] || { log "npm is needed (KaTeX's fonts come from the npm registry)"; exit 2; }
    log "installing npm from the distribution's packages"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq npm >/dev/null
  fi
  log "fetching KaTeX $KATEX_VERSION's style sheet and fonts (npm registry)"
  mkdir -p "$katex"
  (cd "$katex" && npm pack "katex@$KATEX_VERSION" --silent >/dev/null && tar xzf "katex-$KATEX_VERSION.tgz")
fi
dest=docs/book/src/katex
rm -rf "$dest"
mkdir -p "$dest/fonts"
cp "$katex/package/dist/katex.min.css" "$katex/package/LICENSE" "$dest/"
cp "$katex/package/dist/fonts/"*.woff2 "$katex/package/dist/fonts/"*.woff "$katex/package/dist/fonts/"*.ttf "$dest/fonts/"

out=$(mktemp)
trap 'rm -f "$out"' EXIT
if ! mdbook build docs/book >"$out" 2>&1; then
  cat "$out" >&2
  log "mdbook failed"
  exit 1
fi
if grep -E ' (WARN|ERROR) |warning|error' "$out" >&2; then
  log "mdbook warned (warnings are errors here)"
  exit 1
fi
python3 docs/book/check.py target/book
log "built target/book/index.html"
