"""``shimmy sweep``, ``margins`` and ``modes`` under braking (issue 32): the braking reaches every sample and both
models, and the outputs equal the API's calls under the same braking."""

from __future__ import annotations

import json

import numpy as np
import pytest

from axles.axle import AxleData
from axles.braking import Braking
from axles.units import from_kmh
from bifurcation.equilibria.hopf import eigenvalues
from comparisons.api import Axle, TyrePressures, hopf_points, stability_margins
from comparisons.cli.main import main
from comparisons.sweeps.sample import MARGIN_SPEEDS, SweepTask

RIGHT = Braking.of_slip(0.05, 0.0)


def test_sweep_sample_under_braking_equals_the_api():
    task = SweepTask(AxleData(), (), 2.5, 2.5, ("pressure",), compute=("hopf", "margins"), braking=RIGHT)
    assert task.to_json()["braking"] == RIGHT.describe()
    assert "braking" not in SweepTask(AxleData(), (), 2.5, 2.5, ("pressure",)).to_json()   # resumes stay valid
    row = task.evaluate(np.array([2.5]))
    axle = Axle.paper()
    family = axle.reduced().family(TyrePressures.both(2.5), braking=RIGHT)
    want = [h.speed_kmh for h in hopf_points(family).points]
    assert row["hopf_kmh"] == pytest.approx(want, abs=1e-6) and len(want) == 2
    assert want != pytest.approx([h.speed_kmh for h in hopf_points(axle.reduced().family(
        TyrePressures.both(2.5))).points], abs=0.1)                   # braking moved them
    low = stability_margins(axle.reduced(), (2.5, 2.5), 0.5, 400, pressure_points=1, speed_points=MARGIN_SPEEDS,
                            braking=RIGHT).minimum
    assert row["margin"] == low.damping_ratio and row["margin_kmh"] == low.speed_kmh
    # the unstable interval against the eigenvalues at the braked steady state
    problem = family.problem
    for v in np.linspace(5.0, 150.0, 30):
        unstable = eigenvalues(problem, from_kmh(v), problem.nominal)[0].real > 0
        inside = any(a <= v <= b for a, b in zip(row["unstable_from_kmh"], row["unstable_to_kmh"]))
        assert unstable == inside, v


def test_modes_and_margins_commands_under_braking(capsys):
    """modes' least damping ratio at 60 km/h equals margins' at that speed, both about the braked steady state,
    and differs from free rolling's."""
    def damping(argv):
        assert main(argv) == 0
        return json.loads(capsys.readouterr().out)

    modes = damping(["modes", "--pressure", "2.5", "--speed", "60", "--brake-slip", "0.05,0", "--json"])
    least = min(m["damping_ratio"] for m in modes["models"]["reduced"])
    free = min(m["damping_ratio"] for m in damping(["modes", "--pressure", "2.5", "--speed", "60",
                                                    "--json"])["models"]["reduced"])
    margins = damping(["margins", "--range", "2.5", "2.6", "--pressures", "2", "--vmin", "60", "--vmax", "61",
                       "--speeds", "2", "--brake-slip", "0.05,0", "--json"])
    assert modes["braking"] == margins["braking"] == RIGHT.describe()
    assert margins["damping_ratio"][0][0] == pytest.approx(least, rel=1e-12) and least < free < 0
