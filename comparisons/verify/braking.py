"""``shimmy verify``'s section "Under braking": both models at a planned braking level (issue 32).

At the planned cases where the reduced model shimmies (the first in quick mode) the reduced model and the MBS with
every assumption of the reduced model on are linearised about straight running under braking, which is the steady
state Newton finds (not x = 0).  Rows:

* the steady state at 60 km/h (information: the steer and tramp the braking holds), and the two models' steady
  states against each other (a check: they are the same equations, :data:`STEADY_TOL` relative);
* the eigenvalues at the steady state at :data:`~comparisons.verify.context.EIGEN_SPEEDS_KMH` (a check,
  :data:`~comparisons.verify.context.EIGEN_TOL` relative);
* every Hopf speed under braking against free rolling (information: the shift), and the MBS's against the reduced
  model's (a check, :data:`~comparisons.verify.context.HOPF_TOL_KMH`).  A free-rolling Hopf point without a braked
  partner (a mode that braking closed) and a braked one without a free-rolling partner are listed as information.

Status rules as docs/verify.md: FAIL only where the two models differ beyond the tolerance in these same equations,
or where a computation fails; the shifts themselves are information.
"""

from __future__ import annotations

import math

import numpy as np

from axles.braking import PLANNED_BRAKINGS, Braking
from axles.units import from_kmh, kmh
from comparisons import assumption_shifts as shifts
from comparisons.api import family_of
from comparisons.verify.context import EIGEN_SPEEDS_KMH, EIGEN_TOL, HOPF_TOL_KMH, Context, shimmy_cases
from comparisons.verify.plan import VMAX, CaseKind
from comparisons.verify.report import CheckStatus, Row, Section
from bifurcation.equilibria.hopf import find_hopf_points
from reduced_model.model import ShimmyModel

# verify's planned braking levels are axles.braking.PLANNED_BRAKINGS; quick mode keeps the first, and
# ``verify --brake-slip/--brake-force`` replaces them with the one given.
STEADY_TOL = 1e-9          # relative: the two models' steady states under braking
STEADY_SPEED_KMH = 60.0
COLUMNS = ("case", "braking", "point", "free_kmh", "braked_kmh", "shift_kmh", "mbs_reduced_kmh", "frequency_hz",
           "steady_state_deg", "relative_diff")


def brakings_of(ctx: Context) -> tuple[Braking, ...]:
    if ctx.braking is not None and ctx.braking.active:
        return (ctx.braking,)
    return PLANNED_BRAKINGS[:1] if ctx.quick else PLANNED_BRAKINGS


def braking_section(ctx: Context) -> Section:
    from comparisons.studies.assumption_study import match_hopf
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.model import MbsModel
    model = ShimmyModel(params=ctx.axle.params)
    mbs_model = MbsModel(model.params, model.effects, Fidelity.reduced(), ctx.axle.dims)
    cases = [c for c in shimmy_cases(ctx) if c.kind is not CaseKind.ASYMMETRIC]
    cases = cases[:1] if ctx.quick else cases[:2]
    rows = []
    if not cases:
        rows.append(Row({}, CheckStatus.COULD_NOT_CHECK, "no planned case where the reduced model shimmies: no Hopf "
                                                         "speed for braking to shift"))
    for case in cases:
        free_family = family_of(model, case.pressures)
        free = find_hopf_points(free_family, free_family.nominal, 0.0, VMAX)
        for braking in brakings_of(ctx):
            ctx.progress(f"Under braking: {braking} at {case.label}")
            base = {"case": case.label, "braking": str(braking)}
            reduced = family_of(model, case.pressures, "pressure", braking)
            mbs = family_of(mbs_model, case.pressures, "pressure", braking)
            q = reduced.nominal
            rows += steady_rows(base, reduced, mbs, q)
            rows.append(eigen_row(base, reduced, mbs, q))
            braked = find_hopf_points(reduced, q, 0.0, VMAX)
            braked_mbs = find_hopf_points(mbs, q, 0.0, VMAX, lyapunov=False)
            rows += hopf_rows(base, free, braked, braked_mbs, match_hopf)
    return Section(
        key="braking", title="Under braking: both models at a planned braking level", columns=COLUMNS,
        rows=tuple(rows),
        text=(f"Steady braking (MF 6.1 combined slip; the brake force steers each wheel at its offset from the "
              f"kingpin) at the first {'' if ctx.quick else 'two '}planned case{'' if ctx.quick else 's'} with "
              f"shimmy. Straight running under braking is the steady state Newton finds, not x = 0; the Hopf points "
              f"are those of that steady state. Checks: the MBS with every assumption of the reduced model on has "
              f"the same steady state ({STEADY_TOL:g} relative), eigenvalues ({EIGEN_TOL:g}) and Hopf speeds "
              f"({HOPF_TOL_KMH} km/h). Information: each Hopf speed's shift from free rolling. Planned levels: "
              f"{', '.join(str(b) for b in brakings_of(ctx))}; `shimmy verify --brake-slip` sets another."))


