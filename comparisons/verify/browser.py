"""The HTML report in a real browser: headless Chromium (Debian's ``chromium``) measures whether a page fits its
width and takes screenshots of it.  Used by the report's tests and by ``tools/report_screenshots.py``; nothing
in ``verify`` itself needs a browser.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile

TIMEOUT_S = 120
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--virtual-time-budget=10000")
# Written into a copy of the page: what the browser made of its layout, as JSON in a <pre> that --dump-dom prints.
PROBE = """<script>window.addEventListener('load', () => {
  const root = document.documentElement;
  const boxes = [...document.querySelectorAll('.scroll')];
  const r = {width: window.innerWidth, page_width: root.scrollWidth,
             scrolling_tables: boxes.filter(b => b.scrollWidth > b.clientWidth + 1).length,
             tables: document.querySelectorAll('table').length,
             narrowest_note: Math.min(...[...document.querySelectorAll('td.note')].map(c => c.clientWidth), 1e9)};
  const p = document.createElement('pre'); p.id = 'layout-probe'; p.textContent = JSON.stringify(r);
  document.body.appendChild(p);
});</script>"""


class BrowserError(RuntimeError):
    """No Chromium, or it did not render the page: the message says which in one line."""


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


def _run(args: list[str]) -> subprocess.CompletedProcess:
    program = chromium()
    if program is None:
        raise BrowserError("no Chromium here (Debian: apt-get install -y chromium)")
    # Chromium keeps its profile in a folder of its own: a fresh one per run, removed afterwards.
    with tempfile.TemporaryDirectory(prefix="shimmy-chromium-") as profile:
        try:
            return subprocess.run([program, *FLAGS, f"--user-data-dir={profile}", *args], capture_output=True,
                                  text=True, timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            raise BrowserError(f"Chromium did not finish within {TIMEOUT_S} s") from None


def layout(page: str, width: int, height: int = 1000) -> dict:
    """What Chromium makes of ``page`` in a window ``width`` px wide: the window's width, the page's scroll width
    (wider than the window: the page overflows horizontally), how many tables scroll inside their own box, the
    number of tables and the narrowest note cell (px)."""
    with tempfile.TemporaryDirectory(prefix="shimmy-layout-") as folder:
        copy = os.path.join(folder, "probe.html")
        with open(page, encoding="utf-8") as fh:
            text = fh.read()
        with open(copy, "w", encoding="utf-8") as fh:
            fh.write(text.replace("</body>", PROBE + "</body>"))
        proc = _run([f"--window-size={width},{height}", "--dump-dom", "file://" + os.path.abspath(copy)])
    found = re.search(r'<pre id="layout-probe">(.*?)</pre>', proc.stdout)
    if not found:
        raise BrowserError(f"Chromium rendered no layout of {page}: {proc.stderr.strip()[-300:]}")
    return json.loads(found.group(1).replace("&quot;", '"'))


def screenshot(page: str, out: str, width: int, height: int = 1400, anchor: str = "") -> str:
    """A PNG of the page's first ``height`` px in a window ``width`` px wide, or from the element ``anchor`` on
    (a copy of the page whose first lines are that element's: headless Chromium draws a blank page when asked to
    scroll to a fragment before its screenshot)."""
    with tempfile.TemporaryDirectory(prefix="shimmy-shot-") as folder:
        copy = os.path.join(folder, "page.html")
        with open(page, encoding="utf-8") as fh:
            text = fh.read()
        if anchor:
            start = text.find(f'<h2 id="{anchor}"')
            if start < 0:
                raise BrowserError(f"{page} has no section '{anchor}'")
            body = text.find("<body>") + len("<body>")
            text = text[:body] + text[start:]
        with open(copy, "w", encoding="utf-8") as fh:
            fh.write(text)
        proc = _run([f"--window-size={width},{height}", f"--screenshot={os.path.abspath(out)}",
                     "file://" + os.path.abspath(copy)])
    if not os.path.exists(out) or os.path.getsize(out) == 0:
        raise BrowserError(f"Chromium wrote no screenshot of {page}: {proc.stderr.strip()[-300:]}")
    return out
