"""Where each run's data lives in a Rerun recording, how it is drawn (colours, names), and the stored blueprints.

A recording of one run uses the root paths (``/scene``, ``/states/theta1_deg`` ...); a side-by-side recording of
several runs of the same experiment puts each run's scene under ``/scene/<run>`` and each state of every run
under ``/states/<state>_<unit>/<run>``, so that one time-series view per state overlays the runs.
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
# In side-by-side recordings the run decides the colour (the view says which state it shows).
RUN_COLOURS = (0x1F77B4FF, 0xFF7F0EFF, 0x2CA02CFF, 0xD62728FF)
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
        return self._leaf(f"/tyre_forces/{side}_N")

    @property
    def speed(self) -> str:
        return self._leaf("/speed_kmh")

    @property
    def mode(self) -> str:
        return self._leaf("/mode")

    @property
    def events(self) -> str:
        return self._leaf("/events")


def mode_colour(label: str, index: int) -> int:
    return MODE_COLOURS.get(label, OTHER_MODE_COLOURS[index % len(OTHER_MODE_COLOURS)])


def _whole_run(span: tuple[float, float]):
    """A time axis showing the whole run (the viewer's default follows the time cursor with a narrower window)."""
    import rerun as rr
    from rerun.blueprint.archetypes import TimeAxis
    return TimeAxis(view_range=rr.TimeRange(start=rr.TimeRangeBoundary.absolute(seconds=span[0]),
                                            end=rr.TimeRangeBoundary.absolute(seconds=span[1])))


def _plot(span, **kwargs):
    import rerun.blueprint as rrb
    return rrb.TimeSeriesView(axis_x=_whole_run(span), **kwargs)


def _panels():
    import rerun.blueprint as rrb
    from rerun.blueprint.components import PanelState
    return (rrb.TimePanel(timeline=TIMELINE, state=PanelState.Collapsed),
            rrb.BlueprintPanel(state=PanelState.Collapsed), rrb.SelectionPanel(state=PanelState.Collapsed))


def _states_plot(span, paths: RunPaths, names, title: str):
    return _plot(span, origin="/states", contents=[paths.state(n) for n in names], name=title)


def single_blueprint(span: tuple[float, float]):
    """One run over ``span`` (s): the 3D axle and the text of /info on the left; angles, rates, forces, speed,
    mode lane and events on the right."""
    import rerun.blueprint as rrb
    p = RunPaths()
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="/scene", name="front axle (true angles; arrows: tyre lateral forces)"),
                rrb.TextDocumentView(origin=INFO_ENTITY, name="about this recording"),
                row_shares=[3, 1],
            ),
            rrb.Vertical(
                _states_plot(span, p, ("theta1", "theta2", "psi"), "wheel yaw theta1, theta2, axle tramp psi [deg]"),
                rrb.Tabs(
                    _states_plot(span, p, ("alpha1", "alpha2"), "tyre slip angles alpha1, alpha2 [deg]"),
                    _states_plot(span, p, ("theta1_dot", "theta2_dot", "psi_dot"), "angular rates [deg/s]"),
                    _plot(span, origin="/tyre_forces", name="tyre lateral forces [N]"),
                ),
                _plot(span, origin=p.speed, name="speed [km/h]"),
                rrb.StateTimelineView(origin=p.mode, name="detected mode", time_view=_whole_run(span)),
                rrb.TextLogView(origin=p.events, name="mode switches"),
                row_shares=[4, 3, 1.4, 1.2, 1.2],
            ),
            column_shares=[1, 1.3],
        ),
        *_panels(),
    )


def comparison_blueprint(runs: list[tuple[str, str]], span: tuple[float, float]):
    """Several runs of one experiment over ``span`` (s), ``runs`` = [(key, title)]: the 3D axles next to each
    other with /info, one plot per state overlaying the runs, the speed, and one mode lane per run."""
    import rerun.blueprint as rrb
    scenes = [rrb.Spatial3DView(origin=RunPaths(key).scene, name=title) for key, title in runs]
    plots = [_plot(span, origin=f"/states/{STATE_LEAVES[n]}", name=f"{STATE_WORDS[n]} [{STATE_UNIT_LABELS[n]}]")
             for n in ("theta1", "theta2", "psi", "alpha1", "alpha2", "theta1_dot", "theta2_dot", "psi_dot")]
    plots.append(_plot(span, origin="/speed_kmh", name="speed [km/h]"))
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(*scenes, rrb.TextDocumentView(origin=INFO_ENTITY, name="about this recording"),
                           column_shares=[2] * len(scenes) + [1.2]),
            rrb.Grid(*plots, grid_columns=3),
            rrb.StateTimelineView(origin="/mode", name="detected mode, one lane per model", time_view=_whole_run(span)),
            row_shares=[3, 5, 1.2],
        ),
        *_panels(),
    )
