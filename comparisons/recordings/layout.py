"""Where each run's data lives in a Rerun recording, how it is drawn (colours, names), and the stored blueprints.

A recording of one run uses the root paths (``/scene``, ``/states/theta1_deg`` ...); a side-by-side recording of
several runs of the same experiment puts each run's scene under ``/scene/<run>`` and each state of every run
under ``/states/<state>_<unit>/<run>``, so that one time-series view per state overlays the runs.

Each plotted series comes three ways (see :mod:`comparisons.recordings.writer`): the waveform itself
(``/states/...``, ``/tyre_forces/...``), shown in a window of :data:`WAVE_WINDOW_S` around the time cursor; its
per-cycle upper and lower envelopes (``/envelopes/<series>[/<run>]/upper`` and ``.../lower``), shown over the
whole run; and in side-by-side files the difference of the models' amplitudes (``/difference/<series>/<run>``,
each run minus the first).  Legends are hidden: every view's name says which colour is which, so nothing is
drawn on the data.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from reduced_model.model import STATE_NAMES, STATE_UNITS

TIMELINE = "sim_time"
INFO_ENTITY = "/info"
UNIT_SUFFIX = {"rad": ("deg", "deg", np.degrees), "rad/s": ("deg_per_s", "deg/s", np.degrees)}
STATE_LEAVES = {name: f"{name}_{UNIT_SUFFIX[unit][0]}" for name, unit in zip(STATE_NAMES, STATE_UNITS)}
STATE_UNIT_LABELS = {name: UNIT_SUFFIX[unit][1] for name, unit in zip(STATE_NAMES, STATE_UNITS)}
STATE_WORDS = {"theta1": "right wheel yaw theta1", "theta1_dot": "right wheel yaw rate theta1_dot",
               "theta2": "left wheel yaw theta2", "theta2_dot": "left wheel yaw rate theta2_dot",
               "psi": "axle tramp psi", "psi_dot": "axle tramp rate psi_dot",
               "alpha1": "right tyre slip alpha1", "alpha2": "left tyre slip alpha2"}
# One fixed, distinct colour per state (matplotlib's tab10 order), RGBA.
STATE_COLOURS = dict(zip(STATE_NAMES, (0x1F77B4FF, 0x17BECFFF, 0xFF7F0EFF, 0xBCBD22FF, 0x2CA02CFF, 0x8C564BFF,
                                       0xD62728FF, 0x9467BDFF)))
FORCE_COLOURS = {"right": 0xD62728FF, "left": 0x9467BDFF}
SPEED_COLOUR = 0x333333FF
# In side-by-side recordings the run decides the colour (the view says which state it shows).  The first run
# (the reference) is drawn narrow and opaque, the others wide and translucent: where the lines coincide each
# stays visible, whichever the viewer draws on top.
RUN_COLOURS = (0x1F77B4FF, 0xFF7F0EB0, 0x2CA02CB0, 0xD62728B0)
RUN_WIDTHS = (1.5, 4.0, 4.0, 4.0)
COLOUR_NAMES = {0x1F77B4: "blue", 0x17BECF: "cyan", 0xFF7F0E: "orange", 0xBCBD22: "olive", 0x2CA02C: "green",
                0x8C564B: "brown", 0xD62728: "red", 0x9467BD: "purple", 0x333333: "dark grey"}
ENVELOPE_BOUNDS = ("upper", "lower")
WAVE_WINDOW_S = 4.0         # the waveform views show this much simulated time, centred on the cursor
FORCE_LEAVES = {"right": "right_N", "left": "left_N"}
MODE_COLOURS = {"straight": 0x9E9E9EFF, "yaw": 0x1F77B4FF, "tramp": 0xD62728FF, "mixed": 0x9467BDFF,
                "none": 0xBDBDBDFF}
OTHER_MODE_COLOURS = (0x2CA02CFF, 0xFF7F0EFF, 0x8C564BFF, 0xE377C2FF)


@dataclass(frozen=True)
class RunPaths:
    """Entity paths of one run; ``key`` is "" in a single-run recording."""

    key: str = ""

    def _leaf(self, path: str) -> str:
        return f"{path}/{self.key}" if self.key else path

    @property
    def scene(self) -> str:
        return self._leaf("/scene")

    def state(self, name: str) -> str:
        return self._leaf(f"/states/{STATE_LEAVES[name]}")

    def force(self, side: str) -> str:
        return self._leaf(f"/tyre_forces/{FORCE_LEAVES[side]}")

    def envelope(self, series: str, bound: str) -> str:
        """The upper or lower per-cycle envelope of ``series`` (a leaf: ``theta1_deg``, ``tyre_forces/right_N``)."""
        return f"{self._leaf(f'/envelopes/{series}')}/{bound}"

    def difference(self, series: str) -> str:
        """This run's amplitude minus the reference run's (side-by-side files only)."""
        return self._leaf(f"/difference/{series}")

    @property
    def speed(self) -> str:
        return self._leaf("/speed_kmh")

    @property
    def mode(self) -> str:
        return self._leaf("/mode")

    @property
    def events(self) -> str:
        return self._leaf("/events")


def colour_name(colour: int) -> str:
    return COLOUR_NAMES.get(colour >> 8, f"#{colour >> 8:06X}")


def series_leaves() -> dict[str, str]:
    """Every plotted series but the speed: key (state name or "F_y <side>") -> its leaf under /envelopes."""
    return {**{n: STATE_LEAVES[n] for n in STATE_NAMES},
            **{f"F_y {side}": f"tyre_forces/{leaf}" for side, leaf in FORCE_LEAVES.items()}}


def mode_colour(label: str, index: int) -> int:
    return MODE_COLOURS.get(label, OTHER_MODE_COLOURS[index % len(OTHER_MODE_COLOURS)])


def _whole_run(span: tuple[float, float]):
    """A time axis showing the whole run (the viewer's default follows the time cursor with a narrower window)."""
    import rerun as rr
    from rerun.blueprint.archetypes import TimeAxis
    return TimeAxis(view_range=rr.TimeRange(start=rr.TimeRangeBoundary.absolute(seconds=span[0]),
                                            end=rr.TimeRangeBoundary.absolute(seconds=span[1])))


def _cursor_window():
    """A time axis of :data:`WAVE_WINDOW_S` centred on the time cursor: the waveform slides past as it plays."""
    import rerun as rr
    from rerun.blueprint.archetypes import TimeAxis
    half = 0.5 * WAVE_WINDOW_S
    return TimeAxis(view_range=rr.TimeRange(start=rr.TimeRangeBoundary.cursor_relative(seconds=-half),
                                            end=rr.TimeRangeBoundary.cursor_relative(seconds=half)))


def _plot(axis, **kwargs):
    import rerun.blueprint as rrb
    return rrb.TimeSeriesView(axis_x=axis, plot_legend=rrb.PlotLegend(visible=False), **kwargs)


def _panels():
    import rerun.blueprint as rrb
    from rerun.blueprint.components import PanelState
    return (rrb.TimePanel(timeline=TIMELINE, state=PanelState.Collapsed),
            rrb.BlueprintPanel(state=PanelState.Collapsed), rrb.SelectionPanel(state=PanelState.Collapsed))


def _state_key(names) -> str:
    return ", ".join(f"{n} {colour_name(STATE_COLOURS[n])}" for n in names)


def single_blueprint(span: tuple[float, float]):
    """One run over ``span`` (s): the 3D axle and the text of /info on the left; on the right the envelopes of
    the angles over the whole run, the angles' waveform around the cursor, the other series' envelopes (tabs),
    the speed, the mode lane and the events."""
    import rerun.blueprint as rrb
    p, whole = RunPaths(), _whole_run(span)
    angles = ("theta1", "theta2", "psi")

    def envelopes(names, what):
        return _plot(whole, origin="/envelopes", contents=[f"/envelopes/{STATE_LEAVES[n]}/**" for n in names],
                     name=f"{what}: upper and lower envelope per cycle, whole run ({_state_key(names)})")

    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="/scene", name="front axle (true angles; arrows: tyre lateral forces)"),
                rrb.TextDocumentView(origin=INFO_ENTITY, name="about this recording"),
                row_shares=[3, 1],
            ),
            rrb.Vertical(
                envelopes(angles, "wheel yaw and axle tramp [deg]"),
                _plot(_cursor_window(), origin="/states", contents=[p.state(n) for n in angles],
                      name=f"the same angles [deg], {WAVE_WINDOW_S:g} s around the cursor ({_state_key(angles)})"),
                rrb.Tabs(
                    envelopes(("alpha1", "alpha2"), "tyre slip angles [deg]"),
                    envelopes(("theta1_dot", "theta2_dot", "psi_dot"), "angular rates [deg/s]"),
                    _plot(whole, origin="/envelopes/tyre_forces",
                          name=f"tyre lateral forces [N]: envelopes per cycle (right "
                               f"{colour_name(FORCE_COLOURS['right'])}, left {colour_name(FORCE_COLOURS['left'])})"),
                    _plot(_cursor_window(), origin="/tyre_forces",
                          name=f"tyre lateral forces [N], {WAVE_WINDOW_S:g} s around the cursor"),
                ),
                _plot(whole, origin=p.speed, name="speed [km/h]"),
                rrb.StateTimelineView(origin=p.mode, name="detected mode", time_view=whole),
                rrb.TextLogView(origin=p.events, name="mode switches"),
                row_shares=[3, 3, 3, 1.2, 1, 1],
            ),
            column_shares=[1, 1.3],
        ),
        *_panels(),
    )


