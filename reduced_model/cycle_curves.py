"""Two-parameter curves of cycle folds and torus (Neimark-Sacker) points in the (V, q) plane (figures 8 and 18).

Defining system.  A codimension-one cycle bifurcation is the zero set of its test function restricted to the
manifold of cycles (Govaerts, Numerical Methods for Bifurcations of Dynamical Equilibria, SIAM 2000, ch. 3 and
7, "minimally augmented systems"; Kuznetsov 2004, section 10.3).  Here the cycles are parametrised by
(c, q): c the scaled mean square of the orbit (:meth:`CycleProblem.mean_square`), q the second parameter, with
the speed V and the period T among the cycle's unknowns.  For given (c, q) the cycle is found by Newton's method
on collocation + phase condition + mean square = c (the bordered condensed solve of
:mod:`reduced_model.collocation`), which is the implicit-function elimination of the cycle unknowns from the
augmented system.  What is left is one scalar equation in two unknowns,

* fold of cycles (``cycle_fold``):  phi(c, q) = dV/dc along the cycles at fixed q (the speed component of the
  branch tangent, zero where the one-parameter branch turns),
* torus (``torus``): phi(c, q) = |mu| - 1 of the complex pair of Floquet multipliers being tracked,

continued by the pseudo-arclength engine (:mod:`reduced_model.continuation`) with its 1 x 2 Jacobian from
forward differences of phi (each needs one more inner solve).  The curves run until they leave the (V, q)
window, or the amplitude vanishes: a fold curve then ends at a generalized Hopf (Bautin) point of straight
running, a torus curve at a Hopf-Hopf point (Kuznetsov 2004, sections 8.3 and 8.6), which gives an independent
check against :mod:`reduced_model.hopf_curves`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.optimize

from .continuation import Branch, ContinuationSettings, continue_curve, correct, tangent
from .cycles import SPEED, CyclePoint, CycleProblem, CycleSettings, classify_multipliers, speed_scale, state_scales
from .family import SpeedFamily
from .hopf import MIN_SPEED
from .parameters import ParameterError
from .special_points import BranchStatus, ConvergenceError, PointKind, SpecialPoint

INNER_MAX_ITER = 12
INNER_TOL_SQRT = 1e-6      # weighted Newton step after which the inner cycle solve stops (error ~ step^2)
END_AMPLITUDE = 0.01        # scaled RMS below which a curve is taken to end at a Hopf-type codim-2 point
FD_STEP = 1e-6              # relative forward-difference step for d phi / d(c, q)
JACOBIAN_REUSE = 0.02       # weighted distance within which the difference Jacobian is reused
CURVE_SETTINGS = ContinuationSettings(ds=0.02, ds_min=1e-5, ds_max=0.4, max_steps=300, newton_tol=1e-8,
                                      newton_max_iter=8, max_turn=0.3)


@dataclass(frozen=True)
class CycleCurve:
    """A curve of cycle folds or torus points in (V, q): arrays along the curve (SI) and how each end ended."""

    kind: PointKind
    param: str
    speeds: np.ndarray
    values: np.ndarray
    amplitudes: np.ndarray      # (k, 8) max |x_i| of the critical cycle
    periods: np.ndarray
    status: tuple[BranchStatus, BranchStatus]
    messages: tuple[str, str]
    ends: tuple[tuple[float, float] | None, tuple[float, float] | None]   # (V, q) where the amplitude vanishes

    @property
    def complete(self) -> bool:
        return all(s.is_complete for s in self.status)


class _CurveProblem:
    """phi(c, q) and its forward-difference Jacobian, with the cycle at (c, q) solved inside."""

    def __init__(self, family: SpeedFamily, kind: PointKind, cycle: CyclePoint, settings: CycleSettings):
        if kind not in (PointKind.CYCLE_FOLD, PointKind.TORUS):
            raise ValueError(f"no two-parameter continuation for {kind.value}")
        self.kind = kind
        omega = 2.0 * np.pi / cycle.period
        self.problem = CycleProblem(family, SPEED, cycle.speed, cycle.value, cycle.orbit,
                                    state_scales(family, omega), speed_scale(family), settings)
        self.anchor = self.problem.pack(cycle.orbit, cycle.speed)
        self.w = self.problem.weights()
        c0, _ = self.problem.mean_square(self.anchor)
        self.c_scale = c0
        self.q_scale = 0.1 * max(abs(cycle.value), 1e-12)
        self.pair_angle: float | None = None
        if kind is PointKind.TORUS:
            rest, _ = classify_multipliers(cycle.multipliers)
            pair = rest[np.abs(rest.imag) > 1e-7]
            self.pair_angle = float(abs(np.angle(pair[np.argmin(np.abs(np.abs(pair) - 1.0))])))
        self.last: tuple[np.ndarray, np.ndarray, float] | None = None   # (y, u, phi) of the last evaluation
        self.jacobian: tuple[np.ndarray, np.ndarray] | None = None       # (scaled y, J) of the last differences

    def solve_cycle(self, c: float, q: float, guess: np.ndarray) -> np.ndarray | None:
        """Newton on collocation + phase condition + mean square = c at q (V and T free)."""
        p = self.problem
        try:
            p.set_fixed(value=q)
            u = guess.copy()
            for _ in range(INNER_MAX_ITER):
                G, J = p(u)
                ms, grad = p.mean_square(u)
                du = J.solve_bordered(grad, -np.concatenate([G, [ms - c]]))
                if not np.all(np.isfinite(du)):
                    return None
                u = u + du
                # Quadratic convergence: after a step of size d the error is about d^2.
                if np.linalg.norm(du * self.w) < INNER_TOL_SQRT:
                    return u
        except (ParameterError, np.linalg.LinAlgError):
            return None
        return None

    def test_function(self, u: np.ndarray) -> float:
        p = self.problem
        if self.kind is PointKind.CYCLE_FOLD:
            G, J = p(u)
            _, grad = p.mean_square(u)
            rhs = np.zeros(len(u))
            rhs[-1] = 1.0
            dV_dc = J.solve_bordered(grad, rhs)[-1]
            return float(dV_dc * self.c_scale / p.p_scale)
        rest, _ = classify_multipliers(p.multipliers(u))
        pair = rest[rest.imag > 1e-7]
        if len(pair) == 0:
            return float("nan")
        k = int(np.argmin(np.abs(np.abs(np.angle(pair)) - self.pair_angle)))
        return float(np.abs(pair[k]) - 1.0)

    def phi(self, y: np.ndarray, guess: np.ndarray) -> tuple[float, np.ndarray | None]:
        u = self.solve_cycle(y[0] * self.c_scale, y[1], guess)
        if u is None:
            return float("nan"), None
        return self.test_function(u), u

    def __call__(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """G(y) = phi, DG by forward differences; y = (c / c_scale, q).

        The difference Jacobian is re-evaluated only when y has moved more than JACOBIAN_REUSE (weighted) from
        where it was last taken: within one corrector the engine then runs a chord iteration, which converges
        all the same and needs one inner cycle solve per iteration instead of three.
        """
        f0, u0 = self.phi(y, self.anchor)
        if u0 is None or not np.isfinite(f0):
            return np.array([np.nan]), np.full((1, 2), np.nan)
        scaled = y / np.array([1.0, self.q_scale])
        if self.jacobian is None or np.linalg.norm(scaled - self.jacobian[0]) > JACOBIAN_REUSE:
            J = np.empty((1, 2))
            for i, h in enumerate((FD_STEP, FD_STEP * self.q_scale)):
                yh = y.copy()
                yh[i] += h
                fh, uh = self.phi(yh, u0)
                J[0, i] = (fh - f0) / h if uh is not None else np.nan
            self.jacobian = (scaled, J)
        J = self.jacobian[1].copy()
        self.last = (y.copy(), u0, f0)
        # The Jacobian evaluations moved the problem's q: put it back where u0 belongs.
        self.problem.set_fixed(value=y[1])
        return np.array([f0]), J

    def cycle_at(self, y: np.ndarray) -> np.ndarray:
        if self.last is not None and np.array_equal(self.last[0], y):
            return self.last[1]
        u = self.solve_cycle(y[0] * self.c_scale, y[1], self.anchor)
        if u is None:
            raise ConvergenceError("cycle lost on an accepted point of a bifurcation curve")
        return u

    def accept_point(self, y: np.ndarray) -> CyclePoint:
        """Make the cycle at the accepted y the anchor and phase reference; track the multiplier pair."""
        u = self.cycle_at(y)
        self.problem.set_fixed(value=y[1])
        self.anchor = u
        self.problem.set_reference(self.problem.orbit_of(u))
        point = self.problem.point(u)
        if self.kind is PointKind.TORUS:
            rest, _ = classify_multipliers(point.multipliers)
            pair = rest[rest.imag > 1e-7]
            if len(pair):
                self.pair_angle = float(np.angle(pair[np.argmin(np.abs(np.abs(np.angle(pair)) - self.pair_angle))]))
        return point


def _follow(curve: _CurveProblem, y0: np.ndarray, direction: np.ndarray, lo: float, hi: float, vmin: float, vmax: float,
            settings: ContinuationSettings):
    points: list[CyclePoint] = []
    end: list[tuple[float, float]] = []
    start_state = (curve.anchor.copy(), curve.pair_angle)
    curve.problem.set_reference(curve.problem.orbit_of(curve.anchor))

    def speed(y):
        return curve.cycle_at(y)[-1]

    def accept(branch: Branch) -> str | None:
        y = branch.points[-1]
        k = len(branch.points) - 2
        for get, bound, side in ((lambda y: y[1], lo, -1), (lambda y: y[1], hi, 1), (speed, vmin, -1),
                                 (speed, vmax, 1)):
            if side * (get(y) - bound) <= 0.0:
                continue
            # Cut the step where it leaves the window (Brent on the corrected curve) and stop there.
            try:
                s = scipy.optimize.brentq(lambda s: get(branch.point_at(k, s)[0]) - bound, 0.0,
                                          branch.steps[-1], xtol=1e-12)
                y, t = branch.point_at(k, s)
                branch.points[-1], branch.tangents[-1], branch.steps[-1] = y, t, s
            except (RuntimeError, ValueError, ConvergenceError):
                pass  # keep the point just outside
            point = curve.accept_point(y)
            points.append(point)
            return (f"complete: left the window at {point.speed * 3.6:.3f} km/h, "
                    f"{curve.problem.family.param} = {point.value:.6g}")
        point = curve.accept_point(y)
        points.append(point)
        rms = np.sqrt(max(y[0], 0.0) * curve.c_scale)
        if rms < END_AMPLITUDE and len(points) > 1:
            a, b = points[-2], points[-1]
            ca, cb = branch.points[-2][0], y[0]
            lam = cb / (cb - ca) if cb != ca else 0.0
            end.append((b.speed + lam * (b.speed - a.speed), b.value + lam * (b.value - a.value)))
            what = "Hopf-Hopf" if curve.kind is PointKind.TORUS else "generalized Hopf"
            return (f"complete: the amplitude vanishes at {end[0][0] * 3.6:.3f} km/h, "
                    f"{curve.problem.family.param} = {end[0][1]:.6g} (a {what} point)")
        return None

    weights = np.array([1.0, 1.0 / curve.q_scale])
    first = curve.accept_point(y0)
    points.append(first)
    branch = continue_curve(curve, y0, direction, weights, settings, accept=accept)
    curve.anchor, curve.pair_angle = start_state
    message = branch.message
    if not branch.status.is_complete:
        message = f"{branch.status.value}: {message} (last point at {points[-1].speed * 3.6:.3f} km/h, " \
                  f"{curve.problem.family.param} = {points[-1].value:.6g})"
    return points, branch.status, message, (end[0] if end else None)


def cycle_bifurcation_curve(family: SpeedFamily, point: SpecialPoint, lo: float, hi: float, vmin: float,
                            vmax: float, settings: CycleSettings = CycleSettings(),
                            continuation: ContinuationSettings = CURVE_SETTINGS) -> CycleCurve:
    """The curve of cycle folds or torus points through ``point`` (from a speed branch of ``family`` at fixed
    q), followed both ways in the window [vmin, vmax] x [lo, hi]."""
    vmin = max(vmin, MIN_SPEED)
    cycle: CyclePoint = point.data["cycle"]
    curve = _CurveProblem(family, point.kind, cycle, settings)
    y0 = np.array([1.0, cycle.value])
    # Re-solve at (c0, q0) with q fixed: the located point to the inner tolerance.
    fix_q = np.array([1.0, 0.0])
    result = correct(curve, y0, fix_q, np.array([1.0, 1.0 / curve.q_scale]), CURVE_SETTINGS)
    if result is None:
        raise ConvergenceError(f"could not re-locate the {point.kind.value} at {point.speed * 3.6:.3f} km/h")
    y0 = result[0]
    weights = np.array([1.0, 1.0 / curve.q_scale])
    t0 = tangent(curve(y0)[1], weights, None)
    halves = [_follow(curve, y0, s * t0, lo, hi, vmin, vmax, continuation) for s in (1.0, -1.0)]
    (fwd, s_fwd, m_fwd, e_fwd), (bwd, s_bwd, m_bwd, e_bwd) = halves
    pts = list(reversed(bwd[1:])) + fwd
    return CycleCurve(kind=point.kind, param=family.param,
                      speeds=np.array([p.speed for p in pts]), values=np.array([p.value for p in pts]),
                      amplitudes=np.array([p.amplitude for p in pts]), periods=np.array([p.period for p in pts]),
                      status=(s_bwd, s_fwd), messages=(m_bwd, m_fwd), ends=(e_bwd, e_fwd))
