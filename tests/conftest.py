import numpy as np
import pytest

from reduced_model.family import SpeedFamily
from reduced_model.model import ShimmyModel


@pytest.fixture(scope="session")
def section3():
    return SpeedFamily(ShimmyModel(), "pressure")


def rng(seed=0):
    return np.random.default_rng(seed)


def pytest_addoption(parser):
    parser.addoption("--axle", action="store", default=None, metavar="FILE.toml",
                     help="run the model-equivalence tests (tests/test_equivalence_axle.py) on this axle file "
                          "instead of the paper's truck")


@pytest.fixture(scope="session")
def axle(request):
    """The axle of the equivalence tests: ``pytest --axle FILE.toml``, or the paper's truck."""
    from comparisons.axles.axle_file import AxleFileError, axle_from_path_or_paper
    path = request.config.getoption("--axle")
    try:
        return axle_from_path_or_paper(path)
    except AxleFileError as exc:
        raise pytest.UsageError(f"--axle: {exc}") from None
