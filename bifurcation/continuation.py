"""Pseudo-arclength continuation of the solution curve of G(u) = 0, G: R^(m+1) -> R^m.

Keller's method (Keller, Lectures on Numerical Methods in Bifurcation Problems, Tata Institute 1987; Allgower &
Georg, Introduction to Numerical Continuation Methods, SIAM 2003, ch. 2): Euler predictor along the tangent, Newton
corrector on G = 0 plus the hyperplane orthogonal to the tangent in a weighted norm, step-size adaptation from the
Newton iteration count and the turn of the tangent.  The algorithm knows nothing of the problem: the caller
passes G and its Jacobian (dense, or a structured operator for large discretisations, see
:func:`_solve_bordered`), a weight per unknown, and an optional re-normalisation applied to accepted points
(for eigenvector phase conditions).  Event location along an accepted step uses :meth:`Branch.point_at`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.optimize

from bifurcation.special_points import BranchStatus
from bifurcation.messages import NO_MESSAGE, Message

Residual = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]  # u -> (G(u), DG(u))
Value = Callable[[np.ndarray], np.ndarray]                         # u -> G(u) alone, for chord iterations
Blocks = tuple[slice, ...] | None                                 # blocks of unknowns with their own scales


@dataclass(frozen=True)
class ContinuationSettings:
    ds: float = 0.02          # initial step in the weighted norm
    ds_min: float = 1e-7
    ds_max: float = 0.1
    max_steps: int = 2000
    newton_tol: float = 1e-10  # on the weighted Newton step
    newton_max_iter: int = 8
    max_turn: float = 0.35     # radians between successive tangents
    chord_max_iter: int = 12   # chord iterations (see :func:`correct`) before falling back to Newton
    grow_iter: int = 3         # Newton iterations up to which the next step grows (by 1.5)
    # Steps tried over a corner where the step size underflows (:func:`step_over`), 0: none.  Only for curves of
    # piecewise smooth problems, whose discretised curve has gaps where a node crosses a kink.
    corner_steps: int = 0
    # Newton's step accepted above ``newton_tol`` but below this, once the residual stopped falling (two iterations
    # that did not halve it): the residual is at its rounding floor and the step is that floor's image through an
    # ill-conditioned Jacobian (a cycle fold made by a kink, thousandths of a degree from its Hopf point).  0: never.
    floor_tol: float = 0.0


def _solve_bordered(J, row: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve [J; row] x = rhs.  J is a dense array or a structured operator with ``shape`` and
    ``solve_bordered(row, rhs)`` (e.g. the condensed collocation system of :mod:`bifurcation.cycles.collocation`,
    which returns NaN when singular: the corrector then fails the step)."""
    if hasattr(J, "solve_bordered"):
        return J.solve_bordered(row, rhs)
    return np.linalg.solve(np.vstack([J, row[None, :]]), rhs)


