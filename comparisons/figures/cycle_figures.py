"""One-parameter limit-cycle diagrams (figures 3, 4, 9, 15)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from axles import paper_reference as paper
from axles.axle import interface_text
from axles.units import kmh
from comparisons.figures.cycle_plots import draw_cycle_diagram, special_point_labels
from comparisons.figures.plots import place_labels
from comparisons.figures.registry import (
    FIG9_VMAX_KMH,
    P_I0_BAR,
    TRAIL_FIG9,
    VMAX_KMH,
    CycleKey,
    DiagramStore,
    Drawing,
    register,
    store_cycles,
)
from bifurcation.cycles.branches import branch_peak
from bifurcation.cycles.problem import CycleBranch, CycleDiagram
from bifurcation.special_points import ConvergenceError, PointStatus
from reduced_model.family import SpeedFamily


def _peak(family: SpeedFamily, branch: CycleBranch, name: str):
    try:
        return branch_peak(family, branch, name)
    except ConvergenceError:
        return branch.peak(name)


def _paper(value) -> str:
    return "" if value is None else f" (paper {value:g})"


def _cycle_notes(prefix: str, family: SpeedFamily, diagram: CycleDiagram, paper_hopf=None, paper_modes=None,
                 paper_special=None, hopf_labels=None) -> list[str]:
    """Hopf speeds, per branch its peaks and frequency range, special points (S/T/PD by the paper's names)."""
    notes = []
    def ref(name):
        i = int(name[2:]) - 1 if name[2:].isdigit() else None
        return paper_hopf[i] if paper_hopf and i is not None and i < len(paper_hopf) else None
    hopf = ", ".join(f"{name} {kmh(h.p):.2f}{_paper(ref(name))}"
                     for name, h in sorted(hopf_names(diagram, hopf_labels), key=lambda nh: nh[1].p))
    notes.append(f"{prefix}Hopf points [km/h]: {hopf or 'none: straight running stable in the whole window'}")
    modes = list(paper_modes.items()) if paper_modes else []
    for i, b in enumerate(diagram.branches):
        ends = (f"{kmh(b.start.p):.2f}" if b.start else "?") + " - " + \
            (f"{kmh(b.end.p):.2f} km/h" if b.end else interface_text(b.message).split(": ", 1)[-1])
        name, ref = modes[i] if i < len(modes) else (f"branch {i + 1}", {})
        if not b.points:
            notes.append(f"{prefix}{name} ({ends}): INCOMPLETE, no cycle computed: {interface_text(b.message)}")
            continue
        th, ps = _peak(family, b, "theta1"), _peak(family, b, "psi")
        f_lo, f_hi = b.frequency_range
        f_ref = ref.get("frequency_hz")
        notes.append(
            f"{prefix}{name} (from {ends}): peak max|theta1| {np.degrees(th.max_abs('theta1')):.3f} deg"
            f"{_paper(ref.get('theta1_deg'))} at {kmh(th.p):.2f} km/h, peak max|psi| "
            f"{np.degrees(ps.max_abs('psi')):.3f} deg{_paper(ref.get('psi_deg'))} at {kmh(ps.p):.2f} km/h, "
            f"frequency {f_lo:.2f}-{f_hi:.2f} Hz" + (f" (paper {f_ref[0]:g}-{f_ref[1]:g})" if f_ref else ""))
        if not b.complete:
            notes.append(f"{prefix}{name}: INCOMPLETE: {interface_text(b.message)}")
    for text, p in special_point_labels(diagram):
        status = "" if p.status is PointStatus.LOCATED else f" ({p.status.value})"
        ref = (paper_special or {}).get(text)
        notes.append(f"{prefix}{text} ({p.kind.value}): {kmh(p.p):.2f} km/h{_paper(ref)}, max|theta1| "
                     f"{np.degrees(p.data['amplitude'][0]):.3f} deg{status}")
    return notes


def hopf_names(diagram: CycleDiagram, names: tuple[str, ...] | None = None) -> list[tuple[str, object]]:
    """(name, Hopf point) as in the paper: branch k (by its lowest speed) is bounded by HB(2k+1) below and
    HB(2k+2) above; a branch that leaves the window at its low end starts at its upper Hopf point.  ``names``
    (in speed order) overrides this where the paper keeps the names of a neighbouring diagram (figure 9b)."""
    if names is not None and len(names) == len(diagram.hopf):
        return list(zip(names, sorted(diagram.hopf, key=lambda h: h.p)))
    out, named = [], set()
    for k, b in enumerate(diagram.branches):
        ends = [h for h in (b.start, b.end) if h is not None]
        if len(ends) == 2:
            ends.sort(key=lambda h: h.p)
            pairs = zip(ends, (2 * k + 1, 2 * k + 2))
        else:
            upper = bool(ends) and b.points and np.mean([p.p for p in b.points]) < ends[0].p
            pairs = zip(ends, (2 * k + 2 if upper else 2 * k + 1,))
        for h, n in pairs:
            out.append((f"HB{n}", h))
            named.add(id(h))
    out += [(f"HB? ({kmh(h.p):.1f})", h) for h in diagram.hopf if id(h) not in named]
    return out


def _no_hopf_text(axes, diagram: CycleDiagram) -> None:
    if not diagram.hopf and not diagram.branches:
        for ax in axes:
            ax.text(0.5, 0.5, "no Hopf point, no limit cycle:\nstraight running stable at every speed",
                    transform=ax.transAxes, ha="center", va="center", fontsize=9, color="0.3")


def _cycle_panels(store: DiagramStore, panels, vmax_kmh: float, figure_title: str, paper_args=None):
    """One column of (max|theta1|, max|psi|) axes per panel (title, CycleKey); returns (figure, notes, complete)."""
    columns = len(panels)
    fig = Figure(figsize=(5.6 * columns, 6.4))
    axes = fig.subplots(2, columns, sharex="col", squeeze=False)
    notes, complete, labelled = [], True, []
    for j, (title, key) in enumerate(panels):
        family, diagram = store_cycles(store, key)
        # The Hopf points carry the paper's names (HB1, HB2 bound the yaw mode, HB3, HB4 the second one), not
        # numbers by speed order.
        names = hopf_names(diagram, ((paper_args or [{}] * columns)[j]).get("hopf_labels"))
        labelled += draw_cycle_diagram(axes[:, j], diagram, family, hopf_labels=names, place=False)
        _no_hopf_text(axes[:, j], diagram)
        axes[0, j].set_title(title, fontsize=10)
        for ax in axes[:, j]:
            ax.set_xlim(0.0, vmax_kmh)
            ax.grid(alpha=0.3)
        prefix = f"{title.split(' ')[0]} " if columns > 1 else ""
        notes += _cycle_notes(prefix, family, diagram, **((paper_args or [{}] * columns)[j]))
        complete &= diagram.complete
    fig.suptitle(figure_title + "\nsolid: stable, dashed: unstable (straight running on the axis, cycles above)",
                 fontsize=10)
    fig.tight_layout()
    for ax, items in labelled:      # once the layout is final
        place_labels(ax, items)
    return fig, notes, complete


@register(3, "cycles_nominal", cost=2)
def draw_cycles_nominal(store: DiagramStore) -> Drawing:
    key = CycleKey(P_I0_BAR, 120.0)
    ref = paper.NOMINAL_PEAK
    fig, notes, complete = _cycle_panels(
        store, [(f"{P_I0_BAR:g} bar ($p_{{i0}}$)", key)], 120.0,
        "Fig. 3: limit cycles at nominal pressure (section 3 model)",
        [dict(paper_hopf=paper.HOPF_SPEEDS_KMH[2.5],
              paper_modes={"yaw mode": {"theta1_deg": ref["theta1_deg"], "psi_deg": ref["psi_deg"]}})])
    notes.append(f"paper: both peaks at {ref['speed_kmh']:g} km/h; "
                 + paper.KNOWN_DIFFERENCES["cycles:2.5:peak_speed"])
    return Drawing(fig, tuple(notes), complete)


@register(4, "cycles_1.5bar_2.7bar", cost=3)
def draw_cycles_low_high(store: DiagramStore) -> Drawing:
    panels = [("(a) 1.5 bar (0.6 $p_{i0}$)", CycleKey(1.5, VMAX_KMH)),
              ("(b) 2.7 bar (1.08 $p_{i0}$)", CycleKey(2.7, VMAX_KMH))]
    fig, notes, complete = _cycle_panels(
        store, panels, VMAX_KMH, "Fig. 4: limit cycles at low and high pressure (section 3 model)",
        [dict(paper_hopf=paper.HOPF_SPEEDS_KMH[1.5], paper_modes={
            "yaw mode": paper.LOW_PRESSURE_MODES["yaw"], "tramp mode": paper.LOW_PRESSURE_MODES["tramp"]}),
         dict(paper_hopf=paper.HOPF_SPEEDS_KMH[2.7])])
    notes.append("(a) HB1: " + paper.KNOWN_DIFFERENCES["hopf:1.5:HB1"])
    return Drawing(fig, tuple(notes), complete)


def _trail_key(t0: float) -> CycleKey:
    return CycleKey(1.5, FIG9_VMAX_KMH, (("t0", t0),))


@register(9, "cycles_trail", cost=7)
def draw_cycles_trail(store: DiagramStore) -> Drawing:
    panels = [(f"({c}) t = {t0:g} m, 1.5 bar", _trail_key(t0)) for c, t0 in zip("ab", TRAIL_FIG9)]
    fig, notes, complete = _cycle_panels(
        store, panels, FIG9_VMAX_KMH, "Fig. 9: limit cycles at two pneumatic trails, 1.5 bar (section 3 model; "
        "the window reaches 800 km/h to show HB4)",
        [dict(paper_special=paper.FIG9A, paper_modes={"yaw mode": {}, "tramp mode": {}}),
         # HB1 has moved below 0.5 km/h, where cycles are not continued: the merged mode shows HB4 only.
         dict(paper_modes={"merged mode": {}}, hopf_labels=("HB4",))])
    return Drawing(fig, tuple(notes), complete)


@register(15, "cycles_low_vertical_stiffness", cost=3)
def draw_cycles_k5(store: DiagramStore) -> Drawing:
    k5 = paper.FIG15A["k5_0_Npm"]
    panels = [(f"({c}) {p:g} bar ({p / P_I0_BAR:.3g} $p_{{i0}}$)", CycleKey(p, VMAX_KMH, (("k5_0", k5),)))
              for c, p in zip("ab", (P_I0_BAR, 2.56))]
    fig, notes, complete = _cycle_panels(
        store, panels, VMAX_KMH, f"Fig. 15: limit cycles with vertical stiffness $k_5$ = {k5:.3g} N/m",
        [dict(paper_modes={"low-speed mode": {"psi_deg": paper.FIG15A["psi_low_mode_deg"]},
                           "high-speed mode": {}}), dict(paper_modes={"low-speed mode": {}, "high-speed mode": {}})])
    return Drawing(fig, tuple(notes), complete)
