"""The plugin's model-equivalence checks (:mod:`comparisons.verify.equivalence_checks`) on the paper's axle, in the
project's suite, in their quick form (the full form: ``python -m pytest --axle paper.toml``).

With ``--axle`` the plugin runs the same checks on that axle itself, so they are skipped here.
"""

import pytest

from comparisons.verify.equivalence_checks import *  # noqa: F403  (the checks and their fixtures, collected here)

QUICK = True


@pytest.fixture(autouse=True)
def _not_twice(request):
    if request.config.getoption("axle") is not None:
        pytest.skip("--axle given: the plugin runs these checks on that axle")
