"""Two-parameter curves of cycle folds and torus (Neimark-Sacker) points in the (V, q) plane (figures 8 and 18).

Cycle folds are followed by the minimally augmented system on the collocation discretisation
(:mod:`reduced_model.cycle_fold_system`); torus points still by the reduced formulation below.

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
running, a torus curve at a Hopf-Hopf point (Kuznetsov 2004, sections 8.3 and 8.6).  That end point is not taken
from the extrapolation to zero amplitude: the Hopf curve through the extrapolated point is continued in a small
window around it (:func:`reduced_model.hopf_curves.hopf_curve`) and the codimension-two point is located there
by its own test function (l1 = 0 for a generalized Hopf point, a second eigenvalue pair crossing the imaginary
axis for a Hopf-Hopf point), to the Hopf continuation's accuracy; the extrapolation only says where to look.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.optimize

from .continuation import Branch, ContinuationSettings, continue_curve, correct, tangent
from .cycles import SPEED, CyclePoint, CycleProblem, CycleSettings, classify_multipliers, speed_scale, state_scales
from .family import SpeedFamily
from .hopf import MIN_SPEED, hopf_points
from .parameters import ParameterError
from .special_points import BranchStatus, ConvergenceError, PointKind, PointStatus, SpecialPoint

END_KIND = {PointKind.TORUS: PointKind.HOPF_HOPF, PointKind.CYCLE_FOLD: PointKind.GENERALIZED_HOPF}

# Strong resonances on a torus curve: the critical pair exp(+-i theta) at theta = 2 pi / 3 and pi / 2 (Kuznetsov
# 2004, section 9.5); located where the tracked angle crosses them.
RESONANCES = ((PointKind.RESONANCE_1_3, 2.0 * np.pi / 3.0), (PointKind.RESONANCE_1_4, 0.5 * np.pi))
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
    end_points: tuple[SpecialPoint | None, SpecialPoint | None] = (None, None)  # the located codim-2 points
    special_points: tuple[SpecialPoint, ...] = ()    # codimension-two points of cycles detected along the curve

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)

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
    end_point: list[SpecialPoint] = []
    special: list[SpecialPoint] = []
    arclength = [0.0]
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
        angle_old = abs(curve.pair_angle) if curve.pair_angle is not None else None
        point = curve.accept_point(y)
        points.append(point)
        if curve.kind is PointKind.TORUS and angle_old is not None:
            _resonances(curve, branch, k, angle_old, abs(curve.pair_angle), arclength[-1], special)
        arclength.append(arclength[-1] + branch.steps[-1])
        rms = np.sqrt(max(y[0], 0.0) * curve.c_scale)
        if rms < END_AMPLITUDE and len(points) > 1:
            a, b = points[-2], points[-1]
            ca, cb = branch.points[-2][0], y[0]
            lam = cb / (cb - ca) if cb != ca else 0.0
            guess = (b.speed + lam * (b.speed - a.speed), b.value + lam * (b.value - a.value))
            what = "Hopf-Hopf" if curve.kind is PointKind.TORUS else "generalized Hopf"
            param = curve.problem.family.param
            located = locate_end(curve.problem.family, curve.kind, guess, b, abs(b.speed - a.speed),
                                 abs(b.value - a.value), vmin, vmax)
            if located is None:
                end.append(guess)
                return (f"complete: the amplitude vanishes near {guess[0] * 3.6:.3f} km/h, {param} = "
                        f"{guess[1]:.6g} (extrapolated; no {what} point located there)")
            end.append((located.speed, located.value))
            end_point.append(located)
            return (f"complete: ends at the {what} point located at {located.speed * 3.6:.6f} km/h, {param} = "
                    f"{located.value:.8g} (zero amplitude extrapolated {abs(guess[0] - located.speed) * 3.6:.1e} "
                    f"km/h, {abs(guess[1] - located.value):.1e} away)")
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
    return (points, branch.status, message, (end[0] if end else None), (end_point[0] if end_point else None),
            special)


def _tracked_angle(curve: _CurveProblem, u: np.ndarray) -> float:
    """|arg| of the complex non-trivial multiplier whose angle is nearest the tracked one (NaN if none)."""
    rest, _ = classify_multipliers(curve.problem.multipliers(u))
    pair = rest[rest.imag > 1e-7]
    if len(pair) == 0:
        return float("nan")
    angles = np.abs(np.angle(pair))
    return float(angles[np.argmin(np.abs(angles - abs(curve.pair_angle)))])


def _resonances(curve: _CurveProblem, branch: Branch, k: int, before: float, after: float, s0: float,
                found: list[SpecialPoint]) -> None:
    """Strong resonances 1:3 and 1:4 crossed by the critical angle in the last step, located by Brent."""
    for kind, theta in RESONANCES:
        if (before - theta) * (after - theta) > 0.0:
            continue
        step = branch.steps[-1]
        try:
            s = scipy.optimize.brentq(lambda s: _tracked_angle(curve, curve.cycle_at(branch.point_at(k, s)[0]))
                                      - theta, 0.0, step, xtol=1e-12, rtol=1e-10)
            y, status = branch.point_at(k, s)[0], PointStatus.LOCATED
        except (RuntimeError, ValueError, ConvergenceError):
            y, status = branch.points[-1], PointStatus.NOT_CONVERGED
        u = curve.cycle_at(y)
        curve.problem.set_fixed(value=y[1])
        point = curve.problem.point(u)
        # The evaluations moved the problem's fixed q: put back the accepted point's.
        curve.problem.set_fixed(value=branch.points[-1][1])
        found.append(SpecialPoint(kind=kind, speed=point.speed, value=point.value, bracket=(s0, s0 + step),
                                  status=status, data={"cycle": point, "period": point.period,
                                                       "multipliers": point.multipliers}))





def cycle_bifurcation_curve(family: SpeedFamily, point: SpecialPoint, lo: float, hi: float, vmin: float,
                            vmax: float, settings: CycleSettings = CycleSettings(),
                            continuation: ContinuationSettings = CURVE_SETTINGS) -> CycleCurve:
    """The curve of cycle folds, torus or period-doubling points through ``point`` (from a speed branch of
    ``family`` at fixed q), followed both ways in the window [vmin, vmax] x [lo, hi]."""
    vmin = max(vmin, MIN_SPEED)
    if point.kind is PointKind.CYCLE_FOLD:
        from .cycle_fold_system import fold_curve
        return fold_curve(family, point, lo, hi, vmin, vmax, settings)
    if point.kind is PointKind.PERIOD_DOUBLING:
        from .cycle_fold_system import period_doubling_curve
        return period_doubling_curve(family, point, lo, hi, vmin, vmax, settings)
    cycle: CyclePoint = point.data["cycle"]
    curve = _CurveProblem(family, point.kind, cycle, settings)
    y0 = np.array([1.0, cycle.value])
    # Re-solve at (c0, q0) with q fixed: the located point to the inner tolerance.
    fix_q = np.array([0.0, 1.0])
    result = correct(curve, y0, fix_q, np.array([1.0, 1.0 / curve.q_scale]), CURVE_SETTINGS)
    if result is None:
        raise ConvergenceError(f"could not re-locate the {point.kind.value} at {point.speed * 3.6:.3f} km/h")
    y0 = result[0]
    weights = np.array([1.0, 1.0 / curve.q_scale])
    t0 = tangent(curve(y0)[1], weights, None)
    halves = [_follow(curve, y0, s * t0, lo, hi, vmin, vmax, continuation) for s in (1.0, -1.0)]
    (fwd, s_fwd, m_fwd, e_fwd, p_fwd, r_fwd), (bwd, s_bwd, m_bwd, e_bwd, p_bwd, r_bwd) = halves
    pts = list(reversed(bwd[1:])) + fwd
    return CycleCurve(kind=point.kind, param=family.param,
                      speeds=np.array([p.speed for p in pts]), values=np.array([p.value for p in pts]),
                      amplitudes=np.array([p.amplitude for p in pts]), periods=np.array([p.period for p in pts]),
                      status=(s_bwd, s_fwd), messages=(m_bwd, m_fwd), ends=(e_bwd, e_fwd),
                      end_points=(p_bwd, p_fwd), special_points=tuple(r_bwd + r_fwd))


def locate_end(family: SpeedFamily, kind: PointKind, guess: tuple[float, float], last: CyclePoint, dV: float,
               dq: float, vmin: float, vmax: float) -> SpecialPoint | None:
    """The codimension-two point of straight running where a curve of cycle bifurcations of ``kind`` ends, near
    ``guess`` = (V, q): Hopf points at q = guess[1] within a few curve steps dV of guess[0] (the one with the
    cycle's frequency), the Hopf curve through it continued in a window of a few steps (dV, dq) around the
    guess, and the point of kind END_KIND[kind] located on it by its test function.  None if there is none."""
    from .hopf_curves import hopf_curve

    V0, q0 = guess
    half_V = max(4.0 * dV, 1e-3 * abs(V0))
    half_q = max(4.0 * dq, 1e-4 * abs(q0))
    v_lo, v_hi = max(V0 - half_V, vmin), min(V0 + half_V, vmax)
    try:
        candidates = hopf_points(family, q0, v_lo, v_hi, lyapunov=False)
    except (ParameterError, ConvergenceError):
        return None
    if not candidates:
        return None
    omega = 2.0 * np.pi / last.period
    start = min(candidates, key=lambda h: abs(h.omega - omega))
    try:
        hc = hopf_curve(family, start, q0 - half_q, q0 + half_q, v_lo, v_hi)
    except (ParameterError, ConvergenceError, np.linalg.LinAlgError):
        return None
    found = [p for p in hc.special_points if p.kind is END_KIND[kind] and p.status is PointStatus.LOCATED]
    if not found:
        return None
    return min(found, key=lambda p: ((p.speed - V0) / half_V) ** 2 + ((p.value - q0) / half_q) ** 2)
