#!/usr/bin/env python3
"""Runs every ```sh example of README.md and of the book against a live
`topple serve`.

The book's chapters are the Markdown files SUMMARY.md lists
(docs/book/src/SUMMARY.md), run in its order after README.md.

Each block runs as one `bash -euo pipefail` script, in a scratch directory
holding a copy of specs/, with `topple` (TOPPLE_BIN) first on the PATH and
`curl` failing on HTTP errors (`--fail-with-body`): a block passes when its
script exits 0. The examples are run as written except for what must differ
on a shared machine, substituted before running:

  127.0.0.1:8080, 127.0.0.1:8081  -> two free ports
  the PostgreSQL database `topple` -> topple_readme_<pid> (dropped at the end)
  /etc/topple/tokens               -> a file in the scratch directory

A block that starts `topple serve` itself runs with no other server up; after
it, every address it serves on must answer /readyz within 30 s, then its
processes are stopped. Any other block gets a server of this script's own on
the first address (SQLite in the scratch directory), started once. Every
block runs in the same scratch directory, in order: a walkthrough's later
steps read the files its earlier ones wrote.

A block preceded by `<!-- example: skip: REASON -->` is listed, not run.

Usage: python3 tests/readme_examples.py   (TOPPLE_BIN, default target/debug/topple)
Exit status: 0 when every block passed; 1 otherwise.
"""

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 480  # seconds one block may take (record spectra in a debug build on a busy machine)


