"""The verification report: headers in words, every "-" explained, run metadata, a self-contained report.html
that a real browser renders with its figures, progress lines, and the report's figures from plain data."""

import io
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from comparisons.cli.progress import StepProgress
from comparisons.verify import report_figures as rf
from comparisons.verify.rendering import render_html, render_markdown, write_report
from comparisons.verify.report import CheckStatus, Report, Row, Section, axle_fingerprint, run_metadata


def hopf_section(figures=()):
    rows = (Row({"model": "section 3", "pressure_bar": 1.5, "point": "HB1", "paper_kmh": 20.0,
                 "reduced_kmh": 20.0134, "mbs_reduced_kmh": 20.0134, "mbs_full_kmh": None}, CheckStatus.PASS),
            Row({"model": "section 3", "pressure_bar": 1.5, "point": "HB3", "paper_kmh": None,
                 "reduced_kmh": 201.5, "mbs_reduced_kmh": 201.5, "mbs_full_kmh": 210.25}, CheckStatus.INFO))
    return Section("hopf", "Hopf speeds", ("model", "pressure_bar", "point", "paper_kmh", "reduced_kmh",
                                           "mbs_reduced_kmh", "mbs_full_kmh"), rows, text="Compared `mbs`.",
                   figures=figures)


def cycles_section():
    return Section("cycles", "Limit cycles", ("speed_kmh", "relative_diff", "custom_col"),
                   (Row({"speed_kmh": 60.0, "relative_diff": 0.0012, "custom_col": None}, CheckStatus.PASS),),
                   labels={"custom_col": "a column of this section [m]"})


def test_markdown_headers_in_words_and_dashes_explained():
    text = render_markdown(Report((hopf_section(), cycles_section()), quick=True))
    header = next(line for line in text.splitlines() if line.startswith("| model"))
    assert "mbs_reduced_kmh" not in header and "[km/h]" in header and "tyre pressure [bar]" in header
    assert "| 0.0012 |" in text                                   # a relative difference, as relative
    assert "relative difference, MBS against the reduced model [relative, not %]" in text
    # Each column holding a "-" is explained under its table, in words.
    dash_lines = [line for line in text.splitlines() if line.startswith('A "-" in the table')]
    assert len(dash_lines) == 2
    assert "*paper [km/h]*: the paper prints no value for it" in dash_lines[0]
    assert "*MBS, full geometry [km/h]*: the full geometry has no Hopf point matching" in dash_lines[0]
    assert "*a column of this section [m]*: does not apply" in dash_lines[1]
    assert "`pass`: the check passed" in text


def test_html_tables_scroll_in_their_box_and_no_cell_is_blank():
    rows = (Row({"case": "2.5 bar", "assumption_off": "no_kingpin_inclination", "hopf_shifts_kmh": ""},
                CheckStatus.INFO, "an element row without Hopf points"),)
    s = Section("assumptions", "Assumptions", ("case", "assumption_off", "hopf_shifts_kmh"), rows)
    page = render_html(Report((s,), quick=True), ".")
    assert page.count('<div class="scroll"><table>') == 2            # the summary's table and the section's
    assert '<td class="note">an element row without Hopf points</td>' in page
    assert '<td class="text">-</td>' in page                           # the empty text shows "-" ...
    assert "neither side of the row has a Hopf point" in page           # ... and says what it means
    assert "<td></td>" not in page and '<td class="text"></td>' not in page


