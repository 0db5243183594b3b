"""The generated tables of the docs equal what the code's registries give now."""

import contextlib
import io
import json
import re

from comparisons.cli.commands import figures
from comparisons.cli.main import EXIT_CODES, main
from comparisons.figures import REGISTRY, available_figures
from mbs_shimmy.fidelity import ASSUMPTIONS
from tests.docs.conftest import ROOT


def test_no_generated_table_drifted(docs_tables):
    drifted = docs_tables.drifted()
    assert not drifted, ("generated tables differ from the code; run '.venv/bin/python tools/docs_tables.py "
                         f"--write': {', '.join(drifted)}")


def test_every_table_is_placed(docs_tables):
    assert set(docs_tables.TABLES) <= docs_tables.used_tables()


def test_check_names_a_drifted_table(docs_tables, tmp_path):
    # A copy of the docs with one row edited: the check must say which file and table, not just fail.
    (tmp_path / "docs").mkdir()
    text = (docs_tables.ROOT / "docs" / "cli.md").read_text()
    (tmp_path / "docs" / "cli.md").write_text(text.replace("| 74 |", "| 75 |"))
    assert docs_tables.drifted(tmp_path) == ["docs/cli.md: exit-codes"]
    docs_tables.drifted(tmp_path, write=True)
    assert docs_tables.drifted(tmp_path) == []


def test_axle_table_is_what_params_json_prints(docs_tables):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["params", "--json"]) == 0
    printed = json.loads(out.getvalue())["parameters"]
    table = docs_tables.axle_entries()
    for row in printed:
        assert f"| `{row['name']}` | {row['section']} | {row['value']:.6g} | {row['unit']} | " in table
        assert f"[{row['range'][0]:g}, {row['range'][1]:g}]" in table
    assert table.count("\n") == len(printed) + 2


def test_exit_code_registry_matches_the_commands():
    assert EXIT_CODES[figures.EXIT_UNAVAILABLE].startswith("`figures`")
    assert figures.EXIT_INCOMPLETE in EXIT_CODES
    assert list(EXIT_CODES) == sorted(EXIT_CODES)


def test_the_cost_table_has_a_row_per_switch():
    # Its numbers are measured, not generated; its rows must still follow the registry.
    text = (ROOT / "docs" / "results.md").read_text()
    costs = text[text.index("| switch | Hopf 1.5 bar (km/h) |"):]
    costs = costs[:costs.index("\n\n")]
    rows = [line.split("|")[1].strip() for line in costs.splitlines()[2:]]
    assert [r for r in rows if not r.startswith("**full**")] == [f"`{a.name}`" for a in ASSUMPTIONS]


def test_the_figure_table_follows_the_registry():
    # The 'what' column holds computed numbers, so the table is written by hand; its rows must follow the registry.
    text = (ROOT / "docs" / "figures.md").read_text()
    rows = re.findall(r"^\| (\d+) \| \[`(fig[\w.]+\.png)`\]\(figures/(fig[\w.]+\.png)\)", text, re.M)
    assert [(int(n), a) for n, a, _ in rows] == [(n, REGISTRY[n].file_name) for n in available_figures()]
    assert all(a == b and (ROOT / "docs" / "figures" / a).exists() for _, a, b in rows)
