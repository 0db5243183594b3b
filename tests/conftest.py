import importlib.util
import pathlib
import sys

import numpy as np
import pytest

from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel

# --axle FILE.toml (and --quick) come from the package's pytest plugin, comparisons/verify/pytest_plugin.py


@pytest.fixture(scope="session")
def section3():
    return SpeedFamily(ShimmyModel(), "pressure")


def rng(seed=0):
    return np.random.default_rng(seed)


@pytest.fixture(scope="session")
def campaign_tool():
    """``tools/verify_campaign.py`` as a module: its axle draws (``draw_axle``) and its campaign."""
    path = pathlib.Path(__file__).resolve().parents[1] / "tools" / "verify_campaign.py"
    spec = importlib.util.spec_from_file_location("tools_verify_campaign", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module          # its dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


# The files whose tests take longest, scheduled first: pytest-xdist (--dist loadfile) hands whole files to its
# workers in collection order, and with these last (tests/verify/ sorts late) one worker ran them while the other
# stood idle.  Longest first is the usual remedy; the order within a file, and of every other file, is kept.
LONGEST_FIRST = (
    "tests/verify/test_verify.py",
    "tests/sweeps/test_sweep_faults.py",
    "tests/verify/test_campaign.py",
    "tests/mbs/test_mbs_fold_curve.py",
    "tests/figures/test_figures.py",
    "tests/model/test_simulation.py",
    "tests/bifurcation/test_cycle_audit.py",
    "tests/verify/test_pytest_plugin.py",
    "tests/mbs/test_mbs_curves.py",
    "tests/bifurcation/test_cycle_resonances.py",
    "tests/studies/test_bistable_map.py",
    "tests/studies/test_kick.py",
    "tests/studies/test_cycle_peak.py",
    "tests/sweeps/test_sweep.py",
)


def pytest_collection_modifyitems(config, items):
    rank = {path: i for i, path in enumerate(LONGEST_FIRST)}
    root = pathlib.Path(str(config.rootpath))

    def key(item):
        try:
            path = pathlib.Path(str(item.path)).relative_to(root).as_posix()
        except ValueError:
            return len(rank)
        return rank.get(path, len(rank))
    items.sort(key=key)