def test_metadata():
    meta = run_metadata(quick=True, seconds=12.5, command="shimmy verify --quick")
    rows = dict(meta.rows())
    assert re.fullmatch(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d", rows["date (UTC)"])
    assert rows["shimmy"] == "0.1.0" and rows["exudyn"] == "1.13.6" and rows["rerun-sdk"] == "0.41.0"
    assert rows["numpy"] == np.__version__ and rows["run time"] == "12.5 s"
    assert re.match(r"[0-9a-f]{40}", rows["git commit"])            # the tests run in a checkout
    assert rows["axle"].startswith("axle YANG2024") and len(rows["axle SHA-256"]) == 64
    from axles.axle import paper_axle
    changed = paper_axle().with_overrides({"t0": 0.25})
    assert axle_fingerprint(None)[1] == axle_fingerprint(paper_axle())[1] != axle_fingerprint(changed)[1]
    text = render_markdown(Report((hopf_section(),), quick=True, metadata=meta))
    assert "| exudyn | 1.13.6 |" in text and "## Run" in text


@pytest.fixture(scope="module")
def report_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report")
    rf.plot_hopf_speeds({"section 3": {"paper": [(1.5, 20.0), (2.5, 46.0)], "reduced": [(1.5, 20.01), (2.5, 46.14)],
                                       "mbs_reduced": [(1.5, 20.01), (2.5, 46.14)], "mbs_full": [(1.5, 22.0)]},
                         "all effects": {"reduced": [(1.5, 30.0)]}}, str(folder / "hopf.png"))
    t = np.linspace(0.0, 40.0, 40001)
    speed = 120 + 2.0 * t
    runs = [rf.RunHistory(model, t, speed, amp * np.sin(2 * np.pi * 6 * t) * (t > 20), 0.1 * np.sin(t), [(20.0, 160.0,
                          "yaw -> tramp")]) for model, amp in (("reduced", 10.0), ("mbs", 9.0))]
    rf.plot_jump_histories([rf.Experiment("ramp up", runs, {"S1": 184.7}),
                            rf.Experiment("ramp down", runs, {"T2": 157.4})], str(folder / "jumps.png"))
    rf.plot_assumption_tornado([rf.AssumptionShift(1.5, "small_angles", [0.5, -1.2, None]),
                                rf.AssumptionShift(1.5, "full", [3.0, None, None]),
                                rf.AssumptionShift(2.5, "full", [-0.7])], str(folder / "tornado.png"))
    figures = ("hopf.png", "jumps.png", "tornado.png")
    rep = Report((hopf_section(figures), cycles_section()), quick=True, metadata=run_metadata(True))
    return folder, write_report(rep, str(folder)), figures


def test_report_figures_are_drawn(report_folder):
    folder, _, figures = report_folder
    for name in figures:
        assert (folder / name).stat().st_size > 15_000, name


def test_html_is_self_contained(report_folder):
    _, (md, page), figures = report_folder
    text = open(page, encoding="utf-8").read()
    srcs = re.findall(r'src="([^"]*)"', text)
    assert len(srcs) == len(figures) and all(s.startswith("data:image/png;base64,") for s in srcs)
    assert "<link" not in text and "http" not in text.replace("http-equiv", "")
    assert "MBS with the reduced model&#x27;s assumptions [km/h]" in text
    assert os.path.getsize(md) > 0 and not [f for f in os.listdir(os.path.dirname(page)) if f.startswith(".")]


CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


@pytest.mark.skipif(CHROMIUM is None, reason="no Chromium here (Debian: apt-get install -y chromium); the HTML "
                                              "report is checked in a real browser only where one is installed")
def test_html_renders_in_a_real_browser(report_folder, tmp_path):
    """Chromium, headless, loads a copy of the page with a probe script that writes what the browser made of
    it (decoded image sizes, table rows) into the DOM, which --dump-dom prints."""
    _, (_, page), figures = report_folder
    probe = ("<script>window.addEventListener('load', () => { const r = {images: [...document.images].map(i => "
             "[i.naturalWidth, i.naturalHeight]), rows: [...document.querySelectorAll('table')].map(t => "
             "t.tBodies[0].rows.length), title: document.title}; const p = document.createElement('pre'); "
             "p.id = 'probe'; p.textContent = JSON.stringify(r); document.body.appendChild(p); });</script>")
    copy = tmp_path / "probe.html"
    copy.write_text(open(page, encoding="utf-8").read().replace("</body>", probe + "</body>"), encoding="utf-8")
    proc = subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=10000",
                           "--dump-dom", copy.as_uri()], capture_output=True, text=True, timeout=120)
    found = re.search(r'<pre id="probe">(.*?)</pre>', proc.stdout)
    assert found, proc.stderr[-2000:]
    got = json.loads(found.group(1).replace("&quot;", '"'))
    assert got["title"] == "shimmy verification report"
    assert len(got["images"]) == len(figures) and all(w > 500 and h > 200 for w, h in got["images"])
    # Run metadata (13 rows), summary (2 sections), then each section's table.
    assert got["rows"] == [13, 2, 2, 1]


