"""Which shimmy mode a simulated trajectory is in, window by window, and when it switches.

The two modes of the paper (section 3) differ in frequency and in how much the axle tramps for a given wheel
yaw: at 1.5 bar and t0 = 0.07 m the yaw mode oscillates at 5.3-6.7 Hz with max|psi| / max|theta1| = 0.04, the
tramp mode at 10.6-13.2 Hz with a ratio near 0.3 (computed cycle branches, tests/test_cycles.py); with t0 = 0.25 m
the stable yaw cycles reach 7.5 Hz and a ratio of 0.17 near their fold S1, the stable tramp cycles start at
10.3 Hz and a ratio of 0.33 (figure 9a).  A window is classified from both features, which must agree:

* yaw: ratio below ``ratio_split`` and dominant frequency below ``frequency_split_hz``,
* tramp: ratio above and frequency above,
* none: max|theta1| below ``amplitude_floor`` (the oscillation has died out),
* otherwise the window is ambiguous (a transition, two frequencies beating) and does not vote.

The dominant frequency is the mean rate of upward zero crossings of theta1 about its window mean, crossing times
by linear interpolation.  A switch is reported when a new mode holds for ``persistence`` voting windows in a row;
its time and speed are those of the first of them (window centres).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from reduced_model.trajectory import Trajectory


class Mode(enum.Enum):
    YAW = "yaw"
    TRAMP = "tramp"
    NONE = "none"


@dataclass(frozen=True)
class ModeWindow:
    start: float                 # s
    end: float                   # s
    speed: float                 # m/s at the window centre
    theta1: float                # max |theta1| in the window, rad
    psi: float                   # max |psi| in the window, rad
    frequency_hz: float          # dominant frequency of theta1 (NaN if fewer than two crossings)
    mode: Mode | None            # None: ambiguous, no vote

    @property
    def time(self) -> float:
        return 0.5 * (self.start + self.end)

    @property
    def ratio(self) -> float:
        return self.psi / self.theta1 if self.theta1 > 0.0 else float("nan")


@dataclass(frozen=True)
class ModeSwitch:
    time: float                  # s
    speed: float                 # m/s
    before: Mode
    after: Mode


@dataclass(frozen=True)
class ModeHistory:
    windows: tuple[ModeWindow, ...]
    switches: tuple[ModeSwitch, ...]
    initial: Mode

    @property
    def final(self) -> ModeWindow:
        return self.windows[-1]

    def segments(self, t0: float = 0.0) -> list[tuple[float, Mode]]:
        """(start time s, mode) of each stretch between switches, the first from ``t0``."""
        return [(t0, self.initial)] + [(s.time, s.after) for s in self.switches]

    @property
    def final_mode(self) -> Mode:
        """The mode held at the end (the last voting window decides; ambiguous windows keep the mode)."""
        return self.switches[-1].after if self.switches else self.initial


def peak_abs(t: np.ndarray, y: np.ndarray) -> float:
    """max |y| refined by a parabola through the largest sample and its neighbours."""
    a = np.abs(y)
    k = int(np.argmax(a))
    if k == 0 or k == len(a) - 1:
        return float(a[k])
    ym, y0, yp = a[k - 1], a[k], a[k + 1]
    denom = ym - 2.0 * y0 + yp
    if denom >= 0.0:
        return float(y0)
    return float(y0 - 0.125 * (yp - ym) ** 2 / denom)


def crossing_frequency(t: np.ndarray, y: np.ndarray) -> float:
    """Mean frequency of upward zero crossings of y - mean(y) (NaN with fewer than two crossings)."""
    z = y - np.mean(y)
    idx = np.nonzero((z[:-1] < 0.0) & (z[1:] >= 0.0))[0]
    if len(idx) < 2:
        return float("nan")
    tc = t[idx] - z[idx] * (t[idx + 1] - t[idx]) / (z[idx + 1] - z[idx])
    return float((len(tc) - 1) / (tc[-1] - tc[0]))


@dataclass(frozen=True)
class ModeClassifier:
    window: float = 1.0                            # s
    hop: float = 0.25                              # s between window starts
    ratio_split: float = 0.22                      # max|psi| / max|theta1| between the modes
    frequency_split_hz: float = 8.8                # Hz between the modes
    amplitude_floor: float = math.radians(0.05)    # rad of theta1: below this, no shimmy
    persistence: int = 3                           # voting windows a new mode must hold

    def mode_name(self, ratio: float, frequency_hz: float) -> str:
        """"yaw" below both splits (max|psi| / max|theta1| and frequency), "tramp" above both, else "mixed": how
        Hopf points, cycles and margins are labelled outside a time history."""
        if ratio > self.ratio_split and frequency_hz > self.frequency_split_hz:
            return "tramp"
        if ratio < self.ratio_split and frequency_hz < self.frequency_split_hz:
            return "yaw"
        return "mixed"

    def classify_window(self, t: np.ndarray, theta1: np.ndarray, psi: np.ndarray, speed: float) -> ModeWindow:
        a_theta, a_psi = peak_abs(t, theta1), peak_abs(t, psi)
        freq = crossing_frequency(t, theta1)
        if a_theta < self.amplitude_floor:
            mode: Mode | None = Mode.NONE
        else:
            ratio = a_psi / a_theta
            if not np.isfinite(freq):
                mode = None
            elif ratio < self.ratio_split and freq < self.frequency_split_hz:
                mode = Mode.YAW
            elif ratio > self.ratio_split and freq > self.frequency_split_hz:
                mode = Mode.TRAMP
            else:
                mode = None
        return ModeWindow(start=float(t[0]), end=float(t[-1]), speed=speed, theta1=a_theta, psi=a_psi,
                          frequency_hz=freq, mode=mode)

    def windows(self, trajectory: Trajectory) -> tuple[ModeWindow, ...]:
        t = trajectory.t
        theta1, psi = trajectory.deviation("theta1"), trajectory.deviation("psi")   # about the steady state
        duration = t[-1] - t[0]
        length = min(self.window, duration)
        starts = np.arange(t[0], t[-1] - length + 1e-9, self.hop) if duration > 0 else np.array([t[0]])
        if len(starts) == 0 or starts[-1] < t[-1] - length - 1e-9:
            starts = np.append(starts, t[-1] - length)
        out = []
        for s in starts:
            i0, i1 = np.searchsorted(t, [s, s + length + 1e-12])
            i1 = max(i1, i0 + 3)
            centre = min(int((i0 + i1) // 2), len(t) - 1)
            out.append(self.classify_window(t[i0:i1], theta1[i0:i1], psi[i0:i1], float(trajectory.speed[centre])))
        return tuple(out)

    def classify(self, trajectory: Trajectory) -> ModeHistory:
        """Windows, mode switches and the initial mode of a trajectory."""
        windows = self.windows(trajectory)
        voting = [w for w in windows if w.mode is not None]
        if not voting:
            return ModeHistory(windows=windows, switches=(), initial=Mode.NONE)
        current = voting[0].mode
        switches: list[ModeSwitch] = []
        run: list[ModeWindow] = []
        for w in voting[1:]:
            if w.mode is current:
                run = []
                continue
            if run and w.mode is not run[0].mode:
                run = []
            run.append(w)
            if len(run) >= self.persistence:
                first = run[0]
                switches.append(ModeSwitch(time=first.time, speed=first.speed, before=current, after=first.mode))
                current = first.mode
                run = []
        return ModeHistory(windows=windows, switches=tuple(switches), initial=voting[0].mode)


TRAMP_SHARE = ModeClassifier().ratio_split
"""A mode is tramp where |psi| / max(|theta1|, |theta2|) of its eigenvector exceeds this: the simulations' split."""


def tramp_share(vector: np.ndarray) -> float:
    """|psi| / max(|theta1|, |theta2|) of a state vector in the reduced model's order (an eigenvector's shape)."""
    from reduced_model.model import STATE_NAMES
    v = np.abs(vector)
    th1, th2, psi = (STATE_NAMES.index(n) for n in ("theta1", "theta2", "psi"))
    return float(v[psi] / max(v[th1], v[th2], 1e-300))
