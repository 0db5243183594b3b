"""Shimmy windows: the speed stretches where one mode of straight running is unstable, from Hopf points paired by
the mode of their critical eigenvector and the direction of their crossing (``comparisons.api.shimmy_windows`` is
the entry; ``verify`` names its windows the same way)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from axles.units import kmh
from comparisons.results import HopfResult, HopfSummary, Shown, Table
from reduced_model.modes import TRAMP_SHARE, tramp_share


@dataclass(frozen=True)
class ShimmyWindow:
    """A speed window (m/s) where one mode of straight running is unstable: from its ``onset`` Hopf point, where
    the mode's critical pair crosses into the right half-plane as speed rises, to its ``end``, where it returns.
    ``onset`` is None for a window open from the lowest speed, ``end`` None for one open to the top of the speed
    window.  ``points`` are all the mode's Hopf points in the window, by speed (more than two where a second pair
    of the same mode crosses inside it)."""

    mode: str                         # yaw or tramp
    low: float                        # m/s
    high: float                       # m/s
    onset: HopfSummary | None
    end: HopfSummary | None
    points: tuple[HopfSummary, ...]

    @property
    def low_kmh(self) -> float:
        return kmh(self.low)

    @property
    def high_kmh(self) -> float:
        return kmh(self.high)

    def text(self) -> str:
        """"yaw from 12.193 to 134.824 km/h", naming an open end."""
        low = "the lowest speed" if self.onset is None else f"{self.low_kmh:.3f}"
        high = f"the top of the window ({self.high_kmh:g} km/h)" if self.end is None else f"{self.high_kmh:.3f} km/h"
        return f"{self.mode} from {low} to {high}"


@dataclass(frozen=True)
class ShimmyWindows(Shown):
    """The unstable speed windows of straight running, one per mode and stretch of speed, from the Hopf points
    paired by the mode of their critical eigenvector (every Hopf point is in exactly one window)."""

    title: str
    vmin: float                       # m/s
    vmax: float                       # m/s
    windows: tuple[ShimmyWindow, ...]

    def table(self) -> Table:
        rows = tuple((w.mode, "-" if w.onset is None else f"{w.low_kmh:.3f}",
                      "-" if w.end is None else f"{w.high_kmh:.3f}",
                      f"{w.points[0].frequency_hz:.3f}", str(len(w.points))) for w in self.windows)
        return Table(("mode", "onset km/h", "end km/h", "frequency at first Hopf point Hz", "Hopf points"), rows,
                     f"Shimmy windows, {self.title}, {kmh(self.vmin):g}-{kmh(self.vmax):g} km/h "
                     "(onset '-': unstable from the lowest speed; end '-': up to the top of the window)")


# A speed step (m/s) either side of a Hopf point at which the critical pair's real part shows its crossing: its
# slope is O(0.1 1/(m/s)), so the difference is far above the eigenvalues' rounding error.
CROSSING_STEP = 1e-3


def crosses_up(problem, point) -> bool:
    """True where the Hopf point's critical pair enters the right half-plane as speed rises (an onset), False
    where it leaves it (the end of a window): the real part of the eigenvalue nearest i omega just above the point
    against just below it."""
    def real_part_near(speed: float) -> float:
        values = np.linalg.eigvals(problem.linear_matrix(speed, point.q))
        return float(values[np.argmin(np.abs(values - 1j * point.omega))].real)
    return real_part_near(point.p + CROSSING_STEP) > real_part_near(max(point.p - CROSSING_STEP, 1e-9))


def pair_windows(problem, hopf: HopfResult) -> ShimmyWindows:
    """The windows of ``hopf``'s points on the speed family ``problem``: each point is named yaw or tramp by its
    critical eigenvector (the tramp share |psi| / max|theta| against the simulations' mode split) and pairs with the
    next one of the same mode; an end before any onset means the mode is unstable from the lowest speed, an onset
    without an end that it is unstable up to the top of the window.  No Hopf point is left out."""
    by_mode: dict[str, list[tuple[HopfSummary, bool]]] = {}
    for point in hopf.points:
        mode = "tramp" if tramp_share(point.point.eigenvector) > TRAMP_SHARE else "yaw"
        by_mode.setdefault(mode, []).append((point, crosses_up(problem, point.point)))
    windows = []
    for mode, crossings in by_mode.items():
        # unstable pairs of this mode at the lowest speed: as many as the ends that come before their onsets
        running, unstable = 0, 0
        for _, up in crossings:
            running += 1 if up else -1
            unstable = max(unstable, -running)
        low, onset, members = (hopf.vmin, None, []) if unstable else (None, None, [])
        for point, up in crossings:
            if up and unstable == 0:
                low, onset, members = point.speed, point, []
            members.append(point)
            unstable += 1 if up else -1
            if unstable == 0:
                windows.append(ShimmyWindow(mode, low, point.speed, onset, point, tuple(members)))
        if unstable:
            windows.append(ShimmyWindow(mode, low, hopf.vmax, onset, None, tuple(members)))
    return ShimmyWindows(hopf.title, hopf.vmin, hopf.vmax, tuple(sorted(windows, key=lambda w: w.low)))