def steady_rows(base: dict, reduced, mbs, q: float) -> list[Row]:
    V = from_kmh(STEADY_SPEED_KMH)
    a, b = reduced.equilibrium(V, q), mbs.equilibrium(V, q)
    rel = float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300))
    shown = ", ".join(f"{name} {math.degrees(a[i]):+.4f}" for i, name in ((0, "theta1"), (2, "theta2"), (4, "psi")))
    ok = rel <= STEADY_TOL
    return [Row({**base, "point": f"steady state at {STEADY_SPEED_KMH:g} km/h", "steady_state_deg": shown,
                 "relative_diff": rel}, CheckStatus.PASS if ok else CheckStatus.FAIL,
                "the braking holds the steering deflected; both models' Newton steady states agree" if ok else
                f"the MBS (reduced fidelity) steady state differs by more than {STEADY_TOL:g}")]


def eigen_row(base: dict, reduced, mbs, q: float) -> Row:
    worst = 0.0
    for v in EIGEN_SPEEDS_KMH:
        a = np.sort_complex(np.linalg.eigvals(reduced.linear_matrix(from_kmh(v), q)))
        b = np.sort_complex(np.linalg.eigvals(mbs.linear_matrix(from_kmh(v), q)))
        worst = max(worst, float(np.max(np.abs(a - b)) / np.max(np.abs(a))))
    ok = worst <= EIGEN_TOL
    return Row({**base, "point": "eigenvalues", "relative_diff": worst}, CheckStatus.PASS if ok else CheckStatus.FAIL,
               f"at the steady state, {', '.join(f'{v:g}' for v in EIGEN_SPEEDS_KMH)} km/h (tolerance {EIGEN_TOL:g})")


def hopf_rows(base: dict, free, braked, braked_mbs, match_hopf) -> list[Row]:
    rows = []
    by_braked = {s.reduced_speed: s for s in match_hopf(braked, braked_mbs) if s.reduced_speed is not None}
    for i, s in enumerate(match_hopf(free, braked), 1):
        cells = {**base, "point": f"HB{i}", "free_kmh": shifts.reduced_kmh(s), "braked_kmh": shifts.mbs_kmh(s),
                 "shift_kmh": shifts.shift_kmh(s), "frequency_hz": s.mbs_hz or s.reduced_hz}
        if s.mbs_speed is None:
            rows.append(Row(cells, CheckStatus.INFO, "a free-rolling Hopf point with no partner under braking (the "
                                                     "mode's window closed or left 0-400 km/h)"))
            continue
        partner = by_braked.get(s.mbs_speed)
        mbs_kmh = shifts.mbs_kmh(partner) if partner is not None else None
        cells["mbs_reduced_kmh"] = mbs_kmh
        ok = mbs_kmh is not None and abs(mbs_kmh - kmh(s.mbs_speed)) <= HOPF_TOL_KMH
        note = ("" if s.reduced_speed is not None else "a Hopf point braking adds (no free-rolling partner)")
        rows.append(Row(cells, CheckStatus.PASS if ok else CheckStatus.FAIL,
                        note if ok else f"MBS (reduced fidelity) differs by more than {HOPF_TOL_KMH} km/h"))
    for s in match_hopf(braked, braked_mbs):
        if s.reduced_speed is None:
            rows.append(Row({**base, "point": "MBS only", "mbs_reduced_kmh": shifts.mbs_kmh(s)}, CheckStatus.FAIL,
                            "a Hopf point of the MBS (reduced fidelity) under braking the reduced model lacks"))
    return rows