def test_step_progress_lines():
    out = io.StringIO()
    with StepProgress(3, "verify", stream=out) as progress:
        with progress.step("Hopf speeds at 1.5 bar"):
            pass
        with pytest.raises(RuntimeError):
            with progress.step("limit cycles"):
                raise RuntimeError("x")
        progress(3, 3)
    lines = out.getvalue().splitlines()
    assert len(lines) == 3
    assert lines[0].startswith("verify: [1/3] Hopf speeds at 1.5 bar: done in ")
    assert lines[1].startswith("verify: [2/3] limit cycles: failed in ")
    assert lines[2].startswith("verify: [3/3] step 3: done")


def test_html_escapes_and_marks_failures(tmp_path):
    s = Section("x", "<X & Y>", ("note_col",), (Row({"note_col": "<b>"}, CheckStatus.FAIL, "a < b"),))
    page = render_html(Report((s,), quick=False), str(tmp_path))
    assert "&lt;X &amp; Y&gt;" in page and "<b>" not in page and 'class="FAIL"' in page
    assert "overall-fail" in page


def test_step_progress_messages_and_bar():
    """verify's protocol: a message per step as it starts, "done: <step>" for the announced top-level steps."""
    out = io.StringIO()
    with StepProgress(stream=out) as progress:
        progress.set_steps(["Plan", "Hopf speeds"])
        for message in ("Plan", "done: Plan", "Hopf speeds", "Hopf speeds: 1.5 bar", "Hopf speeds: 2.5 bar",
                        "done: Hopf speeds"):
            progress(message)
    lines = out.getvalue().splitlines()
    assert [line.split(" (")[0] for line in lines] == [
        "verify: [1/2] Plan: done in 0.0 s", "verify:   Hopf speeds: 1.5 bar", "verify:   Hopf speeds: 2.5 bar",
        "verify: [2/2] Hopf speeds: done in 0.0 s"]
    tty = io.StringIO()
    with StepProgress(stream=tty, bar=True) as progress:
        progress.set_steps(["Plan"])
        progress("Plan")
        progress("planning the cases")
        progress("done: Plan")
    assert "verify: planning the cases" in tty.getvalue() and "[1/1] Plan: done" in tty.getvalue()


def test_plan_step_counts_the_planning(monkeypatch):
    """verify announces the Plan before its scans and the whole list after them; the Plan's time is the scans'
    (it once read "[1/10] Plan: done in 0.0 s (29 s so far)": only its section, which formats the plan, was
    timed)."""
    now = [0.0]
    monkeypatch.setattr("comparisons.cli.progress.time.perf_counter", lambda: now[0])
    out = io.StringIO()
    with StepProgress(stream=out, bar=False) as progress:
        progress.set_steps(["Plan"])
        progress("Plan")                       # run_verification, before make_plan
        progress("scanning the reduced model")  # make_plan's own messages
        now[0] = 29.0
        progress.set_steps(["Plan", "Hopf speeds"])
        progress("Plan")                       # run_sections, before the Plan section
        progress("done: Plan")
    line = next(x for x in out.getvalue().splitlines() if "] Plan:" in x)
    assert line.startswith("verify: [1/2] Plan: done in 29.") and "(29 s so far)" in line


def test_tornado_rows_name_what_they_compare(monkeypatch, tmp_path):
    """An assumption's row compares the MBS with it off against the reduced model, an element's row the full
    geometry with the element against without (the axis once said "MBS minus reduced model" for both); a row
    without Hopf points says so instead of staying blank."""
    kept = {}
    monkeypatch.setattr(rf, "save_figure", lambda fig, path: kept.setdefault("fig", fig))
    rf.plot_assumption_tornado([rf.AssumptionShift(2.5, "small_angles", [0.5, -1.2]),
                                rf.AssumptionShift(2.5, "no_kingpin_inclination", []),
                                rf.AssumptionShift(2.5, "full", [0.3, None])], str(tmp_path / "t.png"))
    (ax,) = kept["fig"].axes[:1]
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert "small angles off: MBS - reduced model" in labels
    assert "no kingpin inclination: full geometry with - without\n(no Hopf point on either side)" in labels
    assert "every assumption off (full geometry): MBS - reduced model" in labels
    assert "MBS minus reduced" not in ax.get_xlabel()