def tangent(J: np.ndarray, w: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
    """Unit (weighted) null vector of J, oriented along ``previous``."""
    if previous is None and isinstance(J, np.ndarray):
        t = np.linalg.svd(J * (1.0 / w)[None, :])[2][-1] / w
    else:
        # A structured J without a previous tangent: border with a fixed generic row (any row not orthogonal
        # to the null vector gives it); the caller sets the orientation.
        border = previous if previous is not None else np.random.default_rng(0).standard_normal(J.shape[1]) / w
        rhs = np.zeros(J.shape[0] + 1)
        rhs[-1] = 1.0
        t = _solve_bordered(J, border * w * w, rhs)
    t = t / np.linalg.norm(t * w)
    if previous is not None and np.dot(t * w, previous * w) < 0:
        t = -t
    return t


def step_norm(du: np.ndarray, w: np.ndarray, blocks: Blocks) -> float:
    """Size of a Newton step: the largest weighted norm over the blocks of unknowns (the whole vector as one
    block when ``blocks`` is None), so that no block's convergence hides behind another's scale."""
    if blocks is None:
        return float(np.linalg.norm(du * w))
    return max(float(np.linalg.norm(du[b] * w[b])) for b in blocks)


def _chord(value: Value, J, u_pred: np.ndarray, row: np.ndarray, w: np.ndarray, settings: ContinuationSettings,
           blocks: Blocks) -> tuple[np.ndarray, int] | None:
    """Chord iterations on [G(u); <t, u - u_pred>_W] = 0 with the fixed Jacobian J: (u, iterations), or None
    when they do not contract (the caller then runs Newton)."""
    u = u_pred.copy()
    previous = np.inf
    for it in range(1, settings.chord_max_iter + 1):
        G = value(u)
        if not np.all(np.isfinite(G)):
            return None
        du = _solve_bordered(J, row, -np.concatenate([G, [row @ (u - u_pred)]]))
        if not np.all(np.isfinite(du)):
            return None
        u = u + du
        size = step_norm(du, w, blocks)
        if size < settings.newton_tol:
            return u, it
        if size > 0.5 * previous:
            return None
        previous = size
    return None


def correct(residual: Residual, u_pred: np.ndarray, t: np.ndarray, w: np.ndarray, settings: ContinuationSettings,
            anchor: np.ndarray | None = None, blocks: Blocks = None, value: Value | None = None,
            frozen=None) -> tuple[np.ndarray, np.ndarray, int] | None:
    """Newton on [G(u); <t, u - u_pred>_W] = 0.  Returns (u, DG(u), iterations) or None on failure.

    Converged when every block of the step (``blocks``, slices of u, each measured in its own weights) is below
    ``settings.newton_tol``.

    With ``value`` (G alone) and ``frozen`` (DG at a nearby solution, the previous point's), the chord method runs
    first: the frozen Jacobian in every iteration, G alone evaluated (Kelley, Solving Nonlinear Equations with
    Newton's Method, SIAM 2003, section 1.7; AUTO uses it for expensive Jacobians).  It converges linearly, at a
    rate set by how far the predictor moved from the point J belongs to, and is worth it where DG costs many
    evaluations of G (difference Jacobians).  DG is formed once, at the converged point, for the tangent.  The
    iteration count returned is then half the chord count, as a chord iteration gains about half the digits
    of a Newton one (the count drives the step-size control).  When the chord iterations stop contracting, Newton starts again from
    the predictor."""
    row = t * w * w
    if value is not None and frozen is not None and frozen.shape[1] == len(u_pred):
        chord = _chord(value, frozen, u_pred, row, w, settings, blocks)
        if chord is not None:
            u, iterations = chord
            G, J = residual(u)
            if np.all(np.isfinite(G)) and np.max(np.abs(G)) < 1e-7 * (1.0 + np.max(np.abs(u))):
                return u, J, (iterations + 1) // 2
    u = u_pred.copy()
    G, J = residual(u)
    sizes = [float(np.max(np.abs(G)))]
    for it in range(1, settings.newton_max_iter + 1):
        if not np.all(np.isfinite(G)):
            return None
        F = np.concatenate([G, [row @ (u - u_pred)]])
        du = _solve_bordered(J, row, -F)
        u = u + du
        G, J = residual(u)
        sizes.append(float(np.max(np.abs(G))))
        # A small step with the residual not yet small goes on iterating: where G is only piecewise smooth (a
        # state crossing a kink of the right-hand side between iterations) Newton converges linearly, and its
        # steps shrink below the tolerance before the residual does.
        small = np.max(np.abs(G)) < 1e-7 * (1.0 + np.max(np.abs(u)))
        step = step_norm(du, w, blocks)
        if step < settings.newton_tol and small:
            return u, J, it
        stalled = len(sizes) > 3 and sizes[-1] > 0.5 * sizes[-3] and sizes[-2] > 0.5 * sizes[-3]
        if step < settings.floor_tol and small and stalled:
            # all iterations counted (they set the next step): counted only to the floor, a kink's fold curve took
            # longer steps and stalled short of its end
            return u, J, it
    return None


CORNER_MEMORY = 32     # accepted steps whose largest sets the first step over a corner
CORNER_COLLAPSE = 1.0 / 64.0    # a step this far below that largest is taken for a collapse onto a corner


def recent_step(branch: "Branch") -> float:
    """The largest of the last :data:`CORNER_MEMORY` accepted steps (the first step's size at the start)."""
    return max(branch.steps[-CORNER_MEMORY:] + [branch.settings.ds])


def step_over(residual: Residual, branch: "Branch", w: np.ndarray, blocks: Blocks, settings: ContinuationSettings,
              value: Value | None = None, step_bound=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, int] | None:
    """A step over a corner of the curve: (u, DG(u), tangent, ds, iterations), or None.

    Where the problem is only piecewise smooth (a right-hand side with a kink, discretised at fixed nodes), the
    discretised curve has a steep piece wherever a node crosses the kink: the Jacobian of G changes there over the
    width of a difference step, so the step size collapses onto the crossing (:func:`continue_curve` calls this
    once its retries fall to :data:`CORNER_COLLAPSE` of :func:`recent_step`, or to ``ds_min``).  The curve of the
    problem itself goes on (the discretised one on either side of the crossing approximates it to the
    discretisation's accuracy), so the corrector is started beyond the crossing instead: steps of 1, 2, 4, ...
    times the largest of the last :data:`CORNER_MEMORY` accepted steps, the first that converges with its tangent
    within ``max_turn`` of the one before the corner, i.e. the curve going on as it came (and within
    ``step_bound``, as :func:`continue_curve`'s steps).  The caller records the
    gap (``Branch.corners``); events on such a step may fail to be located and are then reported by bracket."""
    u, t = branch.points[-1], branch.tangents[-1]
    first = recent_step(branch)
    for j in range(settings.corner_steps):
        ds = min(first * 2.0 ** j, settings.ds_max)
        result = correct(residual, u + ds * t, t, w, settings, blocks=blocks, value=value, frozen=branch.jacobian)
        if result is None:
            continue
        u_new, J_new, iters = result
        t_new = branch.tangent_of(u_new, J_new, w, t)
        bounded = step_bound is None or step_bound(u, u_new) <= 1.0
        if bounded and np.dot(t_new * w, t * w) >= np.cos(settings.max_turn):
            return u_new, J_new, t_new, ds, iters
        if ds >= settings.ds_max:
            break
    return None


@dataclass(frozen=True)
class Stop:
    """What an ``accept`` callback of :func:`continue_curve` returns to end a curve: its status and where."""

    status: BranchStatus
    message: Message = NO_MESSAGE


@dataclass
class Branch:
    """Accepted points u_k with tangents t_k; the branch stopped with ``status`` (``message`` says where)."""

    residual: Residual
    weights: np.ndarray
    settings: ContinuationSettings
    points: list[np.ndarray] = field(default_factory=list)
    tangents: list[np.ndarray] = field(default_factory=list)
    steps: list[float] = field(default_factory=list)  # ds used to reach point k from k-1
    status: BranchStatus = BranchStatus.MAX_STEPS
    message: Message = NO_MESSAGE

    blocks: tuple[slice, ...] | None = None
    value: Value | None = None          # G alone, for chord iterations (:func:`correct`)
    jacobian: object = None             # DG at the last accepted point, for chord iterations
    corners: list[int] = field(default_factory=list)    # points reached by a step over a corner (:func:`step_over`)
    tangent_jacobian: Callable | None = None    # DG for the tangents where not Newton's (:func:`continue_curve`)

    def tangent_of(self, u: np.ndarray, J, w: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
        """The tangent at the solution u, whose Newton Jacobian is J (:attr:`tangent_jacobian`'s where set)."""
        return tangent(J if self.tangent_jacobian is None else self.tangent_jacobian(u), w, previous)

    def point_at(self, k: int, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Corrected point at arclength s from point k along its tangent, and the tangent there (only for the
        last step: after a re-discretisation earlier points may have another size)."""
        u_pred = self.points[k] + s * self.tangents[k]
        result = correct(self.residual, u_pred, self.tangents[k], self.weights, self.settings, blocks=self.blocks,
                         value=self.value, frozen=self.jacobian)
        if result is None:
            raise RuntimeError(f"corrector failed at s = {s:.3g} after point {k}")
        u, J, _ = result
        return u, self.tangent_of(u, J, self.weights, self.tangents[k])


def locate_on_step(branch: Branch, k: int, s_hi: float, fun: Callable[[np.ndarray, np.ndarray], float],
                   xtol: float = 1e-12, rtol: float = 1e-10) -> tuple[np.ndarray, np.ndarray, bool]:
    """A zero of fun(u, t) on the corrected branch between point k and arclength s_hi beyond it, by Brent's
    method: (u, t, located).  When Brent fails (no sign change, or a corrector failure) the point k + 1 is
    returned with located False, so that the caller can report the bracket."""
    try:
        s = scipy.optimize.brentq(lambda s: fun(*branch.point_at(k, s)), 0.0, s_hi, xtol=xtol, rtol=rtol)
        u, t = branch.point_at(k, s)
        return u, t, True
    except (RuntimeError, ValueError):
        return branch.points[k + 1], branch.tangents[k + 1], False


def continue_curve(residual: Residual, u0: np.ndarray, direction: np.ndarray | None, weights,
                   settings: ContinuationSettings = ContinuationSettings(),
                   accept: Callable[[Branch], Stop | None] | None = None,
                   renormalize: Callable[[np.ndarray], object] | None = None, blocks=None,
                   step_bound: Callable[[np.ndarray, np.ndarray], float] | None = None,
                   value: Value | None = None, tangent_jacobian: Callable | None = None) -> Branch:
    """Follow G(u) = 0 from u0 (already a solution) in ``direction``.

    ``accept(branch)`` runs after each accepted point and returns None to go on, or a :class:`Stop` to end the
    curve with its status and message.  ``renormalize`` maps an accepted point to an equivalent
    one (same solution, new phase/normalisation or a new discretisation), or returns None to keep it; it may
    return (u, previous tangent in u's layout) when the number of unknowns changed.  The residual must be
    consistent with the renormalised point.  ``weights`` and ``blocks`` (slices of u for the Newton test, see
    :func:`correct`) may be callables, re-read after every renormalisation.  ``step_bound(u_old, u_new)`` is the
    size of a step relative to a bound the caller sets (e.g. on one parameter): a step above 1 is retried
    shorter, and the next step is not predicted longer than the bound allows.  ``value`` (G alone) lets the
    corrector run chord iterations with the last point's Jacobian (:func:`correct`), for residuals whose
    Jacobian is expensive.  ``tangent_jacobian(u)``: DG at a solution for its tangent, where it is not the one
    Newton's method uses: a piecewise smooth problem converges with one side's exact Jacobian (an element of the
    generalized Jacobian: semismooth Newton, Qi and Sun 1993), while its tangent, whose sign change in a parameter
    is a fold, is taken from a Jacobian smoothed across the kink, so that a collocation point crossing the kink
    does not make the tangent jump (a spurious pair of folds).
    """
    def current():
        w_ = np.asarray(weights() if callable(weights) else weights, dtype=float)
        return w_, (blocks() if callable(blocks) else blocks)

    w, blk = current()
    branch = Branch(residual=residual, weights=w, settings=settings, blocks=blk, value=value,
                    tangent_jacobian=tangent_jacobian)
    G, J = residual(u0)
    branch.jacobian = J
    if np.max(np.abs(G)) > 1e-6 * (1.0 + np.max(np.abs(u0))):
        branch.status, branch.message = BranchStatus.NEWTON_FAILED, Message.of("start point is not a solution")
        return branch
    t = branch.tangent_of(u0, J, w, None)
    if direction is not None and np.dot(t * w, direction * w) < 0:
        t = -t
    branch.points.append(u0)
    branch.tangents.append(t)
    branch.steps.append(0.0)
    ds = settings.ds
    for _ in range(settings.max_steps):
        u, t = branch.points[-1], branch.tangents[-1]
        tried_over = False
        while True:
            result = correct(residual, u + ds * t, t, w, settings, blocks=blk, value=value, frozen=branch.jacobian)
            if result is not None:
                u_new, J_new, iters = result
                t_new = branch.tangent_of(u_new, J_new, w, t)
                turn = np.arccos(np.clip(np.dot(t_new * w, t * w), -1.0, 1.0))
                ratio = step_bound(u, u_new) if step_bound is not None else 0.0
                if turn <= settings.max_turn and ratio <= 1.0:
                    break
                if turn <= settings.max_turn and ds / ratio >= settings.ds_min:
                    ds = 0.95 * ds / ratio
                    continue
            ds *= 0.5
            # A step size collapsing far below the recent ones: a corner, where the problem is piecewise smooth
            # (once per point, before the step size underflows).
            corner = settings.corner_steps and not tried_over and ds < max(CORNER_COLLAPSE * recent_step(branch),
                                                                           settings.ds_min)
            over = step_over(residual, branch, w, blk, settings, value, step_bound) if corner else None
            tried_over = tried_over or corner
            if over is not None:
                u_new, J_new, t_new, ds, iters = over
                ratio = 0.0
                branch.corners.append(len(branch.points))
                break
            if ds < settings.ds_min:
                branch.status = BranchStatus.STEP_UNDERFLOW
                branch.message = Message.of(f"step size underflow after {len(branch.points)} points")
                return branch
        branch.points.append(u_new)
        branch.tangents.append(t_new)
        branch.steps.append(ds)
        branch.jacobian = J_new
        if accept is not None:
            stop = accept(branch)
            if stop is not None:
                branch.status, branch.message = stop.status, stop.message
                return branch
        if renormalize is not None:
            # After the events of this step are located: they need the residual the step was computed with.
            renormalized = renormalize(branch.points[-1])
            if renormalized is not None:
                previous = branch.tangents[-1]
                if isinstance(renormalized, tuple):
                    renormalized, previous = renormalized
                w, blk = current()
                branch.weights, branch.blocks = w, blk
                branch.points[-1] = renormalized
                branch.jacobian = residual(renormalized)[1]
                branch.tangents[-1] = branch.tangent_of(renormalized, branch.jacobian, w, previous)
        ds_next = ds * (1.5 if iters <= settings.grow_iter else 1.0 if iters <= max(5, settings.grow_iter) else 0.6)
        if step_bound is not None and ratio > 0.0:
            ds_next = min(ds_next, 0.95 * ds / ratio)
        ds = min(ds_next, settings.ds_max)
    branch.status = BranchStatus.MAX_STEPS
    branch.message = Message.of(f"stopped after {settings.max_steps} steps")
    return branch
