#!/usr/bin/env python3
"""The page's look, as PNGs to compare pixel by pixel between two builds.

    look.py shoot OUT      # screenshots of the page served by $TOPPLE_BIN into OUT
    look.py compare A B    # the PNGs of A and B, pixel by pixel; exit 1 if any differs

`shoot` starts `topple serve` (SQLite in a temporary directory) and headless
Chromium at 1400×1000, then takes the whole page (up to 4000 px tall):

- form-<kind>.png: the form of each kind offered, chosen in turn (and the
  raw JSON editor, filled from the time history's form);
- form-<variant>.png: a few choices within a form (a block by b and h, a
  Coulomb floor, a time history on a record, a forensic query on a record,
  a fragility on a suite, a Mavroeidis–Papageorgiou pulse);
- error.png: a refused slenderness, its field named and marked;
- result-time-history.png: the default time history, finished: outcome,
  warnings, summary, plot and "Your jobs".

What differs from one run to the next whatever the page (a job's id, the
time it was submitted, wall and compute times) is written over with fixed
text of the same length before a screenshot, the same in every run.

`compare` decodes each PNG (8-bit RGB or RGBA, as Chromium writes them) and
gives, for each file, "identical" or the box of the pixels that differ.

Environment: TOPPLE_BIN (default target/debug/topple), CHROMIUM (default
/usr/bin/chromium), E2E_TIMEOUT (seconds a job may take, default 60).
"""

import base64
import os
import shutil
import signal
import struct
import sys
import tempfile
import zlib

import page_test as e2e
from page_test import Chromium, Failure, Page, Server, log

WIDTH, HEIGHT = 1400, 1000

# Text that changes from run to run, written over with fixed text.
STEADY_JS = r"""(() => {
  const id = document.getElementById('job-id');
  if (id.textContent) id.textContent = '00000000-0000-0000-0000-000000000000';
  const kind = document.getElementById('job-kind');
  kind.textContent = kind.textContent.replace(/\d{4}-\d\d-\d\d \d\d:\d\d:\d\d/, '2000-01-01 00:00:00');
  for (const t of document.querySelectorAll('.job-t')) t.textContent = '2000-01-01 00:00:00 · …000000';
  for (const d of document.querySelectorAll('#summary div')) {
    if (/time/.test(d.querySelector('dt').textContent)) d.querySelector('dd').textContent = '0.1';
  }
  return true;
})()"""


def settle(page):
    """Waits for two animation frames: what was changed is drawn."""
    page.js("new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)))")


def shot(page, out, name):
    page.js(STEADY_JS)
    page.js("document.activeElement && document.activeElement.blur && document.activeElement.blur()")
    page.js("window.scrollTo(0, 0)")
    settle(page)
    size = page.send("Page.getLayoutMetrics")["cssContentSize"]
    data = page.send("Page.captureScreenshot", format="png", captureBeyondViewport=True,
                     clip={"x": 0, "y": 0, "width": size["width"],
                           "height": min(size["height"], 4000), "scale": 1})["data"]
    with open(os.path.join(out, name), "wb") as f:
        f.write(base64.b64decode(data))
    log(f"screenshot {name}")


def kinds(page):
    return page.js("[...document.querySelectorAll('input[name=kind]')].map((i) => i.value)")


