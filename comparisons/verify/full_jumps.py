"""The jumps of the full geometry: in each of its bistable windows, speed ramps up and down through it in the full
MBS and in the reduced model, the same ramps for both (:mod:`comparisons.verify.cycles`, whose ramp, classifier
and recording pieces are used here with the full geometry in place of the MBS with the reduced model's
assumptions).

The window's two states come from the full geometry's own branches: straight running (where it is stable) or a
stable cycle, the one whose stable stretch reaches lower is the state below the window.  The ramps are information:
a jump under a slow ramp is a delayed loss of stability whose speed is set by how near the state is to the cycle,
not a well-posed quantity, and the reduced model in the same ramp is another model, with its own windows.
"""

from __future__ import annotations

from axles.units import from_kmh, kmh
from comparisons.verify.context import Context
from comparisons.verify.file_names import pressure_part
from comparisons.verify.cycles import _record_both
from comparisons.verify.jump_experiments import (
    RAMP_KMH_S,
    JumpSetup,
    classifier_for,
    ramps,
    run_ramp,
    snap,
    stable_cycles_at,
    stable_reach,
    window_points,
)
from comparisons.verify.plan import BistableCase
from comparisons.verify.report import CheckStatus, Row


def cycle_mode(classifier, cycle):
    """The mode a classifier names a steady cycle by its max |psi| / max |theta1| and frequency."""
    from reduced_model.modes import Mode
    ratio = cycle.max_abs("psi") / cycle.max_abs("theta1")
    tramp = ratio > classifier.ratio_split and cycle.frequency_hz > classifier.frequency_split_hz
    return Mode.TRAMP if tramp else Mode.YAW


def full_jump_setup(case: BistableCase, family, diagram, window: tuple[float, float]) -> JumpSetup | None:
    """The jump experiments of one window (m/s) of the full geometry's diagram; None when its two states are not
    told apart by the mode classifier (two cycles of the same mode)."""
    from comparisons.studies.kick import stable_straight_running
    from reduced_model.modes import Mode, ModeClassifier
    named = window_points(diagram)
    ends = list(named.values()) + [kmh(h.p) for h in diagram.hopf]
    low, high = snap(kmh(window[0]), ends), snap(kmh(window[1]), ends)
    mid = from_kmh(0.5 * (low + high))
    cycles = list({id(c): c for c in stable_cycles_at(diagram, mid)}.values())   # one per stable stretch
    classifier = classifier_for(cycles) if len(cycles) >= 2 else ModeClassifier()
    states = [(stable_reach(diagram, c), cycle_mode(classifier, c)) for c in cycles]
    states += [(a, Mode.NONE) for a, b in stable_straight_running(family, diagram) if a <= mid <= b]
    if len(states) < 2:
        return None
    (_, below), (_, above) = sorted(states, key=lambda s: s[0])[:2]
    if below is above:
        return None
    margin = max(20.0, 1.5 * (high - low))
    return JumpSetup(case, diagram, False, named, low, high, cycles, classifier.classify, below, above,
                     max(1.0, low - margin), high + margin)


def jump_rows(ctx: Context, label: str, case: BistableCase, family, diagram,
              windows) -> tuple[list[Row], list[str]]:
    """Rows and recording names of the ramps through every window of the full geometry."""
    from mbs_shimmy.fidelity import Fidelity
    rows, recordings = [], []
    tag = pressure_part(case.pressure_bar)
    for window in windows:
        setup = full_jump_setup(case, family, diagram, window)
        where = f"window {kmh(window[0]):.2f}-{kmh(window[1]):.2f} km/h"
        if setup is None:
            rows.append(Row({"case": label, "what": f"{where}: ramps"}, CheckStatus.INFO,
                            "not run: the window's two states are of one mode (a ramp cannot tell them apart)"))
            continue
        for ramp in ramps(setup, RAMP_KMH_S[ctx.quick]):
            ctx.progress(f"Full geometry: {ramp.name} {setup.v_lo:.0f}-{setup.v_hi:.0f} km/h, {where}")
            found, both = run_ramp(setup, ramp, Fidelity.full())
            name = f"full_{ramp.name.replace(' ', '_')}_{tag}_{kmh(window[0]):.0f}kmh_both.rrd"   # unique per window
            recordings += _record_both(ctx, name, both, f"{ramp.name} through the full geometry's {where}: "
                                                        f"reduced model and full geometry side by side", case,
                                     mbs_title="full geometry, MBS (all assumptions off)")
            reduced = found["reduced"]
            end = setup.v_hi if ramp.up else setup.v_lo
            held = found["mbs"] is not None and abs(found["mbs"] - end) < 1e-6
            rate = RAMP_KMH_S[ctx.quick]
            if found["mbs"] is None:
                full = "the full geometry does not jump before the run ends"
            elif held:
                full = (f"the full geometry jumps only in the hold at the ramp's end speed {end:.1f} km/h (not a "
                        f"jump speed)")
            else:
                delay = found["mbs"] - ramp.edge
                full = (f"the full geometry jumps at {found['mbs']:.2f} km/h, {delay:+.2f} km/h "
                        f"({abs(delay) / rate:.1f} s) past its window's end")
            rows.append(Row({"case": label, "what": f"{where}: {ramp.name} at {rate:g} km/h/s "
                             f"{ramp.before.value} -> {ramp.after.value}",
                             "speed_kmh": None if held else found["mbs"],
                             "window_end_kmh": ramp.edge, "reduced_jump_kmh": reduced}, CheckStatus.INFO,
                            full + ("; the reduced model does not make this jump in the same ramp" if reduced is None
                                    else f"; the reduced model jumps at {reduced:.1f} km/h in the same ramp")
                            + " (information: a ramp's jump speed is a delayed loss of stability, not well posed)"))
    return rows, recordings

