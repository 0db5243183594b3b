import numpy as np
import pytest

from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel

BAR = 1e5
KMH = 1 / 3.6


@pytest.fixture(scope="session")
def section3():
    return SpeedFamily(ShimmyModel(), "pressure")


def rng(seed=0):
    return np.random.default_rng(seed)
