"""The files, folders, modules and links the docs name exist (the layout change left the old README naming files
that had moved).  CHANGELOG.md names the old paths on purpose and is not read."""

import re

import pytest

from tests.docs.conftest import ROOT

DOCS = ["README.md", "mbs_shimmy/README.md", *(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md"))]
TOP = ("reduced_model", "mbs_shimmy", "comparisons", "tests", "tools", "docs")
PATH = re.compile(r"`((?:%s)/[\w./-]*)`" % "|".join(TOP))
MODULE = re.compile(r"`((?:reduced_model|mbs_shimmy|comparisons)(?:\.\w+)+)")
LINK = re.compile(r"\]\(([^)#\s]*)(?:#([^)]*))?\)")


def _anchors(path) -> set[str]:
    """GitHub's ids of a page's headings: lower case, punctuation but '-' dropped, spaces to '-'."""
    heads = re.findall(r"^#+ (.*)$", path.read_text(), re.M)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in heads}


def _defines(path, name: str) -> bool:
    text = path.read_text()
    return bool(re.search(rf"^\s*(def|class)\s+{name}\b|^{name}\s*[:=]|import .*\b{name}\b", text, re.M))


def _module_ok(dotted: str) -> bool:
    parts = dotted.split(".")
    for n in range(len(parts), 0, -1):
        base = ROOT.joinpath(*parts[:n])
        source = base.with_suffix(".py") if base.with_suffix(".py").exists() else base / "__init__.py"
        if source.exists():
            return n == len(parts) or _defines(source, parts[n])
    return False


@pytest.mark.parametrize("doc", DOCS)
def test_named_paths_exist(doc):
    text = (ROOT / doc).read_text()
    missing = [p for p in PATH.findall(text) if not (ROOT / p.split("::")[0]).exists()]
    missing += [m for m in MODULE.findall(text) if not _module_ok(m)]
    here = (ROOT / doc).parent
    for link, anchor in LINK.findall(text):
        target = here / link if link else ROOT / doc
        if "://" in link:
            continue
        if not target.exists():
            missing.append(link)
        elif anchor and target.suffix == ".md" and anchor not in _anchors(target):
            missing.append(f"{link}#{anchor}")
    assert not missing, f"{doc} names what does not exist: {missing}"
