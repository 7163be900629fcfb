#!/usr/bin/env python3
"""End-to-end test of the web page at `/` in headless Chromium.

Starts `topple serve` (SQLite in a temporary directory) and Chromium with the
DevTools protocol, then drives the page as a user would, with real mouse
clicks and typed text:

1. the page is served as HTML with a Content-Security-Policy;
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
   at 3 s, that it had not come to rest;
6. a forensic query filled in on the form (the Point Reyes observations and a
   third one added, given by half-width and half-height) is the JSON the raw
   editor shows, runs on those observations and frequencies, shows its plot
   and the bounds of the result;
7. a long overturning spectrum is submitted and canceled with the Cancel
   button; the service reports it canceled;
8. against a second server that wants a token for reads too
   (`--api-token`, `--auth-reads`): the token box opens by itself, the 401
   of a submission without it is explained, and once the token
   is filled in the job runs and its plot loads (fetched with the token);
9. nothing was blocked by the policy and no script error occurred.

Screenshots go to target/e2e/ (page.png: the finished time history;
page-error.png, page-forensic.png, page-cancel.png; failure.png when a step
fails).

Environment: TOPPLE_BIN (default target/debug/topple), CHROMIUM (default
/usr/bin/chromium), E2E_OUT (default target/e2e), E2E_TIMEOUT (seconds the
time history may take, default 60).

Exit status 0 when every check passes, 1 otherwise.
"""

import base64
import json
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
    for directive in ("default-src 'self'", "connect-src 'self'", "script-src"):
        if directive not in csp:
            raise Failure(f"the Content-Security-Policy lacks {directive!r}: {csp!r}")
    if b"<script" not in body or b"src=\"http" in body or b"href=\"http" in body:
        raise Failure("the page is not self-contained")


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
    # Its warning (the friction demand stops at the pulse end) is in sight.
    kinds = page.js("[...document.querySelectorAll('#warnings li')].map((li) => li.dataset.kind)")
    if kinds != [w["kind"] for w in result["warnings"]] or "demand_excludes_fall" not in kinds:
        raise Failure(f"the warnings shown {kinds} are not the result's {result['warnings']}")
    if page.js("document.getElementById('warnings').hidden"):
        raise Failure("the warnings are hidden")
    page.screenshot(os.path.join(OUT, "page.png"))


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
    outcome = page.js("document.getElementById('outcome').textContent")
    bounds = result["bounds"]
    m = re.match(r"Consistent with every observation: a_p = ([0-9.]+) – ([0-9.]+) g at ", outcome)
    if not m or abs(float(m.group(1)) - bounds["min_g"]) > 5e-4 or abs(float(m.group(2)) - bounds["max_g"]) > 5e-4:
        raise Failure(f"the outcome does not give the bounds {bounds}: {outcome!r}")
    if summary_of(page).get("Observations") != "1 toppled, 2 stood":
        raise Failure(f"the forensic summary: {summary_of(page)}")
    page.screenshot(os.path.join(OUT, "page-forensic.png"))


