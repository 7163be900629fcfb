#!/usr/bin/env python3
"""End-to-end test of the web page at `/` in headless Chromium.

Starts `topple serve` (SQLite in a temporary directory) and Chromium with the
DevTools protocol, then drives the page as a user would, with real mouse
clicks and typed text:

1. the page is served as HTML under a Content-Security-Policy that allows
   scripts and style sheets from its own origin only, none inline; its
   markup holds no script, style or event handler of its own; its modules
   and style sheet come from /static/ as text/javascript and text/css; an
   inline script or style added to it is blocked (and reported);
2. in a 1400×1000 window (with or without 140 px of toolbars), Submit is in
   sight on first load for every kind, and stays in sight when eight
   observations make the form outgrow the window;
3. an invalid slenderness is refused and the error names the field
   (`/block/alpha`), marks its input invalid and focuses it;
4. the default time history (the locomotive block) is submitted; the status
   reaches "succeeded", the plot image loads (naturalWidth > 0), the CSV link
   points at the job's `result?format=csv` and serves CSV; the block
   overturns, and the page says when (the result's overturn_time) and how
   (mode 1, after one impact), not a peak rotation; the result's warnings
   are listed;
5. the same block under a weaker pulse survives: the page gives the result's
   peak |θ|/α and the time it came to rest, or, with the simulation stopped
   at 3 s, that it had not come to rest; switching the block from α, p to
   b, h clears the error box of the submission before and empties the η
   typed for the block as it was given (the hint names the default that
   applies), and switching the kind clears the error box and the other
   kind's result;
6. a forensic query filled in on the form (the Point Reyes observations and a
   third one added, given by half-width and half-height) is the JSON the raw
   editor shows, runs on those observations and frequencies, shows its plot;
   its outcome and summary give the result's number of separate intervals,
   their lowest and highest ends and total width, and link the figure and
   the CSV (which holds that many intervals);
7. records, read by the service (`POST /v1/records`), never by the page: a
   two-column CSV with a comment line and a header row (`time_s,acc_g`, 250
   samples, PGA about 0.5 g) chosen in the file input is previewed before
   anything is submitted — its samples, dt and PGA are the file's, its
   motion is drawn (every sample, labelled axes), it is stored and picked
   in the list; a record spectrum, a forensic query and a time history
   name it by its id (`"ground_motion": {"record": id}`, no samples, no
   pulse) and their results are on its samples; back on pulses, no record
   is sent;
8. a file with a typo: the error box names the file and the line; a
   one-column file stating neither unit nor dt: the page asks (the
   service's hint beside a unit picker, a dt field), sends it again, and
   previews it, the old error box gone; the first record, picked again from
   the stored list, is the one sent; a fragility on a suite of both (ticked
   in the list) sends `ground_motions` by id and runs; the Point Reyes record
   (two separate intervals of scale) is said to give two, not one range;
   its locomotive switched to b and h is sent without the example's η, the
   error box before is gone; a fragility of uncertain b and h sends them as
   the truncated normals its hint states, and runs; the survival summary
   gives each rate scale with its age;
9. a long overturning spectrum is submitted and canceled with the Cancel
   button; the service reports it canceled; "Your jobs" lists the service's
   jobs newest first with their statuses, and a click on an older one (the
   forensic query) opens its status, summary and figure;
10. against a second server that wants a token for reads too
   (`--api-token`, `--auth-reads`): the token box opens by itself, the 401
   of a submission without it is explained, and once the token
   is filled in the job runs, its plot loads (fetched with the token) and
   it is listed in "Your jobs";
11. every job submitted from the form (as the browser sent it) holds only
   values the form shows in sight: a control's value, a number a visible
   hint states, a word of its visible text — nothing hidden, nothing left
   from another kind or block description;
12. the floor: pure rocking or Coulomb friction is offered for exactly the
   kinds that take one (FLOOR_KINDS of /static/constants.js, which the
   service renders from its specs); on a Coulomb floor each of them sends
   `contact` with μ and the nonlinear equations (a spectrum, pure rocking's
   beside it), on pure rocking no `contact`, and another server takes every
   one of these specs; a time history on a Coulomb floor hides its end
   (`outputs.duration`) and sends its series only, which is taken, while
   the same spec with an end is refused;
13. nothing was blocked by the policy (every violation is reported on the
   console) and no script error occurred.

Screenshots go to target/e2e/ (page.png: the finished time history;
page-error.png, page-forensic.png, page-cancel.png; page-record-preview.png
and page-record-ask.png: the record fieldset, twice its size, with a
preview and with the unit question; page-record-spectrum.png and
page-record-spectrum-figure.png; page-record-error.png,
page-forensic-record.png, page-time-history-record.png,
page-fragility-suite.png, page-survival.png, page-forensic-intervals.png,
page-fragility-geometry.png, page-jobs.png; failure.png when a step fails).

Environment: TOPPLE_BIN (default target/debug/topple), CHROMIUM (default
/usr/bin/chromium), E2E_OUT (default target/e2e), E2E_TIMEOUT (seconds the
time history may take, default 60).

Exit status 0 when every check passes, 1 otherwise.
"""

import base64
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

import websocket

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.environ.get("TOPPLE_BIN", os.path.join(ROOT, "target", "debug", "topple"))
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
OUT = os.path.abspath(os.environ.get("E2E_OUT", os.path.join(ROOT, "target", "e2e")))
PLOT_TIMEOUT = float(os.environ.get("E2E_TIMEOUT", "60"))
# The window the page must fit: Submit in sight without scrolling.
WIDTH, HEIGHT = 1400, 1000
UUID = re.compile(r"^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$")


class Failure(Exception):
    """A check that did not hold."""


