"""The verify section "Stability margins" on an axle with no Hopf point at all (the paper's axle with
c4 = 120 N m s/rad): it still checks something, and says the axle is damped everywhere."""

from axles.axle import AxleData
from comparisons.verify.context import Context
from comparisons.verify.margin_checks import FIGURE, margins_section
from comparisons.verify.plan import Plan
from comparisons.verify.report import CheckStatus


def test_a_stable_axle_has_a_margin_figure_and_passing_checks(tmp_path):
    axle = AxleData().with_overrides({"c4": 120.0})
    section = margins_section(Context(out=str(tmp_path), quick=True, axle=axle, plan=Plan((), ())))
    assert section.key == "margins" and (tmp_path / FIGURE).stat().st_size > 10_000
    checks = [r for r in section.rows if r.status is not CheckStatus.INFO]
    assert len(checks) >= 3 and all(r.status is CheckStatus.PASS for r in checks)
    zero = [r for r in checks if r.cells["quantity"].startswith("sign of the margin")]
    assert {r.cells["model"] for r in zero} == {"reduced model", "MBS, full geometry"}
    assert all("no Hopf point" in r.note and "damped at every speed" in r.note for r in zero)
    minima = {r.cells["model"]: r.cells for r in section.rows if r.cells["quantity"] == "minimum margin"}
    assert set(minima) == {"reduced model", "MBS, full geometry"}
    assert all(m["damping_ratio"] > 0 for m in minima.values())


def test_the_margin_minima_reach_the_verdict(tmp_path):
    """The section hands each model's minimum to the verdict as data (sentence and JSON from the same point)."""
    axle = AxleData().with_overrides({"c4": 120.0})
    section = margins_section(Context(out=str(tmp_path), quick=True, axle=axle, plan=Plan((), ())))
    facts = {f.model: f for f in section.verdict_facts}
    assert set(facts) == {"reduced model", "MBS, full geometry"}
    minima = {r.cells["model"]: r.cells for r in section.rows if r.cells["quantity"] == "minimum margin"}
    for model, fact in facts.items():
        data = fact.to_json()
        assert data["damping_ratio"] == minima[model]["damping_ratio"] > 0
        assert f"{data['damping_ratio']:+.4f}" in fact.text() and "every mode is damped" in fact.text()


class TwoModes:
    """A constructed family: two oscillators whose real parts are affine in the speed V (m/s), one growing below
    ``low`` and one above ``high``; straight running is stable only in between (about 3 km/h here, less than the
    4 km/h step of the old 101-node grid, with both ends between two of its nodes)."""

    primary_min = 0.1        # m/s
    primary_scale = 10.0     # m/s: what a small step in speed is measured against (as the axles)
    n = 4

    def __init__(self, low: float, high: float):
        self.low, self.high = low, high

    def validate(self, q: float) -> None:
        pass

    def linear_matrix(self, V: float, q: float):
        import numpy as np

        def oscillator(re: float, omega: float):
            return np.array([[re, omega], [-omega, re]])
        A = np.zeros((4, 4))
        A[:2, :2] = oscillator(0.05 * (self.low - V), 2 * 3.1416 * 4.0)
        A[2:, 2:] = oscillator(0.05 * (V - self.high), 2 * 3.1416 * 9.0)
        return A


def test_a_stable_window_narrower_than_the_grid_is_confirmed_not_missed():
    """The old rule (Brent between 101 grid speeds where the margin changes sign) finds no zero at all for a stable
    window 3 km/h wide lying between two grid nodes and reported both Hopf points missed; the sign check reads the
    margin beside each Hopf point and in the middle of the window, and passes."""
    import numpy as np

    from axles.units import from_kmh
    from bifurcation.equilibria.margins import zero_level
    from comparisons.verify.margin_checks import hopf_sign_row
    from comparisons.verify.plan import VMAX
    from reduced_model.family import MIN_SPEED
    family = TwoModes(from_kmh(196.34), from_kmh(199.37))
    grid = np.linspace(MIN_SPEED, VMAX, 101)
    between = [v for v in grid if from_kmh(196.34) < v < from_kmh(199.37)]
    assert not between and zero_level(family, 1e5, grid) == ()   # what the old rule saw: nothing
    row, points = hopf_sign_row(family, "constructed", 1.0)
    assert row.status is CheckStatus.PASS, row.note
    assert [round(v, 2) for v, _ in points] == [196.34, 199.37]
    assert "no oscillation grows at 196.34-199.37 km/h" in row.note


class MissingHopf(TwoModes):
    """The same two oscillators, but the family hides its second Hopf point from ``find_hopf_points`` (as a continuation
    that missed one would): the margin's sign then changes inside an interval."""

    def __init__(self):
        super().__init__(0.0, 0.0)

    def linear_matrix(self, V: float, q: float):
        import numpy as np
        A = np.zeros((4, 4))
        A[:2, :2] = [[-1.0, 20.0], [-20.0, -1.0]]
        # growing from about 64 to 136 km/h (27.78 m/s = 100 km/h)
        re = -0.01 * (V - 27.78) ** 2 + 1.0
        A[2:, 2:] = [[re, 50.0], [-50.0, re]]
        return A


def test_a_hopf_point_the_continuation_missed_fails_the_sign_check(monkeypatch):
    import numpy as np
    from comparisons.verify import margin_checks as margins
    monkeypatch.setattr(margins, "find_hopf_points", lambda *args, **kw: ())
    from comparisons.verify.plan import VMAX
    from reduced_model.family import MIN_SPEED
    row, points = margins.hopf_sign_row(MissingHopf(), "constructed", 1.0, np.linspace(MIN_SPEED, VMAX, 41))
    assert points == [] and row.status is CheckStatus.FAIL
    assert "a Hopf point the continuation did not find" in row.note


class Divergence(TwoModes):
    """Campaign axle CAMPAIGN-29-02 at 0.5 bar, reduced: at the lowest speed two real eigenvalues grow (a
    divergence, left out of the margin, which is positive there); a little faster they meet and grow on as an
    oscillating pair (the margin negative). The margin changes sign with no Hopf point: the old sign check failed."""

    def __init__(self):
        super().__init__(0.0, 0.0)

    def linear_matrix(self, V: float, q: float):
        import numpy as np
        A = np.zeros((4, 4))
        A[:2, :2] = [[-1.0, 60.0], [-60.0, -1.0]]
        d = 50.0 * (1.0 - V)          # eigenvalues 2 +- sqrt(d): two real ones below 1 m/s, a pair above
        A[2:, 2:] = [[2.0, 1.0], [d, 2.0]]
        return A


def test_a_growing_pair_that_meets_the_real_axis_is_no_missed_hopf_point():
    import numpy as np

    from comparisons.verify.margin_checks import hopf_sign_row
    from comparisons.verify.plan import VMAX
    from reduced_model.family import MIN_SPEED
    row, points = hopf_sign_row(Divergence(), "constructed", 0.5, np.linspace(MIN_SPEED, VMAX, 41))
    assert points == [] and row.status is CheckStatus.PASS, row.note
    assert "where a growing pair meets the real axis (a divergence, not a Hopf point)" in row.note