def check_record_spectrum(page, base):
    """A record spectrum from the form: the example record (a one-sine pulse
    of 0.5 g at 1 Hz, 101 samples), block sizes by R, a figure and a summary
    that agree with the result."""
    page.click("input[name=kind][value=record_spectrum]")
    if not page.js("document.getElementById('fs-pulse').querySelector('#f-type').closest('[data-kinds]').hidden"):
        raise Failure("the pulse type is offered for a record spectrum")
    hint = page.js("document.getElementById('rs-hint').textContent")
    if hint != "101 samples over 1 s, PGA 0.5 g.":
        raise Failure(f"the record is not described: {hint!r}")
    page.type_into("#f-rs-steps", "4")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    acc = raw["ground_motion"].pop("acc")
    expected = {"kind": "record_spectrum", "ground_motion": {"dt": 0.01, "unit": "g"},
                "block": {"alpha": 0.2}, "R_m": {"from": 0.2, "to": 2, "steps": 4},
                "scale": {"to": 3}, "formulation": "nonlinear"}
    if raw != expected or len(acc) != 101 or abs(max(acc) - 0.5) > 1e-9:
        raise Failure(f"the form's record spectrum is {raw} with {len(acc)} samples, not {expected}")
    page.click("input[name=kind][value=record_spectrum]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "record spectrum")
    log(f"record spectrum {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    sizes = [round(s["R_m"], 9) for s in result["spectrum"]]
    if sizes != [0.2, 0.8, 1.4, 2.0]:
        raise Failure(f"the record spectrum's sizes: {sizes}")
    toppled = [s for s in result["spectrum"] if s["min_overturn_scale"] is not None]
    outcome = page.js("document.getElementById('outcome').textContent")
    if toppled:
        lowest = min(toppled, key=lambda s: s["min_overturn_scale"])
        m = re.match(r"Lowest overturning scale ([0-9.]+) \(PGA ([0-9.]+) g\), for R = ([0-9.]+) m", outcome)
        if not m or abs(float(m.group(1)) - lowest["min_overturn_scale"]) > 5e-4 * lowest["min_overturn_scale"]:
            raise Failure(f"the outcome does not give the lowest scale {lowest['min_overturn_scale']}: {outcome!r}")
    elif not outcome.startswith("No block size overturns"):
        raise Failure(f"the outcome of a record spectrum without overturning: {outcome!r}")
    summary = summary_of(page)
    if summary.get("Record") != "101 samples, dt = 0.01 s":
        raise Failure(f"the record spectrum summary: {summary}")
    page.screenshot(os.path.join(OUT, "page-record-spectrum.png"))
    page.click("input[name=kind][value=time_history]")


def check_forensic_record(page, base):
    """A forensic query on a record from the form: the observations of the
    pulse query, the record of the record spectrum (a one-sine pulse of 0.5 g
    at 1 Hz), the scale axis as PGA; the summary and outcome agree with the
    result; back to pulses, the pulse's fields return."""
    page.click("input[name=kind][value=forensic]")
    page.click("input[name=fo-by][value=record]")
    hidden = page.js("['f-type', 'fo-pulse-axes', 'fo-record-axes', 'fs-motion'].map((id) =>"
                     " !!document.getElementById(id).closest('[hidden]'))")
    if hidden != [True, True, False, False]:
        raise Failure(f"on a record the form shows the wrong fields (hidden: {hidden})")
    page.click("#show-json")
    raw = json.loads(page.js("document.getElementById('f-raw').value"))
    acc = raw["ground_motion"].pop("acc")
    observations = raw.pop("observations")
    expected = {"kind": "forensic", "ground_motion": {"dt": 0.01, "unit": "g"},
                "pga_g": {"from": 0.05, "to": 3}, "formulation": "nonlinear"}
    if raw != expected or len(acc) != 101 or [o["name"] for o in observations][:2] != ["locomotive", "transformer"]:
        raise Failure(f"the form's record query is {raw}, not {expected}")
    page.click("input[name=kind][value=forensic]")
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    job_id = finished_job(page, before, "forensic query on a record")
    log(f"forensic query on a record {job_id}")
    result = json.loads(http_get(f"{base}/v1/jobs/{job_id}/result")[2])
    if result["excitation"] != "ground_motion" or result["frequencies"]:
        raise Failure(f"not a record query: {result['excitation']}, {len(result['frequencies'])} frequencies")
    outcome = page.js("document.getElementById('outcome').textContent")
    bounds = result["bounds"]
    if bounds["min_scale"] is None:
        if not outcome.startswith("No scale of the record"):
            raise Failure(f"the outcome of a record query without answer: {outcome!r}")
    else:
        m = re.match(r"Consistent with every observation: scale ([0-9.]+) – ([0-9.]+) \(PGA ([0-9.]+) – ([0-9.]+) g\)", outcome)
        if (not m or abs(float(m.group(1)) - bounds["min_scale"]) > 5e-4 * bounds["min_scale"]
                or abs(float(m.group(4)) - bounds["max_g"]) > 5e-4 * bounds["max_g"]):
            raise Failure(f"the outcome does not give the bounds {bounds}: {outcome!r}")
    summary = summary_of(page)
    if summary.get("Record") != "101 samples, dt = 0.01 s, PGA 0.5 g":
        raise Failure(f"the record query's summary: {summary}")
    src = page.js("document.getElementById('plot').getAttribute('src')")
    if src != f"/v1/jobs/{job_id}/plot.svg":
        raise Failure(f"the record query's plot comes from {src!r}")
    page.screenshot(os.path.join(OUT, "page-forensic-record.png"))
    page.click("input[name=fo-by][value=pulse]")
    if page.js("!!document.getElementById('f-type').closest('[hidden]')"):
        raise Failure("back on pulses, the pulse type stays hidden")
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
    page.screenshot(os.path.join(OUT, "page-survival.png"))
    page.click("input[name=kind][value=time_history]")


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


TOKEN = "e2e-token"


def main():
    # A TERM (a CI timeout, say) still stops the server and the browser.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    os.makedirs(OUT, exist_ok=True)
    for name in ("page.png", "page-error.png", "page-forensic.png", "page-cancel.png", "failure.png"):
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
        for domain in ("Page", "Runtime", "Log"):
            page.send(f"{domain}.enable")
        page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)
        page.navigate(server.base + "/")
        page.wait_js("the form", "!!document.getElementById('submit')", 10)
        check_submit_in_sight(page)
        check_invalid_field(page)
        check_time_history(page, server.base)
        check_survivor(page, server.base)
        check_forensic(page, server.base)
        check_record_spectrum(page, server.base)
        check_forensic_record(page, server.base)
        check_mavroeidis_papageorgiou_inputs(page)
        check_survival(page, server.base)
        check_cancel(page, server.base)
        guarded.start()
        log(f"server with a token at {guarded.base}")
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