def shoot(out, work):
    server, chromium, page = Server(work, "look"), Chromium(work), None
    try:
        server.start()
        page = Page(chromium.start())
        for domain in ("Page", "Runtime", "Log"):
            page.send(f"{domain}.enable")
        page.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)
        page.navigate(server.base + "/")
        page.wait_js("the form", "!!document.getElementById('submit')", 10)
        page.wait_js("the list of jobs", "document.getElementById('jobs-list').textContent !== ''", 10)
        shot(page, out, "first-sight.png")
        for kind in kinds(page):
            page.click(f"input[name=kind][value={kind}]")
            shot(page, out, f"form-{kind}.png")
        # Choices within a form.
        page.click("input[name=kind][value=time_history]")
        page.click("input[name=block-by][value=geometry]")
        shot(page, out, "form-time_history-geometry.png")
        page.click("input[name=block-by][value=params]")
        page.click("input[name=contact][value=coulomb]")
        shot(page, out, "form-time_history-coulomb.png")
        page.click("input[name=kind][value=forensic]")
        shot(page, out, "form-forensic-coulomb.png")
        page.click("input[name=contact][value=no_sliding]")
        page.click("input[name=fo-by][value=record]")
        shot(page, out, "form-forensic-record.png")
        page.click("input[name=fo-by][value=pulse]")
        page.click("input[name=kind][value=fragility]")
        page.click("input[name=fg-by][value=records]")
        page.click("input[name=fg-block-by][value=geometry]")
        shot(page, out, "form-fragility-suite.png")
        page.click("input[name=fg-by][value=pulse]")
        page.click("input[name=fg-block-by][value=params]")
        page.click("input[name=kind][value=time_history]")
        page.click("input[name=th-by][value=record]")
        shot(page, out, "form-time_history-record.png")
        page.click("input[name=th-by][value=pulse]")
        page.choose("#f-type", "mavroeidis_papageorgiou")
        page.choose("#f-vert", "ratio")
        shot(page, out, "form-time_history-mp.png")
        page.choose("#f-vert", "")
        page.choose("#f-type", "one_sine")
        # A refused slenderness.
        page.type_into("#f-alpha", "2")
        page.click("#submit")
        page.wait_js("the error", "!document.getElementById('problem').hidden", 10)
        shot(page, out, "error.png")
        page.type_into("#f-alpha", "0.25")
        # The default time history, finished.
        page.click("#submit")
        page.wait_js("the job", "/^[0-9a-f-]{36}$/.test(document.getElementById('job-id').textContent)", 10)
        status = page.wait_js(
            "the job to finish",
            "(() => { const s = document.getElementById('status').textContent;"
            " return ['succeeded', 'failed', 'canceled'].includes(s) && s; })()", e2e.PLOT_TIMEOUT)
        if status != "succeeded":
            raise Failure(f"the time history {status}")
        e2e.wait_plot(page, "time history")
        page.wait_js("the summary", "document.querySelectorAll('#summary dd').length > 0", 10)
        page.wait_js("the job listed", "document.querySelectorAll('#jobs-list .job-row .badge.succeeded').length === 1", 10)
        shot(page, out, "result-time-history.png")
        page.pump()
        if page.problems:
            raise Failure("the browser reported:\n  " + "\n  ".join(page.problems))
    finally:
        if page is not None:
            page.close()
        chromium.stop()
        server.stop()


# --- PNG ----------------------------------------------------------------------------


def pixels(path):
    """(width, height, rows of bytes) of an 8-bit, non-interlaced RGB(A) PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, head = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
    width, height, depth, colour, _, _, interlace = head
    if depth != 8 or colour not in (2, 6) or interlace:
        raise ValueError(f"{path}: depth {depth}, colour type {colour}, interlace {interlace}")
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        filt = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if filt == 1:
                line[i] = (line[i] + a) & 255
            elif filt == 2:
                line[i] = (line[i] + b) & 255
            elif filt == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif filt == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line) if bpp == 3 else bytes(v for k, v in enumerate(line) if k % 4 != 3))
        prev = line
    return width, height, rows


def difference(a, b):
    """None when the two PNGs have the same pixels, else what differs."""
    wa, ha, ra = pixels(a)
    wb, hb, rb = pixels(b)
    if (wa, ha) != (wb, hb):
        return f"size {wa}×{ha} against {wb}×{hb}"
    box = None
    for y, (la, lb) in enumerate(zip(ra, rb)):
        if la == lb:
            continue
        xs = [i // 3 for i in range(0, len(la), 3) if la[i:i + 3] != lb[i:i + 3]]
        x0, x1 = min(xs), max(xs)
        box = (x0, y, x1, y) if box is None else (min(box[0], x0), box[1], max(box[2], x1), y)
    return None if box is None else f"pixels differ in the box x {box[0]}–{box[2]}, y {box[1]}–{box[3]}"


def compare(a, b):
    names = sorted(set(os.listdir(a)) | set(os.listdir(b)))
    names = [n for n in names if n.endswith(".png")]
    bad = 0
    for name in names:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        if not (os.path.exists(pa) and os.path.exists(pb)):
            print(f"{name}: only in {a if os.path.exists(pa) else b}")
            bad += 1
            continue
        diff = difference(pa, pb)
        print(f"{name}: {diff or 'identical'}")
        bad += diff is not None
    print(f"{len(names) - bad} identical, {bad} different")
    return 1 if bad else 0


def main():
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    if len(sys.argv) == 4 and sys.argv[1] == "compare":
        return compare(sys.argv[2], sys.argv[3])
    if len(sys.argv) != 3 or sys.argv[1] != "shoot":
        print(__doc__, file=sys.stderr)
        return 2
    out = os.path.abspath(sys.argv[2])
    os.makedirs(out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="topple-look.")
    try:
        shoot(out, work)
    except (Failure, OSError) as e:
        log(f"FAILED: {e}")
        return 1
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
