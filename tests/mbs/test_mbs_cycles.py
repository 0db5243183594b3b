"""Limit cycles continued on the Exudyn model itself, by the same toolkit code as the reduced model's.

Checks against two independent sides: with every assumption on, the reduced model's own branch (the two models
are then the same equations, evaluated by different code and differentiated by different methods); with the
full geometry, the MBS's own long simulation, which must settle on the stable orbit the continuation found.
The full-geometry tests take about a minute each on 2 cores (Exudyn's right-hand side, ~120 us a call, at every
collocation point), and the reduced-fidelity branch about half a minute: all run in the slow suite, so that
CI stays within its 10 minutes; the equivalence of Hopf points, l1 and folds runs in CI.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from axles.units import BAR, KMH
from mbs_shimmy import Fidelity
from comparisons.studies.limit_cycle import mbs_steady_amplitude
from mbs_shimmy.linearisation import MbsFamily
from mbs_shimmy.model import MbsModel
from bifurcation.cycles.branches import cycle_diagram
from reduced_model.family import SpeedFamily
from reduced_model.model import Effects, ShimmyModel
from axles.parameters import YANG2024
from axles.pressures import TyrePressures

PRESSURE = 1.5 * BAR
AT = tuple(v * KMH for v in (40.0, 60.0, 80.0))


@pytest.fixture(scope="module")
def both_yaw_branches():
    reduced = SpeedFamily(ShimmyModel(), pressures=TyrePressures.uniform(PRESSURE))
    mbs = MbsFamily(MbsModel(fidelity=Fidelity.reduced()), pressures=TyrePressures.uniform(PRESSURE))
    return [cycle_diagram(f, PRESSURE, 0.0, 120.0 * KMH, at=AT) for f in (reduced, mbs)]


@pytest.mark.slow
def test_mbs_with_every_assumption_on_continues_the_reduced_models_branch(both_yaw_branches):
    reduced, mbs = both_yaw_branches
    assert len(mbs.branches) == len(reduced.branches) == 1
    r, m = reduced.branches[0], mbs.branches[0]
    assert m.complete and r.complete
    assert m.end.p == pytest.approx(r.end.p, abs=1e-4 * KMH)
    assert len(m.user_points) == len(r.user_points) == len(AT)
    for a, b in zip(sorted(r.user_points, key=lambda p: p.p), sorted(m.user_points, key=lambda p: p.p)):
        assert b.p == pytest.approx(a.p, rel=1e-12)
        assert b.period == pytest.approx(a.period, rel=1e-6)
        np.testing.assert_allclose(b.amplitude[:8], a.amplitude, rtol=1e-6, atol=1e-9)
        assert b.stable == a.stable


@pytest.mark.slow
def test_full_geometry_stable_orbit_is_where_its_simulation_settles():
    """The yaw branch of the full axle at 1.5 bar, born at 41.3 km/h, continued to 50 km/h: its orbit at 45 km/h
    against a long MBS run from a small kick, max |theta1| and frequency to 0.5 %."""
    family = MbsFamily(MbsModel(fidelity=Fidelity.full()), pressures=TyrePressures.uniform(PRESSURE))
    speed = 45.0 * KMH
    diagram = cycle_diagram(family, PRESSURE, 35.0 * KMH, 50.0 * KMH, at=(speed,))
    (orbit,) = [p for b in diagram.branches for p in b.user_points]
    assert orbit.stable
    run = mbs_steady_amplitude(YANG2024, Effects(), Fidelity.full(), TyrePressures.uniform(PRESSURE), speed, settle=15.0)
    assert run.settled
    assert run.theta1 == pytest.approx(orbit.max_abs("theta1"), rel=5e-3)
    # The frequency from the upward zero crossings of theta1 over the run's last settled window.
    assert run.frequency_hz == pytest.approx(orbit.frequency_hz, rel=5e-3)


@pytest.mark.slow
def test_cycles_command_on_the_mbs_in_the_same_schema():
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "cycles", "--pressure", "1.5", "--model", "mbs",
                           "--fidelity", "full", "--vmin", "35", "--vmax", "50", "--at", "45", "--json"],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["model"] == "mbs" and out["fidelity"] == "full"
    (branch,) = out["branches"]
    assert branch["complete"] and "left the window at 50 km/h" in branch["message"]
    cycles = [p for p in branch["points"] if p["kind"] == "cycle"]
    assert cycles and all("max_y_axle_m" in p and "max_phi_gear_deg" in p for p in cycles)
    assert max(p["max_y_axle_m"] for p in cycles) > 0.0
    (orbit,) = out["at"][0]["orbits"]
    # 14 states: the reduced model's 8 and y_axle, z_axle, phi_gear with their rates.
    assert orbit["speed_kmh"] == pytest.approx(45.0) and len(orbit["multipliers"]) == 14
