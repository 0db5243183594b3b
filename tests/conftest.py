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