def blocks(readme):
    """(line number, skip reason or None, text) of every ```sh block."""
    lines = open(readme, encoding="utf-8").read().split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```sh":
            start = i + 1
            j = start
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            before = next((l for l in reversed(lines[:i]) if l.strip()), "")
            m = re.match(r"\s*<!--\s*example:\s*skip:\s*(.*?)\s*-->", before)
            out.append((start, m.group(1) if m else None, "\n".join(lines[start:j])))
            i = j
        i += 1
    return out


BOOK = os.path.join(ROOT, "docs", "book", "src")


def sources():
    """README.md, then the book's chapters in the order of its SUMMARY.md."""
    out = [os.path.join(ROOT, "README.md")]
    summary = open(os.path.join(BOOK, "SUMMARY.md"), encoding="utf-8").read()
    for chapter in re.findall(r"\]\(([^)]+\.md)\)", summary):
        path = os.path.normpath(os.path.join(BOOK, chapter))
        if path not in out:
            out.append(path)
    return out


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def ready(port, within=30.0):
    deadline = time.time() + within
    while time.time() < deadline:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/readyz", timeout=2) as r:
                if r.status == 200:
                    return True
        except Exception:
            pass
        time.sleep(0.2)
    return False


def group_alive(pgid):
    try:
        os.killpg(pgid, 0)
        return True
    except (ProcessLookupError, PermissionError):
        return False


def stop(proc):
    """Stops a process group started with start_new_session: SIGTERM, then
    SIGKILL after 15 s; returns once every process of the group is gone (so
    that its ports are free)."""
    pgid = proc.pid
    if group_alive(pgid):
        os.killpg(pgid, signal.SIGTERM)
    deadline = time.time() + 15
    while group_alive(pgid) and time.time() < deadline:
        if proc.poll() is None:
            try:
                proc.wait(timeout=0.1)
            except subprocess.TimeoutExpired:
                pass
        else:
            time.sleep(0.1)
    if group_alive(pgid):
        os.killpg(pgid, signal.SIGKILL)
    proc.wait()


SHOWN = 30  # lines of a block's output shown


def main():
    binary = os.path.abspath(os.environ.get("TOPPLE_BIN", os.path.join(ROOT, "target/debug/topple")))
    if not os.access(binary, os.X_OK):
        print(f"readme_examples: no binary at {binary} (run cargo test or set TOPPLE_BIN)", file=sys.stderr)
        return 2
    for tool in ("curl", "jq"):
        if shutil.which(tool) is None:
            print(f"readme_examples: {tool} is needed (the examples use it)", file=sys.stderr)
            return 2
    work = tempfile.mkdtemp(prefix="topple-readme-")
    shutil.copytree(os.path.join(ROOT, "specs"), os.path.join(work, "specs"))
    bindir = os.path.join(work, ".bin")
    os.mkdir(bindir)
    os.symlink(binary, os.path.join(bindir, "topple"))
    curl = os.path.join(bindir, "curl")
    with open(curl, "w") as f:
        f.write(f'#!/bin/sh\nexec {shutil.which("curl")} --fail-with-body "$@"\n')
    os.chmod(curl, 0o755)
    env = dict(os.environ, PATH=bindir + os.pathsep + os.environ["PATH"], RUST_LOG="warn")
    env.pop("DATABASE_URL", None)
    ports = [free_port(), free_port()]
    database = f"topple_readme_{os.getpid()}"
    substitutions = [
        ("127.0.0.1:8080", f"127.0.0.1:{ports[0]}"),
        ("127.0.0.1:8081", f"127.0.0.1:{ports[1]}"),
        ("-U postgres topple", f"-U postgres {database}"),
        ("5432/topple", f"5432/{database}"),
        ("/etc/topple/tokens", "tokens"),
    ]
    server, created_db, failures, ran = None, False, [], 0
    log = open(os.path.join(work, "server.log"), "w")
    try:
        every = [(os.path.relpath(path, ROOT), line, skip, text)
                 for path in sources() for line, skip, text in blocks(path)]
        for index, (source, number, skip, text) in enumerate(every):
            line = f"{source}:{number}"
            if skip is not None:
                print(f"--- {line}: skipped ({skip})")
                continue
            script = text
            for a, b in substitutions:
                script = script.replace(a, b)
            serves = "topple serve" in script
            if serves and server is not None:
                stop(server)
                server = None
            if not serves and server is None:
                server = subprocess.Popen(
                    [binary, "serve", "--addr", f"127.0.0.1:{ports[0]}",
                     "--database", f"sqlite://{work}/topple.db",
                     # A debug build computes the record spectrum of the records
                     # example in about a minute: let ?wait= hold that long.
                     "--max-wait", "300"],
                    cwd=work, env=env, stdout=log, stderr=log, start_new_session=True)
                if not ready(ports[0]):
                    failures.append((line, "the examples' server did not become ready"))
                    break
            created_db |= "createdb" in script
            print(f"--- {line}")
            started = time.time()
            out_path = os.path.join(work, f".block-{index}.out")
            with open(out_path, "w") as out:
                # A file, not a pipe: what the block leaves running in the
                # background keeps its output open.
                proc = subprocess.Popen(["bash", "-euo", "pipefail", "-c", script], cwd=work, env=env,
                                        stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
                try:
                    proc.wait(timeout=TIMEOUT)
                except subprocess.TimeoutExpired:
                    stop(proc)
                    failures.append((line, f"did not finish within {TIMEOUT} s"))
            output = open(out_path, encoding="utf-8", errors="replace").read()
            lines = output.splitlines()
            for text_line in lines[:SHOWN]:
                print(text_line[:300])
            if len(lines) > SHOWN:
                print(f"… ({len(lines) - SHOWN} more lines)")
            ran += 1
            if proc.returncode != 0:
                failures.append((line, f"exit status {proc.returncode}"))
            elif serves:
                for port in sorted({int(p) for p in re.findall(r"--addr 127\.0\.0\.1:(\d+)", script)}):
                    if not ready(port):
                        failures.append((line, f"nothing ready at 127.0.0.1:{port}"))
            stop(proc)  # what the block left running in the background
            print(f"    ({time.time() - started:.1f} s)")
    finally:
        if server is not None:
            stop(server)
        log.close()
        if created_db:
            subprocess.run(["dropdb", "-h", "127.0.0.1", "-U", "postgres", "--if-exists", "--force", database],
                           check=False)
    if failures:
        for line, why in failures:
            print(f"FAILED: {line}: {why}", file=sys.stderr)
        print(f"server log: {os.path.join(work, 'server.log')}", file=sys.stderr)
        return 1
    shutil.rmtree(work, ignore_errors=True)
    print(f"readme_examples: {ran} blocks ran, all passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