def log(message):
    print(f"e2e: {message}", file=sys.stderr, flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def http_post_json(url, body, timeout=10):
    """(status, parsed body) of POST url with a JSON body; error statuses too."""
    request = urllib.request.Request(url, data=json.dumps(body).encode(), method="POST",
                                     headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=timeout) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


def http_get(url, timeout=5):
    """(status, headers, body) of GET url; error statuses too."""
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            return r.status, r.headers, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read()


def wait_until(what, predicate, timeout, interval=0.1):
    """predicate()'s first truthy value within timeout seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise Failure(f"timed out after {timeout:g} s waiting for {what}")
        time.sleep(interval)


# --- processes ----------------------------------------------------------------


class Server:
    """`topple serve` on a free port with a fresh SQLite database."""

    def __init__(self, work, name, *args):
        self.work = work
        self.name = name
        self.args = list(args)
        self.proc = None
        self.base = None
        self.log_path = os.path.join(work, f"{name}.log")

    def start(self):
        # Settings come from the arguments only, not from the environment.
        env = {k: v for k, v in os.environ.items()
               if not k.startswith("TOPPLE_") and k != "DATABASE_URL"}
        for attempt in range(3):
            port = free_port()
            with open(self.log_path, "wb") as out:
                self.proc = subprocess.Popen(
                    [BIN, "serve", "--addr", f"127.0.0.1:{port}",
                     "--database", f"sqlite://{self.work}/{self.name}.db",
                     "--shutdown-grace", "1", *self.args],
                    stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env)
            base = f"http://127.0.0.1:{port}"
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline and self.proc.poll() is None:
                try:
                    if http_get(base + "/readyz", timeout=1)[0] == 200:
                        self.base = base
                        return
                except OSError:
                    pass
                time.sleep(0.1)
            self.stop()
            # Another process may have taken the port between choosing and binding.
            if "address already in use" not in self.log().lower():
                break
            log(f"port {port} was taken; attempt {attempt + 2}")
        raise Failure(f"the server ({self.name}) did not become ready:\n" + self.log()[-4000:])

    def log(self):
        try:
            with open(self.log_path, encoding="utf-8", errors="replace") as f:
                return f.read()
        except OSError:
            return ""

    def stop(self):
        if self.proc is None:
            return
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.proc = None


class Chromium:
    """Headless Chromium with the DevTools protocol on a port of its choosing."""

    def __init__(self, work):
        self.profile = os.path.join(work, "chromium-profile")
        self.proc = None

    def _launch(self, err):
        return subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
             "--disable-dev-shm-usage", "--no-first-run", "--no-default-browser-check",
             "--disable-extensions", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--mute-audio",
             "--hide-scrollbars", "--window-size=1280,900", "--remote-debugging-port=0",
             f"--user-data-dir={self.profile}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=err, stdin=subprocess.DEVNULL,
            start_new_session=True)

    def start(self):
        os.makedirs(self.profile, exist_ok=True)
        with open(os.path.join(self.profile, "..", "chromium.log"), "wb") as err:
            self.proc = self._launch(err)
        port_file = os.path.join(self.profile, "DevToolsActivePort")

        def port():
            if self.proc.poll() is not None:
                raise Failure(f"chromium exited with status {self.proc.returncode}")
            try:
                with open(port_file) as f:
                    first = f.readline().strip()
                return int(first) if first else None
            except (OSError, ValueError):
                return None

        debug_port = wait_until("chromium's DevTools port", port, 30)
        targets = wait_until(
            "a page target",
            lambda: [t for t in json.loads(http_get(f"http://127.0.0.1:{debug_port}/json/list")[2])
                     if t.get("type") == "page"],
            15)
        return targets[0]["webSocketDebuggerUrl"]

    def stop(self):
        if self.proc is None:
            return
        # Chromium runs helper processes in its own session: end that group.
        try:
            os.killpg(self.proc.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        try:
            self.proc.wait(5)
        except subprocess.TimeoutExpired:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.proc.wait()
        self.proc = None


# --- the DevTools protocol ------------------------------------------------------


class Page:
    """One page target: commands, and the events that say something went wrong."""

    def __init__(self, ws_url):
        self.ws = websocket.create_connection(ws_url, timeout=30, suppress_origin=True)
        self.next_id = 0
        self.problems = []  # script errors and blocked resources
        self.submissions = []  # [requestId, body or None]: the POSTs to /v1/jobs, as sent
        self.requests = []  # the URL of every request the browser sent

    def close(self):
        try:
            self.ws.close()
        except Exception:
            pass

    def _event(self, message):
        method = message.get("method")
        params = message.get("params", {})
        if method == "Runtime.exceptionThrown":
            d = params.get("exceptionDetails", {})
            text = d.get("exception", {}).get("description") or d.get("text")
            self.problems.append(f"uncaught exception: {text}")
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            args = " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", []))
            self.problems.append(f"console.{params['type']}: {args}")
        elif method == "Network.requestWillBeSent":
            request = params.get("request", {})
            self.requests.append(request.get("url", ""))
            if request.get("method") == "POST" and re.search(r"/v1/jobs(\?|$)", request.get("url", "")):
                self.submissions.append([params.get("requestId"), request.get("postData")])
        elif method == "Log.entryAdded":
            entry = params.get("entry", {})
            # Failed requests the test provokes (the 422) are "network" entries;
            # policy violations are "security", script errors "javascript".
            if entry.get("level") == "error" and entry.get("source") != "network":
                self.problems.append(f"{entry.get('source')}: {entry.get('text')}")

    def send(self, method, **params):
        self.next_id += 1
        mid = self.next_id
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.recv())
            if message.get("id") == mid:
                if "error" in message:
                    raise Failure(f"{method}: {message['error']}")
                return message.get("result", {})
            self._event(message)

    def last_submission(self):
        """The body of the last job submitted (POST /v1/jobs), as the
        browser sent it."""
        self.pump()
        if not self.submissions:
            raise Failure("no job was submitted")
        entry = self.submissions[-1]
        if entry[1] is None:
            entry[1] = self.send("Network.getRequestPostData", requestId=entry[0])["postData"]
        return json.loads(entry[1])

    def pump(self):
        """Reads events that arrived meanwhile."""
        self.send("Runtime.evaluate", expression="0")

    def js(self, expression):
        """The value of a JavaScript expression (awaited when a promise)."""
        r = self.send("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise Failure(f"evaluating {expression!r}: {r['exceptionDetails']}")
        return r.get("result", {}).get("value")

    def wait_js(self, what, expression, timeout):
        return wait_until(what, lambda: self.js(expression), timeout)

    def navigate(self, url):
        self.send("Page.navigate", url=url)
        self.wait_js("the page to load", "document.readyState === 'complete'", 20)

    def click(self, selector):
        """A real mouse click at the middle of the element."""
        rect = self.js(
            f"(() => {{ const el = document.querySelector({json.dumps(selector)});"
            " if (!el) return null; el.scrollIntoView({block: 'center'});"
            " const r = el.getBoundingClientRect();"
            " return {x: r.left + r.width / 2, y: r.top + r.height / 2, w: r.width, h: r.height}; })()")
        if not rect or rect["w"] <= 0 or rect["h"] <= 0:
            raise Failure(f"{selector} is not on the page (or not visible)")
        hit = self.js(
            f"(() => {{ const el = document.querySelector({json.dumps(selector)});"
            f" const at = document.elementFromPoint({rect['x']}, {rect['y']});"
            " return at === el || el.contains(at) || (el.control && el.control === at); })()")
        if not hit:
            raise Failure(f"{selector} is covered by another element")
        for kind in ("mousePressed", "mouseReleased"):
            self.send("Input.dispatchMouseEvent", type=kind, x=rect["x"], y=rect["y"],
                      button="left", clickCount=1)

    def type_into(self, selector, text):
        """Replaces the field's value by typing text."""
        self.click(selector)
        self.js(f"(() => {{ const el = document.querySelector({json.dumps(selector)});"
                " el.focus(); el.value = ''; })()")
        self.send("Input.insertText", text=text)

    def choose(self, selector, value):
        """Sets a <select> (or any input) to value, as a user's choice would:
        the page sees input and change events."""
        ok = self.js(
            f"(() => {{ const el = document.querySelector({json.dumps(selector)});"
            f" if (!el || el.disabled) return false; el.value = {json.dumps(value)};"
            " el.dispatchEvent(new Event('input', {bubbles: true}));"
            " el.dispatchEvent(new Event('change', {bubbles: true}));"
            f" return el.value === {json.dumps(value)}; }})()")
        if not ok:
            raise Failure(f"cannot set {selector} to {value!r}")

    def set_files(self, selector, paths):
        """Chooses files in a file input, as the file dialog would: the page
        sees a change event."""
        found = self.send("Runtime.evaluate", expression=f"document.querySelector({json.dumps(selector)})")
        object_id = found.get("result", {}).get("objectId")
        if not object_id:
            raise Failure(f"{selector} is not on the page")
        self.send("DOM.setFileInputFiles", files=list(paths), objectId=object_id)

    def element_screenshot(self, selector, path, scale=1):
        """The element alone (scrolled into view), at `scale` times its size."""
        rect = self.js(
            f"(() => {{ const el = document.querySelector({json.dumps(selector)});"
            " if (!el) return null; el.scrollIntoView({block: 'center'});"
            " const r = el.getBoundingClientRect();"
            " return {x: r.left + window.scrollX, y: r.top + window.scrollY, width: r.width, height: r.height}; })()")
        if not rect or rect["width"] <= 0:
            raise Failure(f"{selector} is not on the page (or not visible)")
        shot = self.send("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                         clip=dict(rect, scale=scale))
        with open(path, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        log(f"screenshot {os.path.relpath(path, ROOT)}")

    def window_screenshot(self, path):
        """What the window shows, scrolled to the top: the first sight of the page."""
        self.js("window.scrollTo(0, 0)")
        shot = self.send("Page.captureScreenshot", format="png")
        with open(path, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        log(f"screenshot {os.path.relpath(path, ROOT)}")

    def screenshot(self, path):
        size = self.send("Page.getLayoutMetrics")["cssContentSize"]
        shot = self.send("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                         clip={"x": 0, "y": 0, "width": size["width"],
                               "height": min(size["height"], 4000), "scale": 1})
        with open(path, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        log(f"screenshot {os.path.relpath(path, ROOT)}")


# --- the checks -------------------------------------------------------------------


def check_served(base):
    status, headers, body = http_get(base + "/")
    if status != 200:
        raise Failure(f"GET / answered {status}")
    ctype = headers.get("content-type", "")
    if ctype.replace(" ", "").lower() != "text/html;charset=utf-8":
        raise Failure(f"GET / content-type is {ctype!r}")
    csp = headers.get("content-security-policy", "")
    for directive in ("default-src 'self'", "connect-src 'self'", "script-src 'self'", "style-src 'self'"):
        if directive not in csp:
            raise Failure(f"the Content-Security-Policy lacks {directive!r}: {csp!r}")
    if "'unsafe-inline'" in csp or "'unsafe-eval'" in csp:
        raise Failure(f"the Content-Security-Policy allows inline code: {csp!r}")
    html = body.decode()
    if "src=\"http" in html or "href=\"http" in html:
        raise Failure("the page is not self-contained")
    if re.search(r"<script(?![^>]*\bsrc=)|<style|\sstyle=\"|\son[a-z]+=", html):
        raise Failure("the markup holds a script, a style or an event handler of its own")
    if '<script type="module" src="/static/main.js"></script>' not in html:
        raise Failure("the page does not load its modules")
    for path, want in (("/static/main.js", "text/javascript"), ("/static/kinds/time_history.js", "text/javascript"),
                       ("/static/constants.js", "text/javascript"), ("/static/style.css", "text/css")):
        status, headers, _ = http_get(base + path)
        ctype = headers.get("content-type", "").replace(" ", "").lower()
        if status != 200 or ctype != f"{want};charset=utf-8":
            raise Failure(f"GET {path}: {status} {ctype!r}")


# Every violation of the policy, reported on the console (as an error the
# test fails on), in every document the browser opens.
REPORT_VIOLATIONS_JS = """document.addEventListener('securitypolicyviolation', (e) =>
  console.error(`policy violation: ${e.violatedDirective} ${e.blockedURI || '(inline)'}`));"""


def check_policy_enforced(page):
    """An inline script and an inline style added to the page are blocked
    and reported: the policy holds in the browser. (The reports are taken
    off the problems: they are the ones provoked here.)"""
    page.pump()
    before = len(page.problems)
    page.js("(() => { const s = document.createElement('script'); s.textContent = 'window.inlineRan = true';"
            " document.head.append(s); const st = document.createElement('style');"
            " st.textContent = 'body { outline: 9px solid red; }'; document.head.append(st); })()")
    page.wait_js("the violations to be reported", "new Promise((ok) => setTimeout(() => ok(true), 200))", 5)
    if page.js("window.inlineRan === true"):
        raise Failure("an inline script ran")
    if page.js("getComputedStyle(document.body).outlineWidth") == "9px":
        raise Failure("an inline style applied")
    page.pump()
    reported = page.problems[before:]
    if not any("script-src" in p for p in reported) or not any("style-src" in p for p in reported):
        raise Failure(f"the blocked inline script and style were not both reported: {reported}")
    del page.problems[before:]
    log(f"the policy blocked and reported an inline script and style ({len(reported)} reports)")
    page.js("document.querySelectorAll('head > script:not([src]), head > style').forEach((el) => el.remove())")


def operations_of(yaml_text):
    """`METHOD /path` of every operation under `paths:` of an OpenAPI YAML
    document (paths indented by two spaces, methods by four)."""
    out, path, inside = [], None, False
    for line in yaml_text.splitlines():
        if not line.startswith(" "):
            inside = line.rstrip() == "paths:"
            continue
        if not inside:
            continue
        m = re.match(r"^  (/\S*):$", line)
        if m:
            path = m.group(1).strip("'\"")
            continue
        m = re.match(r"^    (get|put|post|delete|patch):$", line)
        if m and path:
            out.append(f"{m.group(1).upper()} {path}")
    return out


def check_reference(page, base, guarded_base=None):
    """The API reference at /docs: linked from the page, rendered from the
    OpenAPI document (every operation of /openapi.yaml has its title, the
    submission's among them), styled by its own sheet under the page's
    policy, every link within it landing, and no request leaving this
    server."""
    status, headers, body = http_get(base + "/docs")
    if status != 200 or not headers.get("content-type", "").startswith("text/html"):
        raise Failure(f"GET /docs: {status} {headers.get('content-type')!r}")
    if headers.get("content-security-policy", "") != http_get(base + "/")[1].get("content-security-policy"):
        raise Failure("/docs is not served under the page's policy")
    page.navigate(base + "/")
    page.wait_js("the link to the reference", "!!document.querySelector('a[href=\"/docs\"]')", 10)
    page.pump()
    page.requests.clear()
    page.navigate(base + "/docs")
    page.wait_js("the reference", "!!document.getElementById('op-create_job')", 10)
    title = page.js("document.querySelector('#op-create_job h3').textContent")
    summary = page.js("document.querySelector('#op-create_job .summary').textContent")
    if title != "POST /v1/jobs" or summary != "Submit a job.":
        raise Failure(f"the submission's operation reads {title!r}, {summary!r}")
    shown = set(page.js("[...document.querySelectorAll('section.operation h3')].map((h) => h.textContent)"))
    operations = operations_of(http_get(base + "/openapi.yaml")[2].decode())
    if len(operations) < 10:
        raise Failure(f"read only {len(operations)} operations from /openapi.yaml")
    for operation in operations:
        if operation not in shown:
            raise Failure(f"/docs lacks {operation}")
    missing = page.js("[...document.querySelectorAll('a[href^=\"#\"]')]"
                      ".filter((a) => !document.getElementById(decodeURIComponent(a.hash.slice(1))))"
                      ".map((a) => a.getAttribute('href'))")
    if missing:
        raise Failure(f"/docs links to anchors it lacks: {missing[:5]}")
    background = page.js("getComputedStyle(document.querySelector('#op-create_job .method')).backgroundColor")
    if background in ("", "rgba(0, 0, 0, 0)", "transparent"):
        raise Failure("/docs is unstyled: its style sheet did not apply")
    page.js("document.querySelector('a[href=\"#schema-JobSpec\"]').click()")
    page.wait_js("the link to JobSpec to be followed", "location.hash === '#schema-JobSpec'", 5)
    page.pump()
    away = [u for u in page.requests if not u.startswith(base + "/")]
    if away:
        raise Failure(f"/docs made requests away from {base}: {away[:5]}")
    if not page.requests:
        raise Failure("no request of /docs was seen")
    page.screenshot(os.path.join(OUT, "page-docs.png"))
    if guarded_base is not None and http_get(guarded_base + "/docs")[0] != 200:
        raise Failure("/docs is not open on a server whose reads need a token")
    log(f"the reference at /docs: {len(shown)} operations, {len(page.requests)} requests, all to {base}")


def submit_in_sight(page):
    """Whether Submit is wholly inside the window, scrolled to the top, and
    not covered: (True, '') or (False, where it is)."""
    return page.js(
        "(() => { window.scrollTo(0, 0); const b = document.getElementById('submit');"
        " const r = b.getBoundingClientRect();"
        " const inside = r.width > 0 && r.top >= 0 && r.left >= 0"
        "   && r.bottom <= window.innerHeight && r.right <= window.innerWidth;"
        " const at = inside && document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);"
        " return [inside && at === b, `top ${r.top}, bottom ${r.bottom} of ${window.innerHeight}`]; })()")


def check_submit_in_sight(page):
    """At 1400×1000, Submit is in sight on first load whatever the kind, and
    stays so when the form outgrows the window (many observations)."""
    # The page alone, then in a 1400×1000 window whose toolbars take 140 px.
    for height in (HEIGHT, HEIGHT - 140):
        page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=height,
                  deviceScaleFactor=1, mobile=False)
        size = page.js("[window.innerWidth, window.innerHeight]")
        if size != [WIDTH, height]:
            raise Failure(f"the window is {size}, not {WIDTH}×{height}")
        for kind in ("time_history", "spectrum", "friction_spectrum", "forensic", "record_spectrum", "raw",
                     "time_history"):
            page.click(f"input[name=kind][value={kind}]")
            seen, where = submit_in_sight(page)
            if not seen:
                raise Failure(f"with the kind {kind}, Submit is out of sight at {WIDTH}×{height}: {where}")
    page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
              deviceScaleFactor=1, mobile=False)
    page.click("input[name=kind][value=forensic]")
    rows = page.js("document.querySelectorAll('#obs-list .obs').length")
    for _ in range(6):
        page.click("#obs-add")
    tall = page.js("document.getElementById('job-form').getBoundingClientRect().bottom")
    if tall <= HEIGHT:
        raise Failure(f"eight observations should outgrow the window; the form ends at {tall}")
    seen, where = submit_in_sight(page)
    if not seen:
        raise Failure(f"with eight observations, Submit is out of sight: {where}")
    while page.js("document.querySelectorAll('#obs-list .obs').length") > rows:
        page.click("#obs-list .obs:last-child .obs-remove")
    page.click("input[name=kind][value=time_history]")


def check_invalid_field(page):
    page.type_into("#f-alpha", "2")
    page.click("#submit")
    page.wait_js("the error to be shown", "!document.getElementById('problem').hidden", 10)
    text = page.js("document.getElementById('problem').innerText")
    if "/block/alpha" not in text or "Slenderness" not in text:
        raise Failure(f"the error does not name the field: {text!r}")
    if page.js("document.getElementById('f-alpha').getAttribute('aria-invalid')") != "true":
        raise Failure("the offending input is not marked invalid")
    if page.js("document.activeElement && document.activeElement.id") != "f-alpha":
        raise Failure("the offending input does not have the focus")
    page.screenshot(os.path.join(OUT, "page-error.png"))
    page.type_into("#f-alpha", "0.25")


def wait_plot(page, what):
    """Waits for the plot of the job shown to load (or an error to show)."""
    loaded = page.wait_js(
        f"the plot of the {what} to load",
        "(() => { const img = document.getElementById('plot');"
        " if (img && img.complete && img.naturalWidth > 0) return 'loaded';"
        " const problem = document.getElementById('problem');"
        " return !problem.hidden && problem.innerText; })()",
        PLOT_TIMEOUT)
    if loaded != "loaded":
        raise Failure(f"the plot of the {what} did not load: {loaded!r}")


def check_time_history(page, base):
    page.click("input[name=kind][value=time_history]")
    page.click("#submit")
    page.wait_js("the job to be shown", "!document.getElementById('job').hidden", 10)
    job_id = page.js("document.getElementById('job-id').textContent")
    if not UUID.match(job_id or ""):
        raise Failure(f"no job id shown: {job_id!r}")
    log(f"time history {job_id}")
    status = page.wait_js(
        "the job to finish",
        "(() => { const s = document.getElementById('status').textContent;"
        " return ['succeeded', 'failed', 'canceled'].includes(s) && s; })()",
        PLOT_TIMEOUT)
    if status != "succeeded":
        raise Failure(f"the time history {status}: {page.js('document.body.innerText')}")
    wait_plot(page, "time history")
    src = page.js("document.getElementById('plot').getAttribute('src')")
    if src != f"/v1/jobs/{job_id}/plot.svg":
        raise Failure(f"the plot comes from {src!r}")
    status, headers, _ = http_get(base + src)
    if status != 200 or not headers.get("content-type", "").startswith("image/svg+xml"):
        raise Failure(f"GET {src}: {status} {headers.get('content-type')}")
    href = page.js("document.getElementById('csv-link').getAttribute('href')")
    if href != f"/v1/jobs/{job_id}/result?format=csv":
        raise Failure(f"the CSV link is {href!r}")
    status, headers, body = http_get(base + href)
    if status != 200 or not headers.get("content-type", "").startswith("text/csv"):
        raise Failure(f"GET {href}: {status} {headers.get('content-type')}")
    rows = body.decode().strip().splitlines()
    if len(rows) < 600:
        raise Failure(f"the CSV has {len(rows)} lines; 600 samples were asked for")
    href = page.js("document.getElementById('json-link').getAttribute('href')")
    if href != f"/v1/jobs/{job_id}/result":
        raise Failure(f"the JSON link is {href!r}")
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    problem = page.js("document.getElementById('problem').hidden ? '' : document.getElementById('problem').innerText")
    if problem:
        raise Failure(f"an error is shown beside the result: {problem!r}")
    # An overturned block: when and how, not a peak rotation of π/(2α).
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if not (result["overturned"] and result["mode"] == 1 and result["impact_count"] == 1):
        raise Failure(f"the default block was expected to overturn in mode 1 after one impact: {result['mode']}")
    outcome = page.js("document.getElementById('outcome').textContent")
    m = re.match(r"Overturned at t = ([0-9.]+) s \(mode 1: after 1 impact\)\.$", outcome)
    if not m or abs(float(m.group(1)) - result["overturn_time"]) > 5e-4 * result["overturn_time"]:
        raise Failure(f"the outcome does not give the overturning time {result['overturn_time']} and mode: {outcome!r}")
    summary = summary_of(page)
    if summary.get("Mode") != "1 (after impacts)" or "Peak |θ|/α" in summary:
        raise Failure(f"the summary of an overturned block: {summary}")
    if abs(float(summary["Overturns at (s)"]) - result["overturn_time"]) > 5e-4 * result["overturn_time"]:
        raise Failure(f"the summary's overturning time: {summary}")
    # The block as it ran: its η the one given (or the default, named).
    block = result["spec"]["block"]
    want = f"α = {js_fmt(block['alpha'])} rad, p = {js_fmt(block['p'])} rad/s, η = {js_fmt(block['eta'])}"
    if summary.get("Block") != want or block["eta"] != 0.9:
        raise Failure(f"the summary does not give the block as it ran ({want}): {summary.get('Block')!r}")
    # Its warning (the friction demand stops at the pulse end) is in sight.
    kinds = page.js("[...document.querySelectorAll('#warnings li')].map((li) => li.dataset.kind)")
    if kinds != [w["kind"] for w in result["warnings"]] or "demand_excludes_fall" not in kinds:
        raise Failure(f"the warnings shown {kinds} are not the result's {result['warnings']}")
    if page.js("document.getElementById('warnings').hidden"):
        raise Failure("the warnings are hidden")
    page.screenshot(os.path.join(OUT, "page.png"))


# What the form shows: the values of its controls in sight (a radio or a
# checkbox when ticked; the words and numbers of a text field or a text
# area), the numbers its hints in sight state, and its visible text.
SHOWN_JS = """(() => {
  const form = document.getElementById('job-form');
  const values = [];
  for (const el of form.querySelectorAll('input, select, textarea')) {
    if (el.disabled || el.closest('[hidden]') || el.getClientRects().length === 0) continue;
    if (el.type === 'file' || el.type === 'password') continue;
    if ((el.type === 'radio' || el.type === 'checkbox') && !el.checked) continue;
    values.push(el.value);
    if (el.tagName === 'TEXTAREA' || el.type === 'text') values.push(...el.value.split(/[\\s,;]+/).filter(Boolean));
  }
  const hints = [...form.querySelectorAll('.hint')]
    .filter((h) => !h.closest('[hidden]') && h.getClientRects().length > 0).map((h) => h.textContent).join(' ');
  return {values, hints, text: form.innerText};
})()"""

# Constants of the form a kind sends whatever is filled in (and says so:
# "Stripes of PGA (g)").
FORM_CONSTANTS = {("fragility", "/im"): "pga_g"}


def json_leaves(value, pointer=""):
    """(JSON pointer, value) of every scalar in a document."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from json_leaves(v, f"{pointer}/{k}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from json_leaves(v, f"{pointer}/{i}")
    else:
        yield pointer, value


def check_sent_is_visible(page, body, what):
    """Every value of the job sent is one the form shows in sight: a
    control's value, a number a visible hint states (a truncation bound,
    a converted unit), or a word of its visible text. Nothing hidden, and
    nothing left over from another kind or block description, is sent."""
    shown = page.js(SHOWN_JS)
    texts = set(shown["values"])
    numbers = []
    for v in texts:
        try:
            numbers.append(float(v))
        except ValueError:
            pass
    hinted = [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e-?\d+)?", shown["hints"].replace("−", "-"))]
    words = set(re.findall(r"[\w.-]+", shown["text"]))
    for pointer, v in json_leaves(body):
        if FORM_CONSTANTS.get((body.get("kind"), pointer)) == v:
            continue
        if isinstance(v, bool):
            ok = str(v).lower() in texts
        elif isinstance(v, (int, float)):
            ok = any(x == v for x in numbers) or any(abs(x - v) <= 1e-3 * abs(v) for x in hinted)
        elif isinstance(v, str):
            ok = v in texts or v in words
        else:
            ok = False
        if not ok:
            raise Failure(f"the {what} sent {pointer} = {v!r}, which the form does not show "
                          f"(in sight: {sorted(texts)}; hints: {shown['hints']!r})")


def summary_of(page):
    """The summary shown, as {term: value}."""
    return page.js("Object.fromEntries([...document.querySelectorAll('#summary div')]"
                   ".map((d) => [d.querySelector('dt').textContent, d.querySelector('dd').textContent]))")


def finished_job(page, before, what):
    """The id of the job submitted after `before`, once it succeeded and its
    plot and summary show."""
    page.wait_js(f"the {what} to be accepted",
                 f"document.getElementById('job-id').textContent !== {json.dumps(before)}", 10)
    job_id = page.js("document.getElementById('job-id').textContent")
    status = page.wait_js(
        f"the {what} to finish",
        "(() => { const s = document.getElementById('status').textContent;"
        " return ['succeeded', 'failed', 'canceled'].includes(s) && s; })()",
        PLOT_TIMEOUT)
    if status != "succeeded":
        raise Failure(f"the {what} {status}: {page.js('document.body.innerText')[:2000]}")
    wait_plot(page, what)
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    body = page.last_submission()
    if body.get("kind") != page.js("document.querySelector('input[name=kind]:checked').value"):
        raise Failure(f"the {what} sent is of the kind {body.get('kind')!r}")
    check_sent_is_visible(page, body, what)
    return job_id


def check_survivor(page, base):
    """A block that rocks and survives: its peak |θ|/α and when it came to rest."""
    page.type_into("#f-amp", "1")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "surviving time history")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if result["overturned"] or result["rest_time"] is None:
        raise Failure(f"a_p = 1 g was expected to leave the block at rest: {result['rest_time']}")
    outcome = page.js("document.getElementById('outcome').textContent")
    m = re.match(r"Survived: peak \|θ\|/α = ([0-9.]+); came to rest at t = ([0-9.]+) s\.$", outcome)
    if (not m or abs(float(m.group(1)) - result["peak_theta_over_alpha"]) > 5e-4
            or abs(float(m.group(2)) - result["rest_time"]) > 5e-3):
        raise Failure(f"the outcome of a survivor (peak {result['peak_theta_over_alpha']}, "
                      f"rest at {result['rest_time']} s): {outcome!r}")
    # Stopped at 3 s, before it came to rest: the page says so.
    page.type_into("#f-duration", "3")
    before = job_id
    page.click("#submit")
    job_id = finished_job(page, before, "time history stopped at 3 s")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if result["rest_time"] is not None or result["end_time"] != 3.0:
        raise Failure(f"stopped at 3 s, the block was expected still rocking: {result['rest_time']}")
    outcome = page.js("document.getElementById('outcome').textContent")
    if not outcome.endswith("; still rocking when the simulation ended at t = 3 s (did not come to rest)."):
        raise Failure(f"the outcome of a block still rocking at the end: {outcome!r}")
    page.type_into("#f-duration", "")
    page.type_into("#f-amp", "2.25")


def check_forensic(page, base):
    """A forensic query from the form: the Point Reyes observations and a
    third added by hand, the same JSON as the raw editor's, a plot."""
    page.click("input[name=kind][value=forensic]")
    page.click("#obs-add")
    row = "#obs-list .obs:last-child"
    page.type_into(f"{row} .obs-name", "cabinet")
    page.type_into(f"{row} .obs-b", "0.3")
    page.type_into(f"{row} .obs-h", "0.9")
    page.type_into("#f-fo-steps", "6")
    hint = page.js(f"document.querySelector('{row} .hint').textContent")
    if "0.6 m wide × 1.8 m tall" not in hint:
        raise Failure(f"the block's full size is not spelled out: {hint!r}")
    expected = {
        "kind": "forensic",
        "pulse": {"type": "one_sine"},
        "observations": [
            {"name": "locomotive", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": True},
            {"name": "transformer", "block": {"b": 0.6, "h": 1.2}, "overturned": False},
            {"name": "cabinet", "block": {"b": 0.3, "h": 0.9}, "overturned": False},
        ],
        "frequency_hz": {"from": 0.25, "to": 3, "steps": 6},
        "a_p_g": {"from": 0.05, "to": 3},
        "formulation": "nonlinear",
    }
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if raw != expected:
        raise Failure(f"the form's forensic query is {raw}, not {expected}")
    page.click("input[name=kind][value=forensic]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query")
    log(f"forensic query {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    seen = [(o["name"], o["overturned"]) for o in result["observations"]]
    if seen != [("locomotive", True), ("transformer", False), ("cabinet", False)]:
        raise Failure(f"the query ran on {seen}")
    if [round(f["frequency_hz"], 9) for f in result["frequencies"]] != [0.25, 0.8, 1.35, 1.9, 2.45, 3.0]:
        raise Failure(f"the query's frequencies: {[f['frequency_hz'] for f in result['frequencies']]}")
    src = page.js("document.getElementById('plot').getAttribute('src')")
    if src != f"/v1/jobs/{job_id}/plot.svg":
        raise Failure(f"the forensic plot comes from {src!r}")
    if summary_of(page).get("Observations") != "1 toppled, 2 stood":
        raise Failure(f"the forensic summary: {summary_of(page)}")
    check_forensic_answer(page, base, job_id, result)
    page.screenshot(os.path.join(OUT, "page-forensic.png"))
    return job_id


def check_forensic_coulomb(page, base):
    """The same query on a Coulomb floor (μ = 0.3), the transformer seen
    standing 0.01–0.3 m from where it stood: the floor and the slide go in
    the spec, a slide in centimetres is warned about beside its card, and
    the summary names the floor."""
    page.click("input[name=kind][value=forensic]")
    page.click("input[name=contact][value=coulomb]")
    page.type_into("#f-c-mu", "0.3")
    row = "#obs-list .obs:nth-child(2)"
    if page.js(f"document.querySelector('{row} .obs-slid').hidden"):
        raise Failure("a standing observation on a Coulomb floor has no slide to give")
    if not page.js("document.querySelector('#obs-list .obs:first-child .obs-slid').hidden"):
        raise Failure("an observation that toppled offers a slide")
    page.type_into(f"{row} .obs-slid-hi", "30")
    hint = page.js(f"document.querySelector('{row} .hint').textContent")
    if "not cm" not in hint or "0.3 m" not in hint:
        raise Failure(f"a slide of 30 m is not questioned: {hint!r}")
    page.type_into(f"{row} .obs-slid-lo", "0.01")
    page.type_into(f"{row} .obs-slid-hi", "0.3")
    page.type_into("#f-fo-steps", "3")
    page.type_into("#f-fo-ato", "1")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    page.click("input[name=kind][value=forensic]")
    if raw.get("contact") != {"model": "coulomb", "mu": 0.3} or raw.get("formulation") != "nonlinear":
        raise Failure(f"the floor sent: {raw.get('contact')}, {raw.get('formulation')}")
    slid = [o.get("slid_m") for o in raw["observations"]]
    if slid != [None, [0.01, 0.3], None]:
        raise Failure(f"the slides sent: {slid}")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query on a Coulomb floor")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if [o.get("slid_m") for o in result["observations"]] != slid:
        raise Failure(f"the query ran on {result['observations']}")
    floor = summary_of(page).get("Floor")
    if floor != "Coulomb friction, μ = 0.3":
        raise Failure(f"the summary's floor: {floor!r}")
    page.screenshot(os.path.join(OUT, "page-forensic-coulomb.png"))
    # Back to pure rocking and the first query's axes.
    page.type_into(f"{row} .obs-slid-lo", "")
    page.type_into(f"{row} .obs-slid-hi", "")
    page.type_into("#f-fo-steps", "6")
    page.type_into("#f-fo-ato", "3")
    page.click("input[name=contact][value=no_sliding]")


def constants_of(base):
    """The page's constants as the service renders them (/static/constants.js)."""
    status, _, body = http_get(base + "/static/constants.js")
    if status != 200:
        raise Failure(f"GET /static/constants.js: {status}")
    return {m.group(1): json.loads(m.group(2))
            for m in re.finditer(r"^export const (\w+) = (.+);$", body.decode(), re.M)}


# A record's samples, for a spec sent to another server (which does not
# store the page's records).
INLINE_MOTION = {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, 0.5, 0.2, -0.4, 0.0]}


def small(spec):
    """The spec with its grids cut to a point or two (it is only to be taken)."""
    spec = json.loads(json.dumps(spec))
    for key in ("omega_ratio", "R_m", "stripes", "frequency_hz", "omega_p"):
        if isinstance(spec.get(key), dict) and "steps" in spec[key]:
            spec[key]["steps"] = 1
    if "samples" in spec:
        spec["samples"] = 2
    if isinstance(spec.get("ground_motion"), dict) and "record" in spec["ground_motion"]:
        spec["ground_motion"] = dict(INLINE_MOTION)
    return spec


def check_floor_kinds(page, base, work):
    """The floor is offered for the kinds that take one, and only for them;
    each sends it as the service takes it; a time history on a Coulomb
    floor sends its series and no end of its own."""
    floor_kinds = constants_of(base)["FLOOR_KINDS"]
    if not floor_kinds:
        raise Failure("no kind takes a floor")
    kinds = page.js("[...document.querySelectorAll('input[name=kind]')].map((i) => i.value)")
    for kind in kinds:
        page.click(f"input[name=kind][value={kind}]")
        offered = not page.js("!!document.getElementById('fs-contact').closest('[hidden]')")
        if offered != (kind in floor_kinds):
            raise Failure(f"the floor is {'' if offered else 'not '}offered for {kind} (floor kinds: {floor_kinds})")
    page.click("input[name=kind][value=time_history]")
    models = page.js("[...document.querySelectorAll('input[name=contact]')].map((i) => i.value)")
    if models != ["no_sliding", "coulomb"]:
        raise Failure(f"the floor's models offered: {models}")
    checker = Server(work, "floors")
    try:
        checker.start()
        for kind in floor_kinds:
            for model in models:
                page.click(f"input[name=kind][value={kind}]")
                page.click(f"input[name=contact][value={model}]")
                coulomb = model == "coulomb"
                hidden = page.js("['contact-mu', 'f-c-mu', 'f-c-muk'].map((id) =>"
                                 " !!document.getElementById(id).closest('[hidden]'))")
                if hidden != [not coulomb] * 3:
                    raise Failure(f"{kind} on {model}: μ and μ_k hidden {hidden}")
                if coulomb:
                    page.type_into("#f-c-mu", "0.3")
                page.click("#show-json")
                raw = json.loads(page.js("document.getElementById('f-raw').value"))
                page.click(f"input[name=kind][value={kind}]")
                want = {"model": "coulomb", "mu": 0.3} if coulomb else None
                if raw.get("contact") != want:
                    raise Failure(f"{kind} on {model} sends the floor {raw.get('contact')}")
                if coulomb and raw.get("formulation") != "nonlinear":
                    raise Failure(f"{kind} on a Coulomb floor sends the {raw.get('formulation')} equations")
                if raw.get("no_sliding_beside") != (True if coulomb and kind == "spectrum" else None):
                    raise Failure(f"{kind} on {model}: no_sliding_beside = {raw.get('no_sliding_beside')}")
                status, body = http_post_json(checker.base + "/v1/jobs", small(raw))
                if status not in (200, 201, 202):
                    raise Failure(f"the service does not take {kind} on {model}: {status} {body}")
        # A time history on a Coulomb floor: its series, no end of its own.
        page.click("input[name=kind][value=time_history]")
        page.click("input[name=contact][value=no_sliding]")
        page.type_into("#f-duration", "4")
        page.click("input[name=contact][value=coulomb]")
        hidden = page.js("['duration-field', 'f-series'].map((id) => !!document.getElementById(id).closest('[hidden]'))")
        if hidden != [True, False]:
            raise Failure(f"on a Coulomb floor the time history's end and series are hidden: {hidden}")
        page.click("#show-json")
        raw = json.loads(page.js("document.getElementById('f-raw').value"))
        page.click("input[name=kind][value=time_history]")
        series = int(page.js("document.getElementById('f-series').value"))
        if raw.get("outputs") != {"series": series}:
            raise Failure(f"a time history on a Coulomb floor sends the outputs {raw.get('outputs')}")
        status, body = http_post_json(checker.base + "/v1/jobs", raw)
        if status not in (200, 201, 202):
            raise Failure(f"the service does not take the Coulomb history: {status} {body}")
        raw["outputs"]["duration"] = 4
        status, body = http_post_json(checker.base + "/v1/jobs", raw)
        if status != 422 or not str(body.get("pointer", "")).startswith("/outputs"):
            raise Failure(f"a Coulomb history with an end of its own is not refused: {status} {body}")
        log(f"the floor: {len(floor_kinds)} kinds × {len(models)} models taken, a Coulomb history's end refused")
    finally:
        checker.stop()
    page.click("input[name=contact][value=no_sliding]")
    if page.js("!!document.getElementById('duration-field').closest('[hidden]')"):
        raise Failure("on pure rocking the time history's end stays hidden")
    page.type_into("#f-duration", "")


def intervals_of(lists):
    """(count, lowest, highest, total length) of the intervals in lists."""
    xs = [iv for ivs in lists for iv in ivs]
    if not xs:
        return 0, None, None, 0.0
    return len(xs), min(lo for lo, _ in xs), max(hi for _, hi in xs), sum(hi - lo for lo, hi in xs)


def check_forensic_answer(page, base, job_id, result):
    """A forensic answer is read as what it is — a number of separate
    intervals, never one range from the lowest to the highest: the outcome
    and the summary give the result's count of intervals, their lowest and
    highest ends and their total length, and link to the figure and to the
    CSV that list every one of them."""
    record = result["excitation"] == "ground_motion"
    if record:
        count, lo, hi, measure = intervals_of([result["consistent_scale"]])
        _, lo_g, hi_g, measure_g = intervals_of([result["consistent_pga_g"]])
        where = ""
    else:
        count, lo, hi, measure = intervals_of([f["consistent_g"] for f in result["frequencies"]])
        with_any = sum(1 for f in result["frequencies"] if f["consistent_g"])
        where = f" at {with_any} of {len(result['frequencies'])} frequencies"
    outcome = page.js("document.getElementById('outcome').textContent")
    summary = summary_of(page)
    if count == 0:
        if not outcome.startswith("No "):
            raise Failure(f"no interval, yet the outcome says {outcome!r}")
        return
    unit = "" if record else " g"
    axis = "the record's scale" if record else "a_p"
    if count == 1:
        want = f"one interval of {axis}"
    else:
        want = (f"{count} separate intervals of {axis}{where} (lowest {js_fmt(lo)}{unit}, highest {js_fmt(hi)}{unit}; "
                f"{js_fmt(measure)}{unit} wide in all")
    if record and count > 1:
        want += f"; as PGA: lowest {js_fmt(lo_g)} g, highest {js_fmt(hi_g)} g, {js_fmt(measure_g)} g in all)"
    if want not in outcome:
        raise Failure(f"the outcome does not say {want!r}: {outcome!r}")
    if record and 1 < count <= 6:
        listed = ", ".join(f"{js_fmt(a)} – {js_fmt(b)}" if js_fmt(a) != js_fmt(b) else js_fmt(a)
                           for a, b in result["consistent_scale"])
        if summary.get("The intervals (scale)") != listed:
            raise Failure(f"the summary does not list the {count} intervals {listed!r}: {summary}")
    if not summary.get("Consistent intervals", "").startswith(f"{count}{where} — each in the figure and the CSV"):
        raise Failure(f"the summary does not count the {count} intervals: {summary}")
    if record:
        want_lohi = f"{js_fmt(lo)} (PGA {js_fmt(lo_g)} g), {js_fmt(hi)} (PGA {js_fmt(hi_g)} g)"
        got_lohi = summary.get("Lowest, highest scale", "")
        if not summary.get("Total width, all intervals", "").startswith(js_fmt(measure)) \
                or f"(PGA {js_fmt(measure_g)} g)" not in summary.get("Total width, all intervals", ""):
            raise Failure(f"the summary's total width is not {measure} (PGA {measure_g} g): {summary}")
    else:
        got_lohi = re.sub(r" \(at [0-9.]+ Hz\)", "", summary.get("Lowest, highest a_p", ""))
        want_lohi = f"{js_fmt(lo)} g, {js_fmt(hi)} g"
        if not summary.get("Total width, all intervals", "").startswith(f"{js_fmt(measure)} g, summed over the"):
            raise Failure(f"the summary's total width is not {measure} g: {summary}")
    if got_lohi != want_lohi:
        raise Failure(f"the summary's lowest and highest are not {want_lohi!r}: {summary}")
    links = page.js("[...document.querySelectorAll('#summary a')].map((a) => [a.textContent, a.getAttribute('href')])")
    if links != [["figure", f"/v1/jobs/{job_id}/plot.svg"], ["CSV", f"/v1/jobs/{job_id}/result?format=csv"]]:
        raise Failure(f"the summary does not link the figure and the CSV: {links}")
    status, _, body = http_get(base + links[1][1])
    header, *rows = body.decode().strip().splitlines()
    columns = header.split(",")
    observation = columns.index("observation")
    lo = columns.index("consistent_lo_scale" if record else "consistent_lo_g")
    # The intersection's rows have no observation; a frequency without an
    # interval has a row without ends.
    together = [r for r in rows if r.split(",")[observation] == "" and r.split(",")[lo] != ""]
    if status != 200 or len(together) != count:
        raise Failure(f"the CSV linked has {len(together)} intervals consistent with every observation, not {count}")


# --- records ---------------------------------------------------------------------

HEX32 = re.compile(r"^[0-9a-f]{32}$")


def js_fmt(x):
    """A number as the page writes it: four significant digits."""
    return f"{float(f'{x:.4g}'):g}"


def write_csv_record(work):
    """A two-column CSV as a logger writes it: a comment line (with a year in
    it), a header row naming the columns (the acceleration in g), then 250
    samples every 0.01 s of a 2 Hz sine under a trapezoidal envelope, PGA
    about 0.5 g. Returns (path, samples, PGA in g)."""
    dt, n = 0.01, 250
    t_end = (n - 1) * dt
    acc = [round(0.5 * min(1.0, k * dt / 0.6, (t_end - k * dt) / 0.6) * math.sin(2 * math.pi * 2 * k * dt), 5)
           for k in range(n)]
    path = os.path.join(work, "sine_burst_1995.csv")
    with open(path, "w") as f:
        f.write("# synthetic burst for the page test, station HOL, 1995-03-02\n")
        f.write("time_s,acc_g\n")
        for k, a in enumerate(acc):
            f.write(f"{k * dt:.2f},{a:.5f}\n")
    return path, n, max(abs(a) for a in acc)


def preview_facts(page):
    """The record's numbers the preview shows, as {term: value}."""
    return page.js("Object.fromEntries([...document.querySelectorAll('#rec-facts div')]"
                   ".map((d) => [d.querySelector('dt').textContent, d.querySelector('dd').textContent]))")


def wait_preview(page, what, name):
    """Waits for the preview of the record called `name`, its motion drawn."""
    state = page.wait_js(
        f"the preview of {what}",
        "(() => { const svg = document.querySelector('#rec-plot svg');"
        " if (!document.getElementById('rec-preview').hidden && svg"
        f"   && document.getElementById('rec-name').textContent === {json.dumps(name)}) return 'shown';"
        " if (!document.getElementById('rec-ask').hidden) return 'asked: ' + document.getElementById('rec-ask-text').textContent;"
        " const problem = document.getElementById('problem');"
        " return !problem.hidden && 'error: ' + problem.innerText; })()",
        20)
    if state != "shown":
        raise Failure(f"no preview of {what}: {state}")


def check_preview_numbers(page, what, samples, dt, pga):
    """The preview gives the file's samples, dt and PGA (g), and draws them."""
    facts = preview_facts(page)
    m = re.fullmatch(r"([0-9.]+) g", facts.get("PGA", ""))
    if (facts.get("Samples") != str(samples) or facts.get("dt") != f"{js_fmt(dt)} s"
            or not m or abs(float(m.group(1)) - pga) > 5e-4 * pga):
        raise Failure(f"the preview of {what} says {facts}, not {samples} samples, dt = {dt} s, PGA {pga} g")
    drawn = page.js(
        "(() => { const svg = document.querySelector('#rec-plot svg');"
        " return {peak: Number(svg.dataset.peakG), samples: Number(svg.dataset.samples),"
        " points: svg.querySelector('polyline').getAttribute('points').trim().split(/\\s+/).length,"
        " labels: [...svg.querySelectorAll('text')].map((t) => t.textContent)}; })()")
    if drawn["samples"] != samples or drawn["points"] != samples or abs(drawn["peak"] - pga) > 2e-3 * pga:
        raise Failure(f"the motion drawn for {what} is not the file's ({samples} samples, PGA {pga} g): {drawn}")
    if "t (s)" not in drawn["labels"] or "ü_g/g" not in drawn["labels"]:
        raise Failure(f"the motion's axes are not labelled: {drawn['labels']}")


def check_record_spectrum(page, base, work):
    """A CSV file chosen on the form is read by the service: before anything
    is submitted, its name, samples, dt and PGA show, its motion is drawn,
    it is stored and listed; the record spectrum names it by its id; its
    figure and summary agree with the file. Returns the stored record."""
    path, samples, pga = write_csv_record(work)
    name = os.path.basename(path)
    page.click("input[name=kind][value=record_spectrum]")
    if page.js("document.getElementById('fs-motion').hidden"):
        raise Failure("the record spectrum offers no record")
    if page.js("!!document.getElementById('fs-pulse').querySelector('#f-type').closest('[hidden]')") is not True:
        raise Failure("the pulse type is offered for a record spectrum")
    page.set_files("#f-rec-file", [path])
    wait_preview(page, "the CSV file", name)
    check_preview_numbers(page, "the CSV file", samples, 0.01, pga)
    status, _, body = http_get(base + "/v1/records?limit=50")
    listed = json.loads(body)["records"] if status == 200 else []
    rec = listed[0] if listed else {}
    if rec.get("name") != name or rec.get("samples") != samples or not HEX32.match(rec.get("id", "")):
        raise Failure(f"the file is not the newest stored record: {status} {body[:300]!r}")
    picked = page.js("(() => { const r = document.querySelector('#rec-stored input:checked'); return r && r.value; })()")
    if picked != rec["id"]:
        raise Failure(f"the stored list does not show the record as picked: {picked!r}")
    if not page.js("document.getElementById('problem').hidden"):
        raise Failure("an error box is shown beside the loaded record")
    page.element_screenshot("#fs-motion", os.path.join(OUT, "page-record-preview.png"), scale=2)
    page.type_into("#f-rs-steps", "3")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    expected = {"kind": "record_spectrum", "ground_motion": {"record": rec["id"]},
                "block": {"alpha": 0.2}, "R_m": {"from": 0.2, "to": 2, "steps": 3},
                "scale": {"to": 3}, "formulation": "nonlinear"}
    if raw != expected:
        raise Failure(f"the form's record spectrum is {raw}, not {expected}")
    page.click("input[name=kind][value=record_spectrum]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "record spectrum")
    log(f"record spectrum {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    sizes = [round(s["R_m"], 9) for s in result["spectrum"]]
    if sizes != [0.2, 1.1, 2.0]:
        raise Failure(f"the record spectrum's sizes: {sizes}")
    if result["record"]["samples"] != samples or abs(result["record"]["pga_g"] - pga) > 5e-4 * pga:
        raise Failure(f"the record spectrum ran on another record: {result['record']}")
    toppled = [s for s in result["spectrum"] if s["min_overturn_scale"] is not None]
    outcome = page.js("document.getElementById('outcome').textContent")
    if toppled:
        lowest = min(toppled, key=lambda s: s["min_overturn_scale"])
        m = re.match(r"Lowest overturning found: scale ([0-9.]+) \(PGA ([0-9.]+) g\), for R = ([0-9.]+) m", outcome)
        if not m or abs(float(m.group(1)) - lowest["min_overturn_scale"]) > 5e-4 * lowest["min_overturn_scale"]:
            raise Failure(f"the outcome does not give the lowest scale {lowest['min_overturn_scale']}: {outcome!r}")
        # Where it lies: a certain band, or a mixed zone (then not read as certain).
        place = "inside a mixed zone" if lowest["min_overturn_in"] == "mixed" else "in a certain band"
        if place not in outcome:
            raise Failure(f"the outcome does not say the lowest scale lies {place}: {outcome!r}")
        certain = [s for s in result["spectrum"] if s.get("min_certain_overturn_scale") is not None]
        if certain:
            sure = min(s["min_certain_overturn_scale"] for s in certain)
            m = re.search(r"Lowest certain overturning: scale ([0-9.]+)", outcome)
            if not m or abs(float(m.group(1)) - sure) > 5e-4 * sure:
                raise Failure(f"the outcome does not give the lowest certain scale {sure}: {outcome!r}")
    elif not outcome.startswith("No block size overturns"):
        raise Failure(f"the outcome of a record spectrum without overturning: {outcome!r}")
    summary = summary_of(page)
    if summary.get("Record") != f"{samples} samples, dt = 0.01 s":
        raise Failure(f"the record spectrum summary: {summary}")
    page.screenshot(os.path.join(OUT, "page-record-spectrum.png"))
    page.element_screenshot("#plot-box", os.path.join(OUT, "page-record-spectrum-figure.png"))
    return rec


def check_forensic_record(page, base, rec):
    """A forensic query on the record loaded: the observations of the pulse
    query, the record by its id, the scale axis as PGA; the summary and
    outcome agree with the result; back to pulses, the pulse's fields
    return and the record is not sent."""
    page.click("input[name=kind][value=forensic]")
    page.click("input[name=fo-by][value=record]")
    hidden = page.js("['f-type', 'fo-pulse-axes', 'fo-record-axes', 'fs-motion'].map((id) =>"
                     " !!document.getElementById(id).closest('[hidden]'))")
    if hidden != [True, True, False, False]:
        raise Failure(f"on a record the form shows the wrong fields (hidden: {hidden})")
    if page.js("document.getElementById('rec-name').textContent") != rec["name"]:
        raise Failure("the forensic form does not show the record loaded")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    observations = raw.pop("observations")
    expected = {"kind": "forensic", "ground_motion": {"record": rec["id"]},
                "pga_g": {"from": 0.05, "to": 3}, "formulation": "nonlinear"}
    if raw != expected or [o["name"] for o in observations][:2] != ["locomotive", "transformer"]:
        raise Failure(f"the form's record query is {raw}, not {expected}")
    page.click("input[name=kind][value=forensic]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query on a record")
    log(f"forensic query on a record {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if result["excitation"] != "ground_motion" or result["frequencies"]:
        raise Failure(f"not a record query: {result['excitation']}, {len(result['frequencies'])} frequencies")
    check_forensic_answer(page, base, job_id, result)
    summary = summary_of(page)
    want = f"{rec['samples']} samples, dt = {js_fmt(rec['dt'])} s, PGA {js_fmt(result['record']['pga_g'])} g"
    if summary.get("Record") != want:
        raise Failure(f"the record query's summary: {summary}, not {want!r}")
    src = page.js("document.getElementById('plot').getAttribute('src')")
    if src != f"/v1/jobs/{job_id}/plot.svg":
        raise Failure(f"the record query's plot comes from {src!r}")
    page.screenshot(os.path.join(OUT, "page-forensic-record.png"))
    page.click("input[name=fo-by][value=pulse]")
    if page.js("!!document.getElementById('f-type').closest('[hidden]')"):
        raise Failure("back on pulses, the pulse type stays hidden")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if "ground_motion" in raw or raw.get("pulse") != {"type": "one_sine"}:
        raise Failure(f"back on pulses, the query is {raw}")
    page.click("input[name=kind][value=time_history]")


def check_time_history_record(page, base, rec):
    """A time history on the record loaded: the pulse's fields give way to
    the record, the spec names it and sends no pulse; the result's ground
    motion is the record's; back to a pulse, no record is sent."""
    page.click("input[name=kind][value=time_history]")
    page.click("input[name=th-by][value=record]")
    hidden = page.js("['f-type', 'pulse-axes', 'fs-motion', 'fs-block'].map((id) =>"
                     " !!document.getElementById(id).closest('[hidden]'))")
    if hidden != [True, True, False, False]:
        raise Failure(f"a time history on a record shows the wrong fields (hidden: {hidden})")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if raw.get("ground_motion") != {"record": rec["id"]} or "pulse" in raw or raw.get("block", {}).get("alpha") != 0.25:
        raise Failure(f"the form's time history on a record is {raw}")
    page.click("input[name=kind][value=time_history]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "time history on a record")
    log(f"time history on a record {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    peaks = result.get("ground_peaks") or {}
    if abs(peaks.get("pga_g", 0) - rec["pga_g"]) > 5e-4 * rec["pga_g"]:
        raise Failure(f"the time history's ground motion is not the record's: {peaks}")
    outcome = page.js("document.getElementById('outcome').textContent")
    if not re.match(r"(Overturned at t = |Survived: |Did not rock)", outcome):
        raise Failure(f"the time history on a record says {outcome!r}")
    motion = summary_of(page).get("Ground motion", "")
    want = f"a record ({rec['samples']} samples, dt = {js_fmt(rec['dt'])} s): PGA {js_fmt(peaks['pga_g'])} g"
    if not motion.startswith(want):
        raise Failure(f"the summary of a time history on a record says {motion!r}, not {want!r}")
    page.screenshot(os.path.join(OUT, "page-time-history-record.png"))
    # Its vertical component, pasted: sent inside the record, in the series,
    # the CSV and the figure.
    page.choose("#f-vert", "samples")
    page.type_into("#f-vert-text", "0, 0.05, 0.1, -0.05, 0")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    vertical = raw.get("ground_motion", {}).get("vertical")
    if vertical != {"acc": [0, 0.05, 0.1, -0.05, 0], "unit": "g"} or "vertical" in raw:
        raise Failure(f"the time history with a vertical record is {raw}")
    page.click("input[name=kind][value=time_history]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "time history with a vertical record")
    log(f"time history with a vertical record {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    pga_v = (result.get("ground_peaks") or {}).get("pga_v_g")
    if pga_v is None or abs(pga_v - 0.1) > 1e-9 or "ground_vertical_acceleration" not in (result.get("series") or {}):
        raise Failure(f"the vertical record is not the result's: {result.get('ground_peaks')}")
    header = http_get(f"{base}/v1/jobs/{job_id}/result?format=csv")[2].decode().splitlines()[0]
    if not header.endswith(",ground_vertical_acceleration_m_per_s2,ug_v_g"):
        raise Failure(f"the CSV of a time history with a vertical record has the columns {header!r}")
    wait_plot(page, "time history with a vertical record")
    said = summary_of(page).get("Vertical ground motion", "")
    if said != "a record of its own: PGA_v 0.1 g":
        raise Failure(f"the summary of a time history with a vertical record says {said!r}")
    status, _, svg = http_get(f"{base}/v1/jobs/{job_id}/plot.svg")
    if status != 200 or "ü_v / g" not in svg.decode():
        raise Failure(f"the figure of a time history with a vertical record: {status}, no ü_v panel")
    page.choose("#f-vert", "")
    page.click("input[name=th-by][value=pulse]")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if "ground_motion" in raw or raw.get("pulse", {}).get("type") != "one_sine" or "vertical" in raw:
        raise Failure(f"back on a pulse, the time history is {raw}")
    # Beside a pulse: a ratio, sent only when chosen; no samples of its own.
    page.click("input[name=kind][value=time_history]")
    if not page.js("document.getElementById('f-vert-own').hidden"):
        raise Failure("beside a pulse, the page offers vertical samples")
    page.choose("#f-vert", "ratio")
    page.type_into("#f-vert-ratio", "-0.3")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if raw.get("vertical") != {"ratio": -0.3} or "ground_motion" in raw:
        raise Failure(f"a pulse with a vertical ratio is {raw}")
    page.click("input[name=kind][value=time_history]")
    page.choose("#f-vert", "")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if "vertical" in raw:
        raise Failure(f"without a vertical motion the time history is {raw}")
    page.click("input[name=kind][value=time_history]")


def check_record_questions(page, base, work, first):
    """A file the service cannot read: the error box names it and its line.
    A one-column file that states neither unit nor dt: the page asks (with
    the service's hint) and sends it again; the preview is the file's and
    the error box is gone. Then the first record, picked from the stored
    list, is previewed again. Returns the one-column record's id."""
    page.click("input[name=kind][value=record_spectrum]")
    bad = os.path.join(work, "typo.csv")
    with open(bad, "w") as f:
        f.write("time_s,acc_g\n0.00,0.0\n0.01,0.12\n0.02,0..3\n0.03,0.1\n")
    page.set_files("#f-rec-file", [bad])
    page.wait_js("the file's error", "!document.getElementById('problem').hidden", 10)
    text = page.js("document.getElementById('problem').innerText")
    if "typo.csv" not in text or not re.search(r"line\s*\d", text, re.I):
        raise Failure(f"the error does not name the file and its line: {text!r}")
    if not page.js("document.getElementById('rec-preview').hidden"):
        raise Failure("a preview is shown beside the error")
    page.screenshot(os.path.join(OUT, "page-record-error.png"))

    samples, dt, peak = 300, 0.02, 2.0  # m/s²
    one = os.path.join(work, "one_column.txt")
    with open(one, "w") as f:
        for k in range(samples):
            f.write(f"{peak * math.sin(math.pi * k / (samples - 1)) * math.sin(2 * math.pi * 2 * k * dt):.6f}\n")
    with open(one) as f:
        pga = max(abs(float(v)) for v in f.read().split()) / 9.81
    page.set_files("#f-rec-file", [one])
    asked_all, seen = [], 0
    for _ in range(4):
        state = page.wait_js(
            "the service's question or the preview",
            "(() => { if (!document.getElementById('rec-preview').hidden) return 'shown';"
            " const ask = document.getElementById('rec-ask');"
            f" if (!ask.hidden && Number(ask.dataset.round) > {seen}) return 'asked';"
            " const problem = document.getElementById('problem');"
            " return !problem.hidden && 'error: ' + problem.innerText; })()",
            15)
        if state == "shown":
            break
        if state != "asked":
            raise Failure(f"the one-column file: {state}")
        seen = page.js("Number(document.getElementById('rec-ask').dataset.round)")
        asked = page.js("[...document.querySelectorAll('#rec-ask [data-param]')]"
                        ".filter((el) => !el.hidden && el.matches('.field')).map((el) => el.dataset.param)")
        hint = page.js("document.getElementById('rec-ask-text').textContent")
        if len(hint) < 20 or "one_column.txt" not in hint:
            raise Failure(f"the question gives no hint of the service's: {hint!r}")
        if seen == 1:
            page.element_screenshot("#fs-motion", os.path.join(OUT, "page-record-ask.png"), scale=2)
        for param in asked:
            if param == "unit":
                page.choose("#f-rec-unit", "m/s2")
            elif param == "dt":
                page.type_into("#f-rec-dt", str(dt))
            else:
                raise Failure(f"the service asks for {param} of a one-column file")
        asked_all += [p for p in asked if p not in asked_all]
        page.click("#rec-resend")
    if "unit" not in asked_all:
        raise Failure(f"the unit of the one-column file was never asked for (asked: {asked_all})")
    wait_preview(page, "the one-column file", "one_column.txt")
    check_preview_numbers(page, "the one-column file", samples, dt, pga)
    if not page.js("document.getElementById('rec-ask').hidden"):
        raise Failure("the question stays after the file was read")
    if not page.js("document.getElementById('problem').hidden"):
        raise Failure("the old error box stays on screen after the file was read")
    other = page.js("(() => { const r = document.querySelector('#rec-stored input:checked'); return r && r.value; })()")
    if not HEX32.match(other or "") or other == first["id"]:
        raise Failure(f"the one-column record is not the one picked: {other!r}")
    # The first record again, from the stored list.
    page.click(f"#rec-stored input[value='{first['id']}']")
    wait_preview(page, "the stored record picked", first["name"])
    if preview_facts(page).get("Samples") != str(first["samples"]):
        raise Failure(f"the stored record picked shows {preview_facts(page)}")
    page.click("#show-json")
    if json.loads(page.js("document.getElementById('f-raw').value"))["ground_motion"] != {"record": first["id"]}:
        raise Failure("the stored record picked is not the one sent")
    page.click("input[name=kind][value=time_history]")
    return other


def check_fragility_suite(page, base, ids):
    """A fragility on a suite of stored records: ticked in the list, sent as
    ground_motions by id with no pulse; the job runs; back to pulses, no
    record is sent."""
    page.click("input[name=kind][value=fragility]")
    page.click("input[name=fg-by][value=records]")
    hidden = page.js("['f-type', 'fg-pulse-axes', 'fs-motion'].map((id) =>"
                     " !!document.getElementById(id).closest('[hidden]'))")
    if hidden != [True, True, False]:
        raise Failure(f"a fragility on records shows the wrong fields (hidden: {hidden})")
    kinds = page.js("[...document.querySelectorAll('#rec-stored input')].map((i) => i.type)")
    if not kinds or set(kinds) != {"checkbox"}:
        raise Failure(f"the suite is not chosen with checkboxes: {kinds}")
    for rid in ids:
        page.click(f"#rec-stored input[value='{rid}']")
    page.type_into("#f-fg-from", "0.3")
    page.type_into("#f-fg-to", "1.5")
    page.type_into("#f-fg-steps", "3")
    page.type_into("#f-fg-samples", "8")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if (raw.get("ground_motions") != [{"record": rid} for rid in ids] or "pulse" in raw
            or raw.get("stripes") != {"from": 0.3, "to": 1.5, "steps": 3} or raw.get("samples") != 8):
        raise Failure(f"the form's fragility on a suite is {raw}")
    page.click("input[name=kind][value=fragility]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "fragility on a suite")
    log(f"fragility on a suite {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if [s["n"] for s in result["stripes"]] != [8, 8, 8]:
        raise Failure(f"the fragility's stripes: {result['stripes']}")
    page.screenshot(os.path.join(OUT, "page-fragility-suite.png"))
    page.click("input[name=fg-by][value=pulse]")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if "ground_motions" in raw or raw.get("pulse", {}).get("type") != "one_sine":
        raise Failure(f"back on pulses, the fragility is {raw}")
    page.click("input[name=kind][value=time_history]")


def check_survival(page, base):
    """A survival job from the form: the example power-law hazard, a
    lognormal fragility and three ages; the outcome gives the result's
    probabilities."""
    page.click("input[name=kind][value=survival]")
    if not page.js("document.getElementById('fs-pulse').hidden"):
        raise Failure("the pulse fieldset is offered for a survival job")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    if (raw.get("fragility") != {"beta": 0.38, "median_g": 0.38} or raw.get("age_years") != [1000, 10000, 30000]
            or len(raw["hazard"]["points"]) != 6 or raw["hazard"]["im"] != "pga_g"):
        raise Failure(f"the form's survival job is {raw}")
    page.click("input[name=kind][value=survival]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "survival")
    log(f"survival {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    outcome = page.js("document.getElementById('outcome').textContent")
    first = result["ages"][0]["survival_probability"]
    if f"P = {float(f'{first:.3g}'):g} at 1000 yr" not in outcome:
        raise Failure(f"the survival outcome does not give P_s = {first} at 1000 yr: {outcome!r}")
    # Every rate scale is given with the age it belongs to (16.78 at 1 kyr
    # is 1.678 at 10 kyr): none without its age.
    summary = summary_of(page)
    for age in result["ages"]:
        term = f"Hazard × for P = 5 % at {js_fmt(age['age_years'])} yr"
        if summary.get(term) != js_fmt(age["rate_scale_at_5_percent"]):
            raise Failure(f"the summary does not give the rate scale {age['rate_scale_at_5_percent']} at "
                          f"{age['age_years']} yr: {summary}")
    ageless = [k for k in summary if "Hazard" in k and not re.search(r" at [0-9.]+ yr$", k)]
    if ageless:
        raise Failure(f"a rate scale is given without its age: {ageless}")
    page.screenshot(os.path.join(OUT, "page-survival.png"))
    page.click("input[name=kind][value=time_history]")


def problem_shown(page):
    return page.js("document.getElementById('problem').hidden ? '' : document.getElementById('problem').innerText")


def check_switches_clear(page):
    """Switching how the block is given, or the kind, leaves nothing behind:
    the error box of the submission before goes; a restitution typed for
    the block as it was given is emptied (the hint says the default that
    applies); another kind's result goes from the panel."""
    page.click("input[name=kind][value=time_history]")
    if page.js("document.getElementById('result').hidden"):
        raise Failure("no result is shown before the switches")
    page.type_into("#f-alpha", "2")
    page.click("#submit")
    page.wait_js("the refusal", "!document.getElementById('problem').hidden", 10)
    page.click("input[name=block-by][value=geometry]")
    if problem_shown(page):
        raise Failure(f"the error box stays after switching to b and h: {problem_shown(page)!r}")
    if page.js("document.getElementById('f-eta').value") != "":
        raise Failure("the restitution typed for α and p stays for the block given by b and h")
    hint = page.js("document.getElementById('block-hint').textContent")
    if "η = 1 − 1.5 sin²α = " not in hint or "(the default: none given)" not in hint:
        raise Failure(f"the hint does not say which restitution applies: {hint!r}")
    page.click("input[name=block-by][value=params]")
    page.type_into("#f-eta", "0.9")
    page.click("#submit")
    page.wait_js("the refusal", "!document.getElementById('problem').hidden", 10)
    page.click("input[name=kind][value=spectrum]")
    if problem_shown(page):
        raise Failure(f"the error box stays after switching the kind: {problem_shown(page)!r}")
    state = page.js("['result', 'job', 'empty'].map((id) => document.getElementById(id).hidden).concat([location.hash])")
    if state != [True, True, False, ""]:
        raise Failure(f"the time history's result stays beside the spectrum's form (result, job, empty hidden; hash): {state}")
    page.click("input[name=kind][value=time_history]")
    page.type_into("#f-alpha", "0.25")


def write_point_reyes_record(work):
    """The record of specs/point_reyes_forensic_record.json (a 1 Hz one-sine
    pulse of PGA 0.5 g) as a JSON file to upload."""
    with open(os.path.join(ROOT, "specs", "point_reyes_forensic_record.json")) as f:
        motion = json.load(f)["ground_motion"]
    path = os.path.join(work, "point_reyes_1hz.json")
    with open(path, "w") as f:
        json.dump(dict(motion, name="point_reyes_1hz"), f)
    return path


def check_forensic_intervals(page, base, work):
    """The Point Reyes observations on a record whose answer is two separate
    intervals of scale: the page says two, not one range. Then, the
    locomotive given by b and h instead: the example's η = 0.9 is not sent
    with the new block (the service's default is, and the hint says which),
    the error box of the submission before is gone, and the body sent holds
    the values in sight only."""
    page.click("input[name=kind][value=forensic]")
    page.click("input[name=fo-by][value=record]")
    page.set_files("#f-rec-file", [write_point_reyes_record(work)])
    wait_preview(page, "the Point Reyes record", "point_reyes_1hz.json")
    while page.js("document.querySelectorAll('#obs-list .obs').length") > 2:
        page.click("#obs-list .obs:last-child .obs-remove")
    page.type_into("#f-fo-sfrom", "0.05")
    page.type_into("#f-fo-sto", "3")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query on the Point Reyes record")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if len(result["consistent_scale"]) < 2:
        raise Failure(f"the Point Reyes record was expected to give separate intervals: {result['consistent_scale']}")
    check_forensic_answer(page, base, job_id, result)
    page.screenshot(os.path.join(OUT, "page-forensic-intervals.png"))

    # An error box from a submission: a range the service refuses.
    page.type_into("#f-fo-sto", "500")
    page.click("#submit")
    page.wait_js("the refusal of PGA 500 g", "!document.getElementById('problem').hidden", 10)
    first = "#obs-list .obs:first-child"
    if page.js(f"document.querySelector('{first} .obs-eta').value") != "0.9":
        raise Failure("the example's locomotive has no η = 0.9")
    page.choose(f"{first} .obs-by", "geometry")
    if problem_shown(page):
        raise Failure(f"the error box stays after the block description was switched: {problem_shown(page)!r}")
    if page.js(f"document.querySelector('{first} .obs-eta').value") != "":
        raise Failure("the η of the block given by α and p stays for the block given by b and h")
    page.type_into(f"{first} .obs-b", "0.2")
    page.type_into(f"{first} .obs-h", "0.8")
    housner = 1 - 1.5 * math.sin(math.atan2(0.2, 0.8)) ** 2
    hint = page.js(f"document.querySelector('{first} .hint').textContent")
    if f"η = 1 − 1.5 sin²α = {js_fmt(housner)} (the default: none given)" not in hint:
        raise Failure(f"the card does not say which η applies ({housner}): {hint!r}")
    page.type_into("#f-fo-sto", "3")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query with the locomotive given by b and h")
    sent = page.last_submission()["observations"][0]
    if sent != {"name": "locomotive", "block": {"b": 0.2, "h": 0.8}, "overturned": True}:
        raise Failure(f"the observation switched to b and h was sent as {sent}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    eta = result["observations"][0]["block"]["eta"]
    if abs(eta - housner) > 1e-9:
        raise Failure(f"the locomotive given by b and h ran with η = {eta}, not the default {housner}")
    check_forensic_answer(page, base, job_id, result)
    page.choose(f"{first} .obs-by", "params")
    page.type_into(f"{first} .obs-eta", "0.9")
    page.click("input[name=fo-by][value=pulse]")
    page.click("input[name=kind][value=time_history]")


def check_fragility_geometry(page, base):
    """A fragility of blocks of uncertain half-width b and half-height h:
    the form sends b and h as the truncated normals its hint states (and
    no α or p); the job runs; the summary gives every number with its
    intensity measure."""
    page.click("input[name=kind][value=fragility]")
    page.click("input[name=fg-by][value=pulse]")
    page.click("input[name=fg-block-by][value=geometry]")
    hidden = page.js("['fg-params', 'fg-geometry', 'fg-pulse-axes'].map((id) => !!document.getElementById(id).closest('[hidden]'))")
    if hidden != [True, False, False]:
        raise Failure(f"a fragility by b and h shows the wrong fields (hidden: {hidden})")
    page.type_into("#f-fg-b", "0.6")
    page.type_into("#f-fg-b-sd", "0.06")
    page.type_into("#f-fg-h", "1.5")
    page.type_into("#f-fg-h-sd", "0.1")
    page.type_into("#f-fg-from", "0.3")
    page.type_into("#f-fg-to", "1.5")
    page.type_into("#f-fg-steps", "3")
    page.type_into("#f-fg-samples", "8")
    hint = page.js("document.getElementById('fg-block-hint').textContent")
    if "b normal (mean 0.6, sd 0.06) m on [0.42, 0.78]" not in hint or "h normal (mean 1.5, sd 0.1) m on [1.2, 1.8]" not in hint:
        raise Failure(f"the hint does not state the distributions sent: {hint!r}")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "fragility by b and h")
    log(f"fragility by b and h {job_id}")
    block = page.last_submission()["block"]
    want = {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.42, "max": 0.78},
            "h": {"dist": "normal", "mean": 1.5, "sd": 0.1, "min": 1.2, "max": 1.8}}
    if block != want:
        raise Failure(f"the fragility's uncertain block was sent as {block}, not {want}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if [s["n"] for s in result["stripes"]] != [8, 8, 8]:
        raise Failure(f"the fragility by b and h: {result['stripes']}")
    summary = summary_of(page)
    if summary.get("Stripes (PGA, g)") != "3: 0.3 – 1.5, 8 simulations each":
        raise Failure(f"the fragility summary: {summary}")
    top = max(result["stripes"], key=lambda x: x["p"])
    if not summary.get("Highest P(topple)", "").endswith(f"at PGA {js_fmt(top['im'])} g"):
        raise Failure(f"the highest probability is not given with its stripe {top['im']} g: {summary}")
    page.screenshot(os.path.join(OUT, "page-fragility-geometry.png"))
    # Under ü_v = −0.5 ü_g: the ratio is sent as typed, and the samples whose
    # ground falls away faster than g (from 2 g) are named in the summary.
    page.type_into("#f-vr", "-0.5")
    page.type_into("#f-fg-to", "3")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "fragility under a vertical ratio")
    sent = page.last_submission()
    if sent.get("vertical") != {"ratio": -0.5}:
        raise Failure(f"the vertical ratio was sent as {sent.get('vertical')!r}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    lifted = sum(s.get("lift_off", 0) for s in result["stripes"])
    summary = summary_of(page)
    if lifted and "Lift-off (no verdict)" not in summary:
        raise Failure(f"{lifted} lift-offs, not in the summary: {summary}")
    log(f"fragility under ü_v = -0.5 ü_g {job_id}: {lifted} lift-offs")
    page.type_into("#f-vr", "")
    page.type_into("#f-fg-to", "1.5")
    page.click("input[name=fg-block-by][value=params]")
    page.click("input[name=kind][value=time_history]")


def check_jobs_list(page, base, forensic_id):
    """"Your jobs": the service's listing of this user's jobs, newest first;
    a click on an older one opens it — its status, summary and figure."""
    page.click("#jobs-refresh")
    api = json.loads(http_get(f"{base}/v1/jobs?limit=500")[2])["jobs"]
    created = [j["created_at"] for j in api]
    if created != sorted(created, reverse=True):
        raise Failure(f"the service does not list the jobs newest first: {created}")
    want = [j["id"] for j in api[:20]]
    page.wait_js("the list of jobs",
                 f"[...document.querySelectorAll('#jobs-list .job-row')].map((r) => r.dataset.id).join() === {json.dumps(','.join(want))}",
                 10)
    statuses = page.js("[...document.querySelectorAll('#jobs-list .job-row .badge')].map((b) => b.textContent)")
    if statuses != [j["status"] for j in api[:20]]:
        raise Failure(f"the list's statuses {statuses} are not the service's")
    if forensic_id not in want[1:]:
        raise Failure(f"the forensic query {forensic_id} is not among the older jobs listed")
    page.click(f"#jobs-list .job-row[data-id='{forensic_id}']")
    page.wait_js("the forensic query to open",
                 f"document.getElementById('job-id').textContent === {json.dumps(forensic_id)}"
                 " && document.getElementById('status').textContent === 'succeeded'", 10)
    wait_plot(page, "forensic query opened from the list")
    src = page.js("document.getElementById('plot').getAttribute('src')")
    if src != f"/v1/jobs/{forensic_id}/plot.svg":
        raise Failure(f"the job opened shows the plot {src!r}")
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    result = json.loads(http_get(f"{base}/v1/jobs/{forensic_id}/result")[2])
    check_forensic_answer(page, base, forensic_id, result)
    if not page.js("document.getElementById('job-kind').textContent").startswith("forensic query, submitted "):
        raise Failure("the job opened does not say its kind")
    if page.js(f"document.querySelector(\"#jobs-list .job-row[data-id='{forensic_id}']\").getAttribute('aria-current')") != "true":
        raise Failure("the job opened is not marked in the list")
    page.screenshot(os.path.join(OUT, "page-jobs.png"))


def check_mavroeidis_papageorgiou_inputs(page):
    """γ and ν appear for the Mavroeidis–Papageorgiou pulse only and reach the spec."""
    page.click("input[name=kind][value=time_history]")
    if not page.js("document.getElementById('mp-fields').hidden"):
        raise Failure("γ and ν are offered for a one-sine pulse")
    page.choose("#f-type", "mavroeidis_papageorgiou")
    if page.js("document.getElementById('mp-fields').hidden"):
        raise Failure("γ and ν are not offered for the Mavroeidis–Papageorgiou pulse")
    page.type_into("#f-gamma", "2.5")
    page.type_into("#f-nu", "1.2")
    page.click("#show-json")
    pulse = json.loads(page.js("document.getElementById('f-raw').value"))["pulse"]
    if pulse.get("type") != "mavroeidis_papageorgiou" or pulse.get("gamma") != 2.5 or pulse.get("nu") != 1.2:
        raise Failure(f"the form's MP pulse is {pulse}")
    page.click("input[name=kind][value=time_history]")
    page.choose("#f-type", "one_sine")


def check_cancel(page, base):
    page.click("input[name=kind][value=spectrum]")
    page.type_into("#f-sp-steps", "2000")
    page.click("#submit")
    page.wait_js(
        "a new job to be queued or running",
        "(() => { const s = document.getElementById('status').textContent;"
        " return (s === 'queued' || s === 'running') && !document.getElementById('cancel').hidden; })()",
        10)
    job_id = page.js("document.getElementById('job-id').textContent")
    # The page follows the job through its event stream, not by polling.
    page.wait_js("the page to follow the job's events",
                 "document.getElementById('job').dataset.follow === 'events'", 10)
    page.wait_js("progress to arrive through the events",
                 "parseFloat(document.getElementById('progress').value) > 0", 20)
    log(f"spectrum {job_id}: cancel")
    page.click("#cancel")
    page.wait_js("the job to show as canceled",
                 "document.getElementById('status').textContent === 'canceled'", 10)
    status, _, body = http_get(f"{base}/v1/jobs/{job_id}")
    if status != 200 or json.loads(body)["status"] != "canceled":
        raise Failure(f"the service says {status} {body[:200]!r} after Cancel")
    page.screenshot(os.path.join(OUT, "page-cancel.png"))


def check_token(page, base):
    """Against a service that wants its token for reads too."""
    page.navigate(base + "/")
    page.wait_js("the form", "!!document.getElementById('submit')", 10)
    page.wait_js("the token box to open by itself",
                 "document.getElementById('token-box').open", 10)
    page.wait_js("the list of jobs to ask for the token",
                 "document.getElementById('jobs-list').textContent.includes('needs the API token')", 10)
    page.click("#submit")
    page.wait_js("the error to be shown", "!document.getElementById('problem').hidden", 10)
    text = page.js("document.getElementById('problem').innerText")
    if "401" not in text or "API token" not in text:
        raise Failure(f"the missing token is not explained: {text!r}")
    if not page.js("document.getElementById('token-box').open"):
        raise Failure("the token field is not opened")
    page.type_into("#f-token", TOKEN)
    page.click("#submit")
    loaded = page.wait_js(
        "the plot to load with the token",
        "(() => { const img = document.getElementById('plot');"
        " if (img && img.complete && img.naturalWidth > 0) return img.getAttribute('src');"
        " const problem = document.getElementById('problem');"
        " return !problem.hidden && 'error: ' + problem.innerText; })()",
        PLOT_TIMEOUT)
    if not loaded.startswith("data:image/svg+xml"):
        raise Failure(f"with the token, the plot did not load: {loaded[:200]!r}")
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    job_id = page.js("document.getElementById('job-id').textContent")
    page.wait_js("the job listed with the token",
                 "(() => { const r = document.querySelector('#jobs-list .job-row');"
                 f" return !!r && r.dataset.id === {json.dumps(job_id)}; }})()", 10)


TOKEN = "e2e-token"


def main():
    # A TERM (a CI timeout, say) still stops the server and the browser.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    os.makedirs(OUT, exist_ok=True)
    for name in ("page.png", "page-error.png", "page-forensic.png", "page-cancel.png", "failure.png",
                 "page-record-preview.png", "page-record-ask.png", "page-record-error.png",
                 "page-record-spectrum.png", "page-record-spectrum-figure.png", "page-forensic-record.png",
                 "page-time-history-record.png", "page-fragility-suite.png", "page-survival.png",
                 "page-forensic-intervals.png", "page-fragility-geometry.png", "page-jobs.png",
                 "page-forensic-coulomb.png", "page-docs.png"):
        try:
            os.remove(os.path.join(OUT, name))
        except FileNotFoundError:
            pass
    if not os.access(BIN, os.X_OK):
        log(f"not an executable: {BIN} (set TOPPLE_BIN)")
        return 1
    if not os.access(CHROMIUM, os.X_OK):
        log(f"not an executable: {CHROMIUM} (set CHROMIUM)")
        return 1
    started = time.monotonic()
    work = tempfile.mkdtemp(prefix="topple-e2e.")
    server, chromium, page = Server(work, "open"), Chromium(work), None
    guarded = Server(work, "guarded", "--api-token", TOKEN, "--auth-reads")
    ok = False
    try:
        server.start()
        log(f"server {BIN} at {server.base}")
        check_served(server.base)
        page = Page(chromium.start())
        for domain in ("Page", "Runtime", "Log", "Network"):
            page.send(f"{domain}.enable")
        page.send("Page.addScriptToEvaluateOnNewDocument", source=REPORT_VIOLATIONS_JS)
        page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)
        page.navigate(server.base + "/")
        page.wait_js("the form", "!!document.getElementById('submit')", 10)
        check_policy_enforced(page)
        check_submit_in_sight(page)
        check_invalid_field(page)
        check_time_history(page, server.base)
        check_survivor(page, server.base)
        check_switches_clear(page)
        forensic_id = check_forensic(page, server.base)
        check_forensic_coulomb(page, server.base)
        check_floor_kinds(page, server.base, work)
        record = check_record_spectrum(page, server.base, work)
        check_forensic_record(page, server.base, record)
        check_time_history_record(page, server.base, record)
        other = check_record_questions(page, server.base, work, record)
        check_fragility_suite(page, server.base, [record["id"], other])
        check_forensic_intervals(page, server.base, work)
        check_fragility_geometry(page, server.base)
        check_mavroeidis_papageorgiou_inputs(page)
        check_survival(page, server.base)
        check_cancel(page, server.base)
        check_jobs_list(page, server.base, forensic_id)
        guarded.start()
        log(f"server with a token at {guarded.base}")
        check_reference(page, server.base, guarded.base)
        check_token(page, guarded.base)
        page.pump()
        if page.problems:
            raise Failure("the browser reported:\n  " + "\n  ".join(page.problems))
        ok = True
    except (Failure, OSError, websocket.WebSocketException) as e:
        log(f"FAILED: {e}")
        if page is not None:
            try:
                page.screenshot(os.path.join(OUT, "failure.png"))
                if page.problems:
                    log("the browser reported:\n  " + "\n  ".join(page.problems))
            except Exception as shot_error:
                log(f"no failure screenshot: {shot_error}")
        for s in (server, guarded):
            tail = s.log()[-3000:]
            if tail:
                log(f"server log ({s.name}, tail):\n" + tail)
    finally:
        if page is not None:
            page.close()
        chromium.stop()
        server.stop()
        guarded.stop()
        shutil.rmtree(work, ignore_errors=True)
    elapsed = time.monotonic() - started
    if ok:
        log(f"all checks passed in {elapsed:.1f} s")
        print("1 passed, 0 failed")
        return 0
    print("0 passed, 1 failed")
    return 1


if __name__ == "__main__":
    sys.exit(main())
