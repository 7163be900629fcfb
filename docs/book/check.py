#!/usr/bin/env python3
"""Checks a built book (docs/book/build.sh runs it on target/book).

- Every link between pages lands: the file exists, and the anchor after `#`
  is an `id` (or `name`) on that page.
- Every image, script and style sheet is a file of the book, and so is every
  `url(...)` of its style sheets (the KaTeX fonts): nothing is fetched from
  another origin. Links a reader follows (`<a href="https://…">`) may leave.
- Every page that shows an equation rendered it (no raw `$$` left, no KaTeX
  error box).

Usage: python3 docs/book/check.py BOOK_DIR
Exit status: 0 when the book passes; 1 with one line per problem otherwise.
"""

import html.parser
import os
import re
import sys
import urllib.parse

EXTERNAL = re.compile(r"^([a-z][a-z0-9+.-]*:|//)", re.I)


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.refs = []  # (tag, attribute, value)
        self.text = []
        self.skip = 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key):
                self.ids.add(a[key])
        for key in ("href", "src"):
            if a.get(key) is not None:
                self.refs.append((tag, key, a[key]))
        if tag in ("script", "style", "code", "pre"):
            self.skip += 1

    def handle_endtag(self, tag):
        if tag in ("script", "style", "code", "pre") and self.skip:
            self.skip -= 1

    def handle_data(self, data):
        if not self.skip:
            self.text.append(data)


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    book = os.path.abspath(sys.argv[1])
    pages, problems = {}, []
    for folder, _, files in os.walk(book):
        for name in files:
            path = os.path.join(folder, name)
            if name.endswith(".html"):
                page = Page()
                page.feed(open(path, encoding="utf-8").read())
                pages[path] = page
            elif name.endswith(".css"):
                css = open(path, encoding="utf-8", errors="replace").read()
                for url in re.findall(r"url\(\s*['\"]?([^'\")]+)", css):
                    if url.startswith("data:"):
                        continue
                    if EXTERNAL.match(url):
                        problems.append(f"{rel(book, path)}: fetches {url}")
                    elif not os.path.exists(os.path.join(folder, url.split("?")[0].split("#")[0])):
                        problems.append(f"{rel(book, path)}: url({url}) is missing")
    links = 0
    for path, page in pages.items():
        here = os.path.dirname(path)
        for tag, key, value in page.refs:
            if tag == "base":
                continue
            if EXTERNAL.match(value):
                if tag == "a" and re.match(r"^(https?|mailto):", value):
                    continue
                problems.append(f"{rel(book, path)}: <{tag} {key}> fetches {value}")
                continue
            target, _, fragment = value.partition("#")
            target = urllib.parse.unquote(target.split("?")[0])
            file = path if target == "" else os.path.normpath(os.path.join(here, target))
            if os.path.isdir(file):
                file = os.path.join(file, "index.html")
            if not os.path.exists(file):
                problems.append(f"{rel(book, path)}: <{tag} {key}={value}> has no target")
                continue
            links += 1
            if fragment and file.endswith(".html"):
                ids = pages[file].ids if file in pages else set()
                if urllib.parse.unquote(fragment) not in ids:
                    problems.append(f"{rel(book, path)}: {value}: no #{fragment} there")
        text = "".join(page.text)
        if "$$" in text:
            problems.append(f"{rel(book, path)}: an equation left unrendered ($$)")
    for path, page in pages.items():
        if "katex-error" in open(path, encoding="utf-8").read():
            problems.append(f"{rel(book, path)}: KaTeX could not render an equation")
    for p in problems:
        print(p)
    print(f"check: {len(pages)} pages, {links} links checked, {len(problems)} problems", file=sys.stderr)
    return 1 if problems else 0


def rel(book, path):
    return os.path.relpath(path, book)


if __name__ == "__main__":
    sys.exit(main())