def run_key(runs: list[tuple[str, str]]) -> str:
    """Which colour is which run, for the views' names: ``runs`` = [(key, title)], the first the reference."""
    return "; ".join(f"{colour_name(RUN_COLOURS[k % len(RUN_COLOURS)])}{'' if k == 0 else ', wide'}: "
                     f"{title.split(' (')[0]}" for k, (_, title) in enumerate(runs))


def comparison_blueprint(runs: list[tuple[str, str]], span: tuple[float, float]):
    """Several runs of one experiment over ``span`` (s), ``runs`` = [(key, title)], the first the reference: the
    3D axles next to each other with /info; per state the runs' envelopes over the whole run and their waveforms
    around the cursor, overlaid (the reference narrow, the others wide and translucent, so that no run hides
    another); the amplitude differences; the speed; one mode lane per run."""
    import rerun.blueprint as rrb
    whole, key = _whole_run(span), run_key(runs)
    scenes = [rrb.Spatial3DView(origin=RunPaths(k).scene, name=title) for k, title in runs]
    main, others = ("theta1", "psi"), ("theta2", "alpha1", "alpha2", "theta1_dot", "theta2_dot", "psi_dot")

    def envelopes(n):
        return _plot(whole, origin=f"/envelopes/{STATE_LEAVES[n]}",
                     name=f"{STATE_WORDS[n]} [{STATE_UNIT_LABELS[n]}]: envelopes per cycle ({key})")

    def wave(n):
        return _plot(_cursor_window(), origin=f"/states/{STATE_LEAVES[n]}",
                     name=f"{STATE_WORDS[n]} [{STATE_UNIT_LABELS[n]}], {WAVE_WINDOW_S:g} s around the cursor ({key})")

    names = [title.split(" (")[0] for _, title in runs]
    difference = _plot(whole, origin="/difference",
                       contents=[f"/difference/{STATE_LEAVES[n]}/**" for n in ("theta1", "theta2", "psi")],
                       name=f"amplitude difference [deg], {' / '.join(names[1:])} minus {names[0]} "
                            f"({_state_key(('theta1', 'theta2', 'psi'))})")
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(*scenes, rrb.TextDocumentView(origin=INFO_ENTITY, name="about this recording"),
                           column_shares=[2] * len(scenes) + [1.2]),
            rrb.Horizontal(
                rrb.Vertical(*(envelopes(n) for n in main), rrb.Tabs(*(envelopes(n) for n in others))),
                rrb.Vertical(*(wave(n) for n in main), rrb.Tabs(*(wave(n) for n in others))),
                rrb.Vertical(difference, _plot(whole, origin="/speed_kmh", name=f"speed [km/h] ({key})"),
                             row_shares=[2, 1]),
                column_shares=[1, 1, 0.8],
            ),
            rrb.StateTimelineView(origin="/mode", name="detected mode, one lane per model", time_view=whole),
            row_shares=[2.6, 5, 1.2],
        ),
        *_panels(),
    )
