#!/usr/bin/env python3
"""The lengths of the Rust functions of the project: how many are over 100
and over 200 lines, and the longest, in src/ and tests/ (and benches/,
examples/).

A function runs from its `fn` line to the line of the brace that closes its
body, braces inside string and character literals and comments skipped.
Closures and nested functions count within the function that holds them
(a nested `fn` is listed too).

    python3 tests/function_lengths.py            # the counts and the longest 15
    python3 tests/function_lengths.py --most 40  # more of the longest
    python3 tests/function_lengths.py --check 200 10
        # exit status 1 if a function is over 200 lines, or more than 10
        # are over 100
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FOLDERS = ["src", "tests", "benches", "examples"]
FN = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:async\s+)?(?:unsafe\s+)?fn\s+(\w+)")


def code_only(text: str) -> str:
    """`text` with comments, strings and char literals blanked (newlines
    kept, so that line numbers hold)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "r" and re.match(r'r#*"', text[i:i + 10]) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'r(#*)"', text[i:])
            close = '"' + m.group(1)
            j = text.find(close, i + len(m.group(0)))
            j = n if j < 0 else j + len(close)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4]) or text.startswith("'\\u{", i):
            j = text.find("'", i + 1)
            j = text.find("'", j + 1) if text[i + 1] == "\\" and text[i + 2] == "'" else j
            out.append(" " * (j + 1 - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path: Path) -> list[tuple[str, int, int]]:
    """(name, first line, length in lines) of every function in `path`."""
    lines = code_only(path.read_text(encoding="utf-8")).split("\n")
    found = []
    for k, line in enumerate(lines):
        m = FN.match(line)
        if not m:
            continue
        depth, opened = 0, False
        for j in range(k, len(lines)):
            for ch in lines[j]:
                if ch == "{":
                    depth, opened = depth + 1, True
                elif ch == "}":
                    depth -= 1
                elif ch == ";" and not opened and depth == 0:
                    break
            else:
                if opened and depth == 0:
                    found.append((m.group(1), k + 1, j - k + 1))
                    break
                continue
            break
    return found


def main() -> int:
    args = sys.argv[1:]
    most = int(args[args.index("--most") + 1]) if "--most" in args else 15
    check = None
    if "--check" in args:
        i = args.index("--check")
        check = (int(args[i + 1]), int(args[i + 2]))
    rows = []
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob("*.rs")):
            for name, line, length in functions(path):
                rows.append((length, f"{path.relative_to(ROOT)}:{line}", name))
    rows.sort(reverse=True)
    over100 = [r for r in rows if r[0] > 100]
    over200 = [r for r in rows if r[0] > 200]
    print(f"{len(rows)} functions; {len(over100)} over 100 lines, {len(over200)} over 200")
    for length, where, name in rows[:most]:
        print(f"  {length:5d}  {name}  {where}")
    if check:
        longest, allowed = check
        if any(r[0] > longest for r in rows) or len(over100) > allowed:
            print(f"over the limits: none over {longest} lines, at most {allowed} over 100")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
