"""The input ranges of axles.limits against the models' own limits."""

import ast
import pathlib

from axles import limits
from axles.units import kmh
from reduced_model.family import MIN_SPEED


def test_the_lowest_speed_is_the_models():
    assert limits.SPEED_RANGE_KMH[0] == kmh(MIN_SPEED)


def test_limits_imports_nothing():
    # comparisons.cli.main imports it outside the guard for an interrupt during the model packages' import
    tree = ast.parse(pathlib.Path(limits.__file__).read_text())
    imported = [node for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))]
    assert [getattr(node, "module", None) for node in imported] == ["__future__"]
