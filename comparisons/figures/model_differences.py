"""What differs between two models in a figure drawn for both (``shimmy figures --model mbs``): at one pressure their
shimmy windows (Hopf speeds shifted, a window in one model only), and in a (V, q) plane where straight running is
stable in one model only."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from axles.units import kmh
from comparisons.results import HopfResult, HopfSummary
from comparisons.windows import ShimmyWindow, ShimmyWindows, pair_windows


def windows_of(problem, hopf_points, p_min: float, p_max: float) -> ShimmyWindows:
    """The shimmy windows (:func:`comparisons.windows.pair_windows`) of a family's Hopf points (toolkit points)
    in the speed window [p_min, p_max] (m/s)."""
    points = tuple(HopfSummary.of(h) for h in sorted(hopf_points, key=lambda h: h.p))
    return pair_windows(problem, HopfResult("", p_min, p_max, points))


@dataclass(frozen=True)
class WindowDifference:
    """One mode's window in the reference model beside the other model's (either None where it has none)."""

    mode: str
    reference: ShimmyWindow | None
    other: ShimmyWindow | None

    @property
    def shifts(self) -> tuple[float | None, float | None]:
        """(onset, end) of the other model minus the reference's (m/s); None where either end is open."""
        if self.reference is None or self.other is None:
            return None, None
        onset = None if self.reference.onset is None or self.other.onset is None else \
            self.other.low - self.reference.low
        end = None if self.reference.end is None or self.other.end is None else self.other.high - self.reference.high
        return onset, end

    def text(self, names: tuple[str, str]) -> str:
        """"yaw: the reduced model 26.63-97.13 km/h, the full geometry 39.23-91.79 km/h (onset +12.60, end -5.34
        km/h)", or "tramp 192.98-345.89 km/h: in the reduced model only"."""
        def span(w: ShimmyWindow) -> str:
            return f"{w.low_kmh:.2f}-{w.high_kmh:.2f} km/h"
        if self.other is None or self.reference is None:
            (name, window) = (names[0], self.reference) if self.other is None else (names[1], self.other)
            return f"{self.mode} window {span(window)}: in {name} only"
        onset, end = (None if s is None else kmh(s) for s in self.shifts)
        moved = ", ".join(f"{what} {s:+.2f} km/h" for what, s in (("onset", onset), ("end", end)) if s is not None)
        return (f"{self.mode} window: {names[0]} {span(self.reference)}, {names[1]} {span(self.other)}"
                + (f" ({moved})" if moved else ""))


def compare_windows(reference: ShimmyWindows, other: ShimmyWindows) -> tuple[WindowDifference, ...]:
    """Pairs the windows of two models: a window of one mode in the reference matches the other model's window of
    the same mode it overlaps most in speed (each window in at most one pair); the rest are windows in one model
    only.  By the speed where each starts."""
    pairs, left = [], list(other.windows)
    for w in reference.windows:
        overlap = [(min(w.high, o.high) - max(w.low, o.low), o) for o in left if o.mode == w.mode]
        overlap = [(size, o) for size, o in overlap if size > 0.0]
        if overlap:
            _, match = max(overlap, key=lambda so: so[0])
            left.remove(match)
            pairs.append(WindowDifference(w.mode, w, match))
        else:
            pairs.append(WindowDifference(w.mode, w, None))
    pairs += [WindowDifference(o.mode, None, o) for o in left]
    return tuple(sorted(pairs, key=lambda d: (d.reference or d.other).low))


def stability_difference(reference_unstable: np.ndarray, other_unstable: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(stable in the reference only, stable in the other only) on a common grid, from the counts of unstable
    eigenvalues of straight running (:func:`comparisons.figures.plots.stability_grid`)."""
    a, b = reference_unstable == 0, other_unstable == 0
    return a & ~b, b & ~a
