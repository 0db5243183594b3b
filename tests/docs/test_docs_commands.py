"""Every shimmy command line in the README and docs/ parses with the real parser; every option a synopsis names
exists.  Nothing is computed."""

import pytest


def test_the_docs_show_commands(docs_commands):
    found = docs_commands.find()
    texts = [c.text for c in found]
    # The README's first command and its one-line synopses of every command are found.
    assert ".venv/bin/shimmy verify" in texts
    assert sum(c.synopsis for c in found) >= 11
    assert sum(not c.synopsis for c in found) >= 30


def test_every_documented_command_parses(docs_commands):
    wrong = []
    for c in docs_commands.find():
        problem = docs_commands.check_synopsis(c) if c.synopsis else docs_commands.check_syntax(c)
        if problem:
            wrong.append(f"{c.where}: {c.text}: {problem}")
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("line, message", [
    ("shimmy hopf --pressure 1.5 --vmaxx 300", "unrecognized arguments"),
    ("shimmy hopf --pressure 30", "within [0.05, 20] bar"),
    ("shimmy hopf --vmax 300", "--pressure BAR is required"),
    ("shimmy curves --pressure 1.5 --json", "required"),
])
def test_a_wrong_command_is_caught(docs_commands, line, message):
    cmd = docs_commands.Command("test", line, docs_commands._argv(line))
    assert message in (docs_commands.check_syntax(cmd) or "")


def test_a_wrong_synopsis_is_caught(docs_commands):
    cmd = docs_commands.Command("test", "shimmy cycles MODEL [--two-params NAME]", (), True)
    assert "--two-params" in docs_commands.check_synopsis(cmd)


def test_code_blocks_split_chains_and_skip_tables(docs_commands, tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "x.md").write_text(
        "```bash\n"
        "python3 -m venv .venv && .venv/bin/shimmy verify --quick   # comment\n"
        ".venv/bin/shimmy sweep --vary pressure=1:2:3 \\\n"
        "  --out a.parquet\n"
        "| command | shimmy verify --quick --out /tmp/x |\n"
        "```\n"
        "Text with `shimmy params --json`, a name `shimmy sweep` and `shimmy hopf MODEL [--json]`.\n")
    found = [(c.text, c.synopsis) for c in docs_commands.find(tmp_path)]
    assert found == [(".venv/bin/shimmy verify --quick", False),
                     (".venv/bin/shimmy sweep --vary pressure=1:2:3 --out a.parquet", False),
                     ("shimmy params --json", False), ("shimmy hopf MODEL [--json]", True)]
