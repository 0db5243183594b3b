"""Screenshots of a verification report in headless Chromium, at the widths the report is checked at.

Usage (from the repository root, after ``.venv/bin/shimmy verify --quick --out shimmy-report``)::

    .venv/bin/python tools/report_screenshots.py shimmy-report/report.html --out docs/screenshots

Writes ``report_<width>px.png`` (the top of the page: verdict, run, summary) and ``report_<width>px_<anchor>.png``
(from the section ``--anchor``, default the full geometry's, the widest table) for each of ``--widths`` (default
1280 and 1920), and prints the page's layout at each width: the window's width against the page's, and how many
tables scroll inside their own box.  Exit 1 when the page is wider than a window; 2 when Chromium is missing.
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from comparisons.verify.browser import BrowserError, layout, screenshot  # noqa: E402

WIDTHS = (1280, 1920)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Screenshots of a verification report at 1280 and 1920 px.")
    parser.add_argument("page", help="report.html of a verify run")
    parser.add_argument("--out", default="docs/screenshots", help="folder for the PNG files")
    parser.add_argument("--widths", default=",".join(map(str, WIDTHS)), help="window widths in px, comma list")
    parser.add_argument("--anchor", default="full_geometry", help="the section to show in the second screenshot")
    parser.add_argument("--height", type=int, default=1400, help="window height in px")
    args = parser.parse_args(argv)
    if not os.path.isfile(args.page):
        print(f"report_screenshots: no such file: {args.page}", file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    overflowing = False
    try:
        for width in (int(w) for w in args.widths.split(",")):
            got = layout(args.page, width)
            overflowing |= got["page_width"] > got["width"]
            print(f"{width} px: page {got['page_width']} px wide in a {got['width']} px window, "
                  f"{got['scrolling_tables']} of {got['tables']} tables scroll in their own box")
            for anchor in ("", args.anchor):
                name = f"report_{width}px{'_' + anchor if anchor else ''}.png"
                print(screenshot(args.page, os.path.join(args.out, name), width, args.height, anchor))
    except BrowserError as exc:
        print(f"report_screenshots: {exc}", file=sys.stderr)
        return 2
    return 1 if overflowing else 0


if __name__ == "__main__":
    sys.exit(main())
