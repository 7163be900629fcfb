#!/usr/bin/env python3
"""Screenshots of the web page for the documentation (run by docs/screenshots.sh).

Starts `topple serve` (SQLite in a temporary directory) and headless
Chromium in a 1400×1000 window, fills the form as a user would and submits:

- page-time-history.png: the locomotive of specs/locomotive_nonlinear.json
  (α = 0.25, p = 2.14 rad/s, η = 0.9, μ = 0.7; one-sine pulse, ω_p = 15.7 rad/s,
  a_p = 2.25 g), which overturns;
- page-plot-enlarged.png: its plot, clicked to enlarge;
- page-spectrum.png: the overturning spectrum of the same block
  (ω_p/p from 0.25 to 10, 40 steps, up to 20 αg);
- page-forensic.png: the forensic query of specs/point_reyes_forensic.json
  (the locomotive toppled, the transformer stood; 0.25–3 Hz, 0.05–3 g);
- page-forensic-record.png: the same observations on the record of
  specs/point_reyes_forensic_record.json (uploaded as a file), whose answer
  is two separate intervals of scale;
- page-fragility.png: the fragility of specs/pbr_fragility.json (b and h
  uncertain, one-sine pulses of lognormal frequency; 15 stripes of 200);
- page-survival.png: the survival job of specs/survival_power_law.json;
- page-jobs.png: "Your jobs" listing the jobs above newest first, the
  first time history opened from it: what the window shows, scrolled down
  to the list.

The others are what the window shows, scrolled to the top.

Environment: TOPPLE_BIN (default target/debug/topple), CHROMIUM (default
/usr/bin/chromium), SCREENSHOTS_OUT (default docs/book/src/figures/), E2E_TIMEOUT (seconds a
job may take, default 60).

Exit status 0 when every screenshot was taken, 1 otherwise.
"""

import base64
import os
import shutil
import signal
import sys
import tempfile

import websocket

import page_test as e2e
from page_test import Chromium, Failure, Page, Server, log

WIDTH, HEIGHT = 1400, 1000
OUT = os.path.abspath(os.environ.get("SCREENSHOTS_OUT", os.path.join(e2e.ROOT, "docs", "book", "src", "figures")))


def submit(page, what):
    """Submits the form; waits for the job to succeed, its plot to load and
    its summary to show. Returns the job's id."""
    before = page.js("document.getElementById('job-id').textContent")
    page.click("#submit")
    page.wait_js(f"the {what} to be accepted",
                 f"document.getElementById('job-id').textContent !== {before!r}", 10)
    job_id = page.js("document.getElementById('job-id').textContent")
    status = page.wait_js(
        f"the {what} to finish",
        "(() => { const s = document.getElementById('status').textContent;"
        " return ['succeeded', 'failed', 'canceled'].includes(s) && s; })()",
        e2e.PLOT_TIMEOUT)
    if status != "succeeded":
        raise Failure(f"the {what} {status}: {page.js('document.body.innerText')[:2000]}")
    e2e.wait_plot(page, what)
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    log(f"{what} {job_id}")
    return job_id


def time_history(page):
    page.click("input[name=kind][value=time_history]")
    page.click("input[name=block-by][value=params]")
    for selector, value in (("#f-alpha", "0.25"), ("#f-p", "2.14"), ("#f-eta", "0.9"), ("#f-mu", "0.7")):
        page.type_into(selector, value)
    page.choose("#f-type", "one_sine")
    page.choose("#f-formulation", "nonlinear")
    page.choose("#f-freq-unit", "omega_p")
    page.type_into("#f-freq", "15.7")
    page.choose("#f-amp-unit", "a_p_g")
    page.type_into("#f-amp", "2.25")
    page.type_into("#f-series", "400")
    submit(page, "time history")
    page.window_screenshot(os.path.join(OUT, "page-time-history.png"))
    page.click("#plot")
    page.wait_js("the enlarged plot",
                 "document.getElementById('zoom').open && document.getElementById('zoom-img').naturalWidth > 0", 10)
    page.window_screenshot(os.path.join(OUT, "page-plot-enlarged.png"))
    page.js("document.getElementById('zoom').close()")


