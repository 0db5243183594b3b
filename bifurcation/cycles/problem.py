"""Limit cycles (shimmy oscillations): branches born at Hopf points, Floquet multipliers, cycle bifurcations.

Discretisation: orthogonal collocation on an adaptive mesh (:mod:`bifurcation.cycles.collocation`, where the choice
over multiple shooting is argued).  Unknowns u = (node values, period T, free parameter p), p being the family's
primary parameter or its second one; equations: collocation of x' = T f(x) and the integral phase condition
int_0^1 <x(tau), x_ref'(tau)> dtau = 0 against a recent orbit (Doedel, Keller & Kernevez 1991; AUTO notes).
Continuation is Keller's pseudo-arclength (:mod:`bifurcation.continuation`) with the Newton matrix solved by
condensation (:class:`~bifurcation.cycles.collocation.CondensedJacobian`).

Branches (switching at Hopf points, following, events, user points, diagrams) are in
:mod:`bifurcation.cycles.branches`; their functions are re-exported here.  Along a branch, with the trivial
multiplier (the one nearest +1) left out, the test functions defined here are (Kuznetsov 2004, ch. 10; Govaerts
2000, ch. 7):

* ``cycle_fold``: the parameter component of the branch tangent (a multiplier through +1 at a fold),
* ``torus`` (Neimark-Sacker): |mu| - 1 of the complex pair nearest the unit circle, when the number of complex
  multipliers outside the circle changes,
* ``period_doubling``: mu + 1 of the real negative multiplier nearest -1, when the number of real multipliers
  below -1 changes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bifurcation.continuation import ContinuationSettings, correct
from bifurcation.cycles import collocation as col
from bifurcation.cycles import mesh_adaptation
from bifurcation.cycles.multipliers import classify_multipliers
from bifurcation.equilibria.hopf import HopfPoint
from bifurcation.messages import Message
from bifurcation.problem import Family, ProblemError
from bifurcation.special_points import BranchStatus, PointKind, SpecialPoint

PERIOD_LIMIT = 50.0         # period growth (relative to the start) taken as approach to a homoclinic orbit


REMESH_ROUNDS = 3           # adaptations of one accepted point that still misses the tolerance


@dataclass(frozen=True)
class CycleSettings:
    """``tolerance`` bounds the estimated collocation error of every orbit relative to each state's amplitude
    (:func:`bifurcation.cycles.mesh_adaptation.relative_error`); the mesh gains intervals (up to ``max_intervals``) until
    it is met, and loses them (down to ``min_intervals``) where the estimate is far below it."""

    intervals: int = 40                # at the start of a branch
    degree: int = col.DEFAULT_DEGREE
    adapt_every: int = 3               # accepted points between mesh redistributions (AUTO's IAD)
    tolerance: float = 1e-6
    min_intervals: int = 20
    max_intervals: int = 640
    start_amplitude: float = 0.02      # first amplitude, scaled (0.02: 0.002 rad on the largest angle)
    continuation: ContinuationSettings = ContinuationSettings(ds=0.02, ds_min=1e-6, ds_max=0.5, max_steps=400,
                                                              newton_tol=1e-7, newton_max_iter=8,
                                                              max_turn=0.3)


@dataclass(frozen=True)
class CyclePoint:
    """One periodic orbit: parameters (SI), period, max |x_i| of every state (about the equilibrium at p, q where it
    lies off x = 0), Floquet multipliers, stability."""

    p: float                         # the family's primary parameter (SI)
    q: float                         # the family's second parameter (SI)
    period: float                    # s
    amplitude: np.ndarray = field(repr=False)     # (n,) max over the orbit of |x_i - x*_i|, SI (x* = 0 unless the
    #                                               family's equilibrium lies off x = 0: then x* is the equilibrium at p, q)
    multipliers: np.ndarray = field(repr=False)   # (n,) complex, by decreasing modulus, trivial one included
    trivial: complex = 1.0                        # the multiplier taken as the trivial one (nearest +1)
    stable: bool = False
    orbit: col.Orbit = field(default=None, compare=False, repr=False)
    error: float = float("nan")      # estimated collocation error relative to the amplitudes
    tolerance: float = float("nan")  # the tolerance it was computed for
    names: tuple[str, ...] = ()      # state names, from the problem (``family.state_names``)

    @property
    def meets_tolerance(self) -> bool:
        """False when the mesh could not bring the error estimate below the tolerance (NaN: not checked)."""
        return not self.error > self.tolerance

    @property
    def frequency_hz(self) -> float:
        return 1.0 / self.period

    def max_abs(self, name: str) -> float:
        """max |x_name| over the orbit, about the equilibrium as :attr:`amplitude`; the names come from the problem."""
        if name not in self.names:
            raise KeyError(f"no state '{name}' in this problem (states: {', '.join(self.names) or 'unnamed'})")
        return float(self.amplitude[self.names.index(name)])

    @property
    def nontrivial(self) -> np.ndarray:
        """The multipliers without the trivial one, as :func:`classify_multipliers` reads them."""
        return classify_multipliers(self.multipliers)[0]


@dataclass(frozen=True)
class CycleBranch:
    """A branch of cycles in one free parameter, with its special points and how it ended."""

    free: str                                   # the family's primary or its second parameter name
    points: tuple[CyclePoint, ...]
    special_points: tuple[SpecialPoint, ...]
    status: BranchStatus
    message: Message
    start: HopfPoint | None = None              # Hopf point the branch was born at
    end: HopfPoint | None = None                # Hopf point it returned to, if any
    user_points: tuple[CyclePoint, ...] = ()    # orbits at the requested values of the free parameter

    @property
    def complete(self) -> bool:
        return self.status.is_complete

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)

    @property
    def frequency_range(self) -> tuple[float, float]:
        """Lowest and highest frequency (Hz) on the branch, its Hopf end points included."""
        f = [p.frequency_hz for p in self.points]
        f += [h.frequency_hz for h in (self.start, self.end) if h is not None]
        return min(f), max(f)

    def peak(self, name: str) -> CyclePoint:
        """The computed point with the largest max |x_name| (:func:`bifurcation.cycles.branches.branch_peak` refines it)."""
        return max(self.points, key=lambda p: p.max_abs(name))


@dataclass(frozen=True)
class CycleDiagram:
    """All cycle branches born at the Hopf points of the equilibrium in a window [p_min, p_max] at one value of q."""

    q: float
    p_min: float
    p_max: float
    hopf: tuple[HopfPoint, ...]
    branches: tuple[CycleBranch, ...]

    @property
    def complete(self) -> bool:
        return all(b.complete for b in self.branches)

    @property
    def special_points(self) -> tuple[SpecialPoint, ...]:
        return tuple(p for b in self.branches for p in b.special_points)

    def points_of(self, kind: PointKind) -> tuple[SpecialPoint, ...]:
        return tuple(p for p in self.special_points if p.kind is kind)


def state_scales(family: Family, omega: float) -> np.ndarray:
    """Typical size of each state for norms and mesh monitors in an oscillation at omega rad/s, from the problem."""
    return np.asarray(family.state_scales(omega), float)












class CycleProblem:
    """G(u) = 0 for u = (node values, T, p): collocation + phase condition, Jacobian in condensed block form.

    ``free`` is the family's ``primary`` or its ``param``; the other of (p, q) stays fixed.  The mesh
    and the phase reference are state of the problem, updated between continuation steps (:meth:`renormalize`);
    the continuation's own state (tangent, steps since the last adaptation) stays with the algorithm.

    Where f has a kink (a piecewise smooth family), the Jacobian blocks hold one side's exact df/dx, an element of
    Clarke's generalized Jacobian, with which Newton's method converges superlinearly (semismooth Newton: Qi and
    Sun, Math. Programming 58, 1993); ``smoothed`` asks the family for df/dx differenced across the kink instead,
    for a defining system whose residual contains the Jacobian (a fold's test function,
    :mod:`bifurcation.cycle_curves.fold`), which must not jump as a collocation point crosses the kink.  With the
    smoothed Jacobian a branch through large cycles whose collocation points sit about the kink crawled: Newton
    took 5-8 iterations a step and the step did not grow (measured on a multibody axle in docs/results.md).
    """

    def __init__(self, family: Family, free: str, p: float, q: float, orbit: col.Orbit,
                 scales: np.ndarray, p_scale: float, settings: CycleSettings = CycleSettings(),
                 smoothed: bool = False):
        if free not in (family.primary, family.param):
            raise ProblemError(f"cannot continue cycles in '{free}': the family's parameters are {family.primary} and "
                                 f"{family.param}")
        self.family, self.free = family, free
        self.p, self.q = float(p), float(q)
        self.scales, self.p_scale = scales, p_scale
        self.settings, self.smoothed = settings, smoothed
        # one side's exact df/dx where the family has kinks and is not to be smoothed (smooth families: no keyword)
        self.one_sided = not smoothed and bool(getattr(family, "piecewise_smooth", False))
        self.sch = col.scheme(orbit.degree)
        self.degree, self.n = orbit.degree, orbit.n
        self._cache: tuple[np.ndarray, dict] | None = None
        self.set_reference(orbit)

    # --- layout --------------------------------------------------------------------------------------
    @property
    def intervals(self) -> int:
        return len(self.mesh) - 1

    @property
    def size(self) -> int:
        return self.intervals * self.degree * self.n

    def pack(self, orbit: col.Orbit, p: float) -> np.ndarray:
        return np.concatenate([orbit.nodes.ravel(), [orbit.period, p]])

    def orbit_of(self, u: np.ndarray) -> col.Orbit:
        return col.Orbit(mesh=self.mesh, nodes=u[:self.size].reshape(-1, self.n), period=float(u[self.size]),
                         degree=self.degree)

    def parameters(self, free_value: float) -> tuple[float, float]:
        """(p, q) where the free parameter has the value ``free_value``."""
        if self.free == self.family.primary:
            return float(free_value), self.q
        return self.p, float(free_value)

    def set_fixed(self, p: float | None = None, q: float | None = None) -> None:
        """Change the parameter that is not continued (invalidates cached evaluations)."""
        if p is not None:
            self.p = float(p)
        if q is not None:
            self.q = float(q)
        self._cache = None

    def mean_square(self, u: np.ndarray) -> tuple[float, np.ndarray]:
        """Scaled mean square of the orbit, int sum_b (x_b / s_b)^2 dtau, and its gradient in u (zero in T, p)."""
        e = self.evaluate(u)
        gw = self.widths[:, None] * self.sch.weights[None, :]
        Z = e["Xc"] / self.scales ** 2
        value = float(np.einsum("jk,jkn,jkn->", gw, e["Xc"], Z))
        per_interval = 2.0 * np.einsum("jk,ki,jkn->jin", gw, self.sch.L, Z)
        grad = np.zeros((self.size // self.n, self.n))
        np.add.at(grad, col.node_index(self.intervals, self.degree), per_interval)
        return value, np.concatenate([grad.ravel(), [0.0, 0.0]])

    def weights(self) -> np.ndarray:
        nodes = np.tile(1.0 / self.scales, self.intervals * self.degree) / np.sqrt(self.intervals * self.degree)
        return np.concatenate([nodes, [1.0 / self.period_scale, 1.0 / self.p_scale]])

    def set_reference(self, orbit: col.Orbit) -> None:
        """Mesh and phase reference from ``orbit`` (the reference's derivative at the collocation points)."""
        if self._cache is not None and not np.array_equal(orbit.mesh, self.mesh):
            self._cache = None      # f and its Jacobian do not depend on the reference, only on the mesh
        self.mesh = orbit.mesh.copy()
        self.widths = np.diff(self.mesh)
        self.reference = orbit
        self.period_scale = orbit.period
        Y = orbit.interval_values()
        self.ref_derivative = col.collocation_derivatives(Y, self.widths, self.sch)
        gw = self.widths[:, None] * self.sch.weights[None, :]
        per_interval = np.einsum("jk,ki,jkn->jin", gw, self.sch.L, self.ref_derivative)   # (N, m+1, n)
        self.phase_gradient = np.zeros_like(orbit.nodes)
        np.add.at(self.phase_gradient, col.node_index(len(self.widths), self.degree), per_interval)

    # --- evaluation ----------------------------------------------------------------------------------
    def _parameter_derivative(self, P: np.ndarray, p: float, q: float) -> np.ndarray:
        """df/d(free) at the points P (M, n), as the family forms it."""
        return self.family.parameter_derivative(P, p, q, self.free, self.p_scale)

    def _unpack(self, u: np.ndarray) -> dict:
        """Node values per interval, states at the collocation points, period and parameters of u."""
        X = u[:self.size].reshape(-1, self.n)
        T, free = float(u[self.size]), float(u[self.size + 1])
        p, q = self.parameters(free)
        Y = X[col.node_index(self.intervals, self.degree)]
        return {"Y": Y, "Xc": col.collocation_states(Y, self.sch),
                "dX": col.collocation_derivatives(Y, self.widths, self.sch),
                "T": T, "p": p, "q": q, "free": free}

    def _phase(self, Xc: np.ndarray) -> float:
        gw = self.widths[:, None] * self.sch.weights[None, :]                       # (N, m) quadrature
        return float(np.einsum("jk,jkn,jkn->", gw, Xc, self.ref_derivative))

    def evaluate(self, u: np.ndarray) -> dict:
        if self._cache is not None and np.array_equal(self._cache[0], u):
            return self._cache[1]
        N, m, n = self.intervals, self.degree, self.n
        out = self._unpack(u)
        f, Jf = self.family.rhs_and_jacobians(out["Xc"].reshape(-1, n), out["p"], out["q"],
                                              **({"kink_rows": False} if self.one_sided else {}))
        out.update(f=f.reshape(N, m, n), Jf=Jf.reshape(N, m, n, n))
        self._cache = (u.copy(), out)
        return out

    def value(self, u: np.ndarray) -> np.ndarray:
        """G(u) alone (f without its Jacobian), for the corrector's chord iterations."""
        N, m, n = self.intervals, self.degree, self.n
        e = self._unpack(u)
        try:
            f = np.asarray(self.family.rhs(e["Xc"].reshape(-1, n).T, e["p"], e["q"])).T.reshape(N, m, n)
        except ProblemError:
            return np.full(self.size + 1, np.nan)
        return np.concatenate([(e["dX"] - e["T"] * f).ravel(), [self._phase(e["Xc"])]])

    def blocks(self, u: np.ndarray) -> np.ndarray:
        e = self.evaluate(u)
        if "B" not in e:
            e["B"] = col.block_jacobians(e["Jf"], self.widths, e["T"], self.sch)
        return e["B"]

    def __call__(self, u: np.ndarray) -> tuple[np.ndarray, col.CondensedJacobian]:
        N, m, n = self.intervals, self.degree, self.n
        try:
            e = self.evaluate(u)
        except ProblemError:
            nan = np.full((N, m, n), np.nan)
            return (np.full(self.size + 1, np.nan),
                    col.CondensedJacobian(np.full((N, m, n, m + 1, n), np.nan), nan, nan, nan.reshape(-1, n)))
        G = np.concatenate([(e["dX"] - e["T"] * e["f"]).ravel(), [self._phase(e["Xc"])]])
        return G, self._condensed(e, self.blocks(u), e["f"])

    def _condensed(self, e: dict, blocks, f: np.ndarray) -> col.CondensedJacobian:
        """DG from the collocation blocks (of df/dx) and f at the nodes of the unpacked point ``e``."""
        N, m, n = self.intervals, self.degree, self.n
        dfdp = self._parameter_derivative(e["Xc"].reshape(-1, n), e["p"], e["q"]).reshape(N, m, n)
        return col.CondensedJacobian(blocks, -f, -e["T"] * dfdp, self.phase_gradient)

    def smoothed_jacobian(self, u: np.ndarray) -> col.CondensedJacobian:
        """DG at u with df/dx differenced across a kink (the family's ``kink_rows``): a piecewise smooth branch's
        tangents (:func:`bifurcation.continuation.continue_curve`'s ``tangent_jacobian``); DG itself where the
        problem is smoothed already."""
        if not self.one_sided:
            return self(u)[1]
        N, m, n = self.intervals, self.degree, self.n
        e = self._unpack(u)
        f, Jf = self.family.rhs_and_jacobians(e["Xc"].reshape(-1, n), e["p"], e["q"], kink_rows=True)
        blocks = col.block_jacobians(Jf.reshape(N, m, n, n), self.widths, e["T"], self.sch)
        return self._condensed(e, blocks, f.reshape(N, m, n))

    # --- results -------------------------------------------------------------------------------------
    def multipliers(self, u: np.ndarray) -> np.ndarray:
        """Floquet multipliers (all n, trivial included) by decreasing modulus."""
        mu = np.linalg.eigvals(col.monodromy(self.blocks(u)))
        return mu[np.argsort(-np.abs(mu))]

    def point(self, u: np.ndarray) -> CyclePoint:
        orbit = self.orbit_of(u)
        p, q = self.parameters(u[self.size + 1])
        mu = self.multipliers(u)
        rest, trivial = classify_multipliers(mu)
        about = None if getattr(self.family, "origin_equilibrium", True) else self.family.equilibrium(p, q)
        amplitude = orbit.maxima(about=about)
        return CyclePoint(p=p, q=q, period=orbit.period, amplitude=amplitude, multipliers=mu,
                          trivial=trivial, stable=bool(np.all(np.abs(rest) < 1.0)), orbit=orbit,
                          error=mesh_adaptation.relative_error(orbit, self.scales, amplitude),
                          tolerance=self.settings.tolerance,
                          names=tuple(self.family.state_names))

    def needed_intervals(self, orbit: col.Orbit) -> int:
        """Intervals for ``orbit`` to meet the tolerance: more when the estimate exceeds it, fewer (at most
        halved) when it is below 1/20 of it, within [min_intervals, max_intervals]."""
        st = self.settings
        N = orbit.intervals
        err = mesh_adaptation.relative_error(orbit, self.scales)
        if err > st.tolerance or not np.isfinite(err):
            N = mesh_adaptation.refined_intervals(N, err, st.tolerance, orbit.degree)
        elif err < 0.05 * st.tolerance:
            factor = (max(err, 1e-300) / (0.5 * st.tolerance)) ** (1.0 / (orbit.degree + 1))
            N = int(np.ceil(N * max(factor, 0.5)))
        return int(min(max(N, st.min_intervals), st.max_intervals))

    def scaled_rms(self, u: np.ndarray) -> float:
        """Size of the orbit in the weighted norm (zero at a Hopf point): about x = 0, or about its mean for a family
        whose equilibrium lies off x = 0 (``origin_equilibrium`` False)."""
        orbit = self.orbit_of(u)
        size = orbit.mean_square() if getattr(self.family, "origin_equilibrium", True) else orbit.variance()
        return float(np.sqrt(np.sum(size / self.scales ** 2)))

    # --- between steps -------------------------------------------------------------------------------
    def renormalize(self, u: np.ndarray, tangent: np.ndarray | None, steps_since_adapt: int):
        """Every ``adapt_every`` accepted points, and at once when the orbit misses the error tolerance: adapt
        the mesh (number of intervals from :meth:`needed_intervals`, distribution by equidistribution) and make
        the current orbit the phase reference (AUTO's IAD; in between the reference is a recent orbit, which
        fixes the phase just as well).

        After re-meshing, the interpolated orbit is corrected on the new mesh (Newton on the hyperplane through
        it, orthogonal to the interpolated tangent), so that the branch stays on solutions of the discretisation
        actually used.  ``tangent`` (the continuation's tangent at u; None before the first step: nothing is
        done) and ``steps_since_adapt`` (accepted points since the last adaptation, this one included) are the
        caller's state.  Returns None when nothing changed, else (new point, the tangent carried over to the new
        mesh) for the continuation to orient its tangent; the caller then counts its steps from zero again.
        """
        if tangent is None:
            return None
        orbit = self.orbit_of(u)
        N = self.needed_intervals(orbit)
        if N <= orbit.intervals and steps_since_adapt < self.settings.adapt_every:
            return None
        new_mesh = mesh_adaptation.adapted_mesh(orbit, self.scales, intervals=N)
        if N != orbit.intervals or mesh_adaptation.mesh_quality(self.mesh, new_mesh) > 0.05:
            u, tangent = self.move_to_mesh(u, tangent, new_mesh)
            # The number of intervals assumes the error falls as h^(m+1); where the orbit crosses a kink of the
            # right-hand side (a wheel lifting off) it falls slower, and one adaptation can leave it above the
            # tolerance (the full geometry at t0 = 0.25 m: 20 -> 31 intervals, 3.9e-5 -> 1.2e-5 for 1e-5).
            for _ in range(REMESH_ROUNDS - 1):
                orbit = self.orbit_of(u)
                N = self.needed_intervals(orbit)
                if N <= orbit.intervals:
                    break
                moved = self.move_to_mesh(u, tangent, mesh_adaptation.adapted_mesh(orbit, self.scales, intervals=N))
                if moved[0] is u:
                    break
                u, tangent = moved
            return u, tangent
        self.set_reference(orbit)
        return u, tangent

    def move_to_mesh(self, u: np.ndarray, t: np.ndarray, mesh: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The solution u interpolated onto ``mesh`` and corrected there by Newton on the hyperplane through it
        orthogonal to t (carried over too); on failure the old mesh and point are kept.  Returns (u, t)."""
        orbit = self.orbit_of(u)
        t_orbit = col.Orbit(mesh=self.mesh, nodes=t[:self.size].reshape(-1, self.n), period=1.0,
                            degree=self.degree)
        moved = mesh_adaptation.remesh(orbit, mesh)
        old_reference = self.reference
        self.set_reference(moved)
        u_new = self.pack(moved, u[-1])
        t_new = np.concatenate([mesh_adaptation.remesh(t_orbit, mesh).nodes.ravel(), t[-2:]])
        # Where Jacobians are costly, the one at the interpolated orbit serves every chord iteration.
        chord = self.value if self.family.costly_jacobian else None
        result = correct(self, u_new, t_new, self.weights(), self.settings.continuation,
                         blocks=self.blocks_of_unknowns(), value=chord,
                         frozen=self(u_new)[1] if chord is not None else None)
        if result is None:
            self.set_reference(old_reference)
            return u, t
        self.set_reference(self.orbit_of(result[0]))
        return result[0], t_new

    def meet_tolerance(self, u: np.ndarray, t: np.ndarray, rounds: int = 4) -> np.ndarray:
        """Refine the mesh of a single solution (at the start of a branch, or at a fixed parameter) until its
        error estimate meets the tolerance or max_intervals is reached; t fixes the correcting hyperplane."""
        for _ in range(rounds):
            orbit = self.orbit_of(u)
            N = self.needed_intervals(orbit)
            if N <= orbit.intervals:
                break
            u_new, t = self.move_to_mesh(u, t, mesh_adaptation.adapted_mesh(orbit, self.scales, intervals=N))
            if len(u_new) == len(u):
                break
            u = u_new
        return u

    def blocks_of_unknowns(self) -> tuple[slice, ...]:
        """Node values, period, free parameter: Newton converges when each block's weighted step is small."""
        return (slice(0, self.size), slice(self.size, self.size + 1), slice(self.size + 1, self.size + 2))


# --------------------------------------------------------------------------------------------------------
# Single cycles near a computed one
# --------------------------------------------------------------------------------------------------------
