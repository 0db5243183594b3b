"""pytest plugin: ``python -m pytest --axle FILE.toml`` runs the model-equivalence checks on that axle, from any folder.

Registered by the ``pytest11`` entry point ``shimmy`` in ``pyproject.toml``, so pytest loads it wherever the package
is installed (no conftest.py, no checkout needed).  The checks themselves are the test functions of
:mod:`comparisons.verify.equivalence_checks`, an ordinary test module shipped inside the package.

Mechanism.  Without ``--axle`` the plugin only defines its options and changes nothing else.  With ``--axle``,
:func:`pytest_configure` reads the axle file (a bad file is a :class:`pytest.UsageError`: one ``ERROR:`` line, exit
code 4, no traceback, before anything is collected) and adds the path of the bundled check module to
``config.args``, the list of initial paths that the session collects (:attr:`pytest.Config.args`):

* no test path on the command line (``config.args_source`` is the invocation folder or ``testpaths``): the check
  module *replaces* them, so that ``cd /tmp && pytest --axle FILE`` runs the checks and does not wander through
  /tmp looking for tests;
* test paths given: the check module is *added* to them.

An initial path is collected whatever its name (pytest's ``python_files`` pattern applies only to files found by
walking folders), so the check module is collected by pytest's own Python collector: real test items with fixtures,
parametrisation, ``-k``, ``--junitxml``, ``-x`` and assertion rewriting (registered below), and nothing
reimplemented here.  The alternative, custom ``pytest.Item`` classes built in ``pytest_collect_file``, would need a
file to hang them on and would lose parametrisation and fixtures.

The project's own suite runs the same checks on the paper's axle through ``tests/verify/test_equivalence_axle.py``,
which imports them; it skips them when ``--axle`` is given, because the plugin then runs them on that axle.
"""

from __future__ import annotations

import importlib.util

import pytest

CHECKS_MODULE = "comparisons.verify.equivalence_checks"
# assertion rewriting for the checks (detailed failure messages) also when a test module imports them
pytest.register_assert_rewrite(CHECKS_MODULE)

AXLE_KEY = pytest.StashKey[object]()          # the Axle under test, when --axle was given


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("shimmy", "shimmy model equivalence (reduced model against the multibody model)")
    group.addoption("--axle", action="store", default=None, metavar="FILE.toml",
                    help="run the model-equivalence checks on this axle file ('shimmy params --write FILE.toml' "
                         "makes one), from any folder")
    group.addoption("--axle-set", action="append", default=None, metavar="NAME=VALUE", dest="axle_set",
                    help="override an entry of the --axle file, in the units of 'shimmy params' (degrees, bar, "
                         "otherwise SI); repeatable")
    group.addoption("--quick", action="store_true", default=False,
                    help="the equivalence checks with fewer speeds and pressures and shorter runs")


def checks_path() -> str:
    """File of the bundled check module, found without importing it (so that pytest imports it, rewritten)."""
    spec = importlib.util.find_spec(CHECKS_MODULE)
    if spec is None or spec.origin is None:
        raise pytest.UsageError(f"--axle: the check module {CHECKS_MODULE} is not installed")
    return spec.origin


def load_axle(path: str, overrides: list[str] | None):
    """The axle of ``--axle`` with ``--axle-set`` on top; any problem is one usage line."""
    from comparisons.api import Axle
    from axles.parameters import ParameterError
    try:
        axle = Axle.from_file(path)
    except ParameterError as exc:                   # an AxleFileError among them
        raise pytest.UsageError(f"--axle: {exc}") from None
    try:
        data = axle.with_set(*(overrides or ())).data
    except ParameterError as exc:                   # the API's --set messages, naming this option instead
        text = str(exc).replace("--set", "--axle-set")
        raise pytest.UsageError(text if "--axle-set" in text else f"--axle-set: {text}") from None
    try:   # entries that contradict each other are a bad input, not twenty failed checks
        data.check_consistent()
    except ParameterError as exc:
        raise pytest.UsageError(f"--axle-set: {exc}") from None
    return data


def axle_under_test(config: pytest.Config):
    """The axle the checks run on: ``--axle`` (with ``--axle-set``), else the paper's truck."""
    if AXLE_KEY in config.stash:
        return config.stash[AXLE_KEY]
    from axles.axle import paper_axle
    return paper_axle()


def pytest_configure(config: pytest.Config) -> None:
    path = config.getoption("axle")
    if path is None:
        if config.getoption("axle_set"):
            raise pytest.UsageError("--axle-set NAME=VALUE needs --axle FILE.toml")
        return
    if not path.strip():
        raise pytest.UsageError("--axle needs a file name")
    config.stash[AXLE_KEY] = load_axle(path, config.getoption("axle_set"))
    checks = checks_path()
    if config.args_source is pytest.Config.ArgsSource.ARGS:
        if checks not in config.args:
            config.args.append(checks)
    else:
        config.args = [checks]


@pytest.hookimpl(tryfirst=True)
def pytest_pycollect_makemodule(module_path, parent):
    """The check module under one node id wherever pytest runs (by default an initial path outside the rootdir
    gets an empty one, and JUnit test cases an empty class name)."""
    if AXLE_KEY in parent.config.stash and str(module_path) == checks_path():
        return pytest.Module.from_parent(parent, path=module_path, nodeid=CHECKS_MODULE.replace(".", "/") + ".py")
    return None


def pytest_report_header(config: pytest.Config) -> str | None:
    if AXLE_KEY not in config.stash:
        return None
    axle = config.stash[AXLE_KEY]
    lo, hi = axle.pressure_range_bar
    mode = "quick" if config.getoption("quick") else "full"
    return f"shimmy equivalence checks ({mode}): {axle.label()}; pressures {lo:g}-{hi:g} bar"