def spectrum(page):
    page.click("input[name=kind][value=spectrum]")
    page.type_into("#f-mu", "")  # specs/locomotive_spectrum_nonlinear.json has no μ
    for selector, value in (("#f-sp-from", "0.25"), ("#f-sp-to", "10"), ("#f-sp-steps", "40"),
                            ("#f-sp-amax", "20"), ("#f-sp-tol", "0.0001")):
        page.type_into(selector, value)
    submit(page, "spectrum")
    page.window_screenshot(os.path.join(OUT, "page-spectrum.png"))


def forensic(page):
    page.click("input[name=kind][value=forensic]")
    submit(page, "forensic query")
    page.window_screenshot(os.path.join(OUT, "page-forensic.png"))


def forensic_record(page, work):
    page.click("input[name=kind][value=forensic]")
    page.click("input[name=fo-by][value=record]")
    path = e2e.write_point_reyes_record(work)
    page.set_files("#f-rec-file", [path])
    e2e.wait_preview(page, "the Point Reyes record", os.path.basename(path))
    page.type_into("#f-fo-sfrom", "0.05")
    page.type_into("#f-fo-sto", "3")
    submit(page, "forensic query on a record")
    page.window_screenshot(os.path.join(OUT, "page-forensic-record.png"))
    page.click("input[name=fo-by][value=pulse]")


def fragility(page):
    page.click("input[name=kind][value=fragility]")
    page.click("input[name=fg-block-by][value=geometry]")
    for selector, value in (("#f-fg-b", "0.6"), ("#f-fg-b-sd", "0.06"), ("#f-fg-h", "1.5"), ("#f-fg-h-sd", "0.1"),
                            ("#f-fg-hz", "1"), ("#f-fg-hz-beta", "0.4"), ("#f-fg-from", "0.1"), ("#f-fg-to", "1.5"),
                            ("#f-fg-steps", "15"), ("#f-fg-samples", "200"), ("#f-fg-seed", "42")):
        page.type_into(selector, value)
    submit(page, "fragility")
    page.window_screenshot(os.path.join(OUT, "page-fragility.png"))


def survival(page):
    page.click("input[name=kind][value=survival]")
    submit(page, "survival")
    page.window_screenshot(os.path.join(OUT, "page-survival.png"))


def jobs(page):
    page.click("input[name=kind][value=time_history]")
    page.click("#jobs-list .job-row:last-child")
    e2e.wait_plot(page, "time history opened from the list")
    page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
    # The window scrolled down to the list, the job's summary above it.
    page.js("document.getElementById('jobs-title').closest('.panel').scrollIntoView({block: 'end'})")
    shot = page.send("Page.captureScreenshot", format="png")
    path = os.path.join(OUT, "page-jobs.png")
    with open(path, "wb") as f:
        f.write(base64.b64decode(shot["data"]))
    log(f"screenshot {os.path.relpath(path, e2e.ROOT)}")


def main():
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    os.makedirs(OUT, exist_ok=True)
    work = tempfile.mkdtemp(prefix="topple-screenshots.")
    server, chromium, page = Server(work, "docs"), Chromium(work), None
    ok = False
    try:
        server.start()
        log(f"server {e2e.BIN} at {server.base}")
        page = Page(chromium.start())
        for domain in ("Page", "Runtime", "Log"):
            page.send(f"{domain}.enable")
        page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)
        page.navigate(server.base + "/")
        page.wait_js("the form", "!!document.getElementById('submit')", 10)
        time_history(page)
        spectrum(page)
        forensic(page)
        forensic_record(page, work)
        fragility(page)
        survival(page)
        jobs(page)
        page.pump()
        if page.problems:
            raise Failure("the browser reported:\n  " + "\n  ".join(page.problems))
        ok = True
    except (Failure, OSError, websocket.WebSocketException) as e:
        log(f"FAILED: {e}")
        tail = server.log()[-3000:]
        if tail:
            log("server log (tail):\n" + tail)
    finally:
        if page is not None:
            page.close()
        chromium.stop()
        server.stop()
        shutil.rmtree(work, ignore_errors=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
