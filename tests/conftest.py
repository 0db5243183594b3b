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
