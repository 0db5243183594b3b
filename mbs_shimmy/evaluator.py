"""The multibody model's first-order right-hand side at any state, through Exudyn's solver, and its derivatives:
exact from the compiled twin (:mod:`mbs_shimmy.twin`) where it covers the system, else differences.

The built-in ``ComputeODE2Eigenvalues`` / ``ComputeLinearizedSystem`` ignore first-order states (the tyres' slip
angles) and are wrong for spinning wheels on redundant coordinates (``mbs_shimmy/README.md``, Linearisation).  Instead the
Jacobian of the complete first-order system

    y = (q, q', alpha1, alpha2),  q = ([y_axle], [z_axle], psi, theta1, theta2, [phi_gear])  (tree order),
    y' = (q', M(q)^-1 f(q, q', alpha, t), g(q, q', alpha, t))

is formed from what Exudyn's solver itself evaluates at states written into the ``Current`` configuration: the
mass matrix M (``ComputeMassMatrix``) and the right-hand side f (``ComputeODE2RHS``: joint spring-dampers, the
tree's velocity terms, the force user function) of the tree, whose last two coordinates carry the slip angles as
velocities with unit mass (:mod:`mbs_shimmy.system`), so that their rows of M^-1 f are g.  f includes the Exudyn
connectors (tie-rod, drag link) and the joint spring-dampers of the mounts and the steering gear.  Matrices and
states are returned in the extended order (:attr:`mbs_shimmy.linearisation.MbsFamily.state_names`: the reduced model's eight states, then
the new coordinates and their rates).  The derivatives are
fourth-order central differences (five-point stencil, step h = 1e-4 in every coordinate, rad or rad/s): the
truncation error is of order h^4 times the fifth derivative,
(B_y h)^4 ~ 1e-12 relative through the Magic Formula, and with all assumptions on the generalized forces are
otherwise linear in the states.  Rounding limits the full geometry: spring deflections are differences of
positions of order 1 m (|d| - l0 of the tie-rod, R - |P - C| of the tyre), so forces carry ~1e-10 N of rounding
and the Jacobian ~1e-7 absolute on entries up to 1e4 (1e-11 relative; measured by comparing steps).
Gyroscopic terms enter through the rotor moments in f; the mass matrix of the tree is exact.
"""

from __future__ import annotations

from typing import Callable

from mbs_shimmy import engine  # noqa: F401  (before exudyn: chooses Exudyn's compiled module)

# isort: split
import exudyn as exu
import numpy as np

from mbs_shimmy.system import MbsSystem
from bifurcation.derivatives import PARAMETER_STEP

FD_STEP = 1e-4


def speed_is_time(t: float) -> float:
    """The speed schedule of a system that :class:`MbsEvaluator` evaluates: the speed is handed to Exudyn as the
    time of the state (Exudyn passes the Current configuration's time to the force user function), so that it is an
    argument of every evaluation, as the state is, and no holder has to be set and read back."""
    return t


def constant_speed(speed: float) -> Callable[[float], float]:
    """V(t) = ``speed`` (m/s): the schedule of a system whose forces are evaluated directly at one speed."""
    speed = float(speed)
    return lambda t: speed


class MbsEvaluator:
    """First-order right-hand side of an assembled MBS at arbitrary states, through Exudyn's solver; its
    derivatives from the compiled twin (:mod:`mbs_shimmy.twin`) where it covers the system, else from differences
    of that right-hand side."""

    def __init__(self, system: MbsSystem):
        self.system = system
        self.calls = 0          # right-hand-side evaluations by Exudyn, for the cost reports of the benchmarks
        self.twin_calls = 0     # and by the twin
        self.twin_jacobians = 0          # Jacobians from the twin, and from differences (which derivatives a
        self.difference_jacobians = 0    # result used: MbsFamily.derivatives)
        self.twin_forms = 0              # normal forms from the twin's exact derivatives, from differences, and
        self.difference_forms = 0        # from differences where f is not twice differentiable at the equilibrium
        self.kinked_forms = 0            # (MbsFamily.lyapunov_forms)
        self._twin = None
        self._twin_built = False
        # the last batch of the twin's Jacobians (states, speed, outputs): a Newton iteration asks for the same
        # states again, for df/dV (MbsFamily.parameter_derivative) and for a tangent's smoothed df/dx
        self._last_batch: tuple | None = None
        self.m = system.layout.n_mech
        self.n = system.layout.n
        settings = exu.SimulationSettings()
        settings.solution.file.write = False
        settings.timeIntegration.verboseMode = 0
        settings.timeIntegration.solverType = exu.DynamicSolverType.RK44
        self.solver = exu.MainSolverExplicit()
        self.solver.InitializeSolver(system.mbs, settings)

    def rhs(self, y: np.ndarray, speed: float) -> np.ndarray:
        """y' in MBS order for the MBS state y at ``speed`` (m/s; see module docstring)."""
        s, mbs = self.solver, self.system.mbs
        self.calls += 1
        self.system.set_state(y, time=speed)
        s.ComputeMassMatrix(mbs)
        M = np.array(s.GetSystemMassMatrix())
        s.ComputeODE2RHS(mbs)
        f = np.array(s.GetSystemResidual())[0:self.m + 2]
        acc = np.linalg.solve(M, f)
        return np.concatenate([y[self.m:2 * self.m], acc])

    @property
    def twin(self):
        """The system's twin (built at the first use), or None where it does not cover the system."""
        if not self._twin_built:
            from mbs_shimmy.twin import twin_of     # CasADi's import only where derivatives are asked for
            self._twin, self._twin_built = twin_of(self.system), True
        return self._twin

    def exact_jacobian(self, y: np.ndarray, speed: float, key: int = 0) -> tuple[np.ndarray, np.ndarray] | None:
        """(df/dy, df/dV) from the twin at (y, speed), or None where it has none (no twin, a load outside the
        load table); ``key``: the caller's node (:mod:`mbs_shimmy.twin`)."""
        twin = self.twin
        if twin is None:
            return None
        J, Jv, ok, near = twin.jacobian_and_near_kink(np.asarray(y, dtype=float), speed, key)
        if not ok or near:       # about a lift-off: differences (twin_batch)
            return None
        self.twin_jacobians += 1
        return J, Jv

    def twin_batch(self, Y: np.ndarray, speed: float, jacobians: bool = False,
                   kink_rows: bool = True) -> tuple | None:
        """The twin at the states Y (K, n) in one call: (f,) or with ``jacobians`` (f, df/dy, df/dV), MBS order,
        with Exudyn's right-hand side and its differences in the rows where the twin has none (a positive load
        outside the load table, :attr:`~mbs_shimmy.load_table.LoadTable.RANGE`: below 1e-6 of the static load, or
        above 10 times it), and the twin's differences where a wheel's load lies within
        :attr:`~mbs_shimmy.load_table.LoadTable.KINK_BAND` of its static load of zero, lifted or not (below;
        not with ``kink_rows`` False, for a caller that reads only df/dV, which is never differenced, or forms only
        a Newton direction); None where there is no twin."""
        twin = self.twin
        if twin is None:
            return None
        Y = np.asarray(Y, dtype=float)
        fresh = True
        if jacobians:
            last = self._last_batch
            if last is not None and last[1] == speed and last[0].shape == Y.shape and np.array_equal(last[0], Y):
                f, J, Jv, ok, near_kink = (a.copy() for a in last[2])
                fresh = False
            else:
                f, J, Jv, ok, near_kink = twin.rhs_and_jacobians(Y, speed)
                self._last_batch = (Y.copy(), speed, tuple(a.copy() for a in (f, J, Jv, ok, near_kink)))
            out = (f, J, Jv)
            # About a lift-off the forces have a kink at zero load: the exact Jacobian jumps there, and with it a
            # fold's test function as a collocation state crosses it, which Newton on a fold system cannot follow.
            # Central differences of step FD_STEP straddle the kink smoothly, as Exudyn's differences did before
            # the twin covered lifted wheels: the twin's, cheap.
            near, differenced = np.flatnonzero(ok & near_kink), 0
            if len(near) and kink_rows:
                J[near], done = self._twin_differences(Y[near], speed, keys=near)
                ok[near[~done]] = False
                differenced = int(np.sum(done))
        else:
            f, ok = twin.rhs_batch(Y, speed)
            out = (f,)
        if fresh:
            self.twin_calls += int(np.sum(ok))
        if jacobians:
            self.twin_jacobians += int(np.sum(ok)) - differenced if fresh else 0
            self.difference_jacobians += differenced
        for k in np.flatnonzero(~ok):
            if jacobians:
                f[k], J[k] = self.rhs_and_jacobian(Y[k], speed)
                h = PARAMETER_STEP * max(1.0, abs(speed))
                Jv[k] = (self.rhs(Y[k], speed + h) - self.rhs(Y[k], speed - h)) / (2.0 * h)
            else:
                f[k] = self.rhs(Y[k], speed)
        return out

    def _twin_differences(self, Y: np.ndarray, speed: float, step: float = FD_STEP,
                          keys=None) -> tuple[np.ndarray, np.ndarray]:
        """d y'/d y at the states Y (K, n) by second-order central differences of the twin's right-hand side (as
        :meth:`rhs_and_jacobian`, all 2 n K states in one call), and per state whether the twin covered every
        state of its stencil (where it did not, Exudyn's differences take over)."""
        K, n = Y.shape
        E = step * np.eye(n)
        stencil = np.concatenate([Y[:, None, :] + E[None], Y[:, None, :] - E[None]], axis=1).reshape(-1, n)
        # each stencil state starts from its node's load-table interval (``keys``: the nodes' rows in the batch)
        # and leaves the nodes' cache alone: keyed by its own row, a stencil guessed wrong and was evaluated again
        f, ok = self.twin.rhs_batch(stencil, speed, pad=True, remember=False,
                                    keys=None if keys is None else np.repeat(keys, 2 * n))
        self.twin_calls += len(stencil)
        f, ok = f.reshape(K, 2 * n, n), ok.reshape(K, 2 * n)
        J = ((f[:, :n] - f[:, n:]) / (2.0 * step)).transpose(0, 2, 1)
        return J, np.all(ok, axis=1)

    def mass_matrix(self, y: np.ndarray) -> np.ndarray:
        """The mass matrix of the mechanical coordinates (tree order, :class:`~mbs_shimmy.system.Layout`)."""
        self.system.set_state(y)
        self.solver.ComputeMassMatrix(self.system.mbs)
        return np.array(self.solver.GetSystemMassMatrix())[0:self.m, 0:self.m]

    def jacobian(self, y: np.ndarray, speed: float, step: float = FD_STEP) -> np.ndarray:
        """d y'/d y (MBS order) by fourth-order central differences (five-point stencil)."""
        y = np.asarray(y, dtype=float)
        self.difference_jacobians += 1
        J = np.empty((self.n, self.n))

        def f(z):
            return self.rhs(z, speed)
        for j in range(self.n):
            d = np.zeros(self.n)
            d[j] = step
            J[:, j] = (8.0 * (f(y + d) - f(y - d)) - (f(y + 2 * d) - f(y - 2 * d))) / (12.0 * step)
        return J

    def rhs_and_jacobian(self, y: np.ndarray, speed: float, step: float = FD_STEP) -> tuple[np.ndarray, np.ndarray]:
        """y' and d y'/d y (MBS order) by second-order central differences: half the calls of
        :meth:`jacobian`.  Its truncation error, (B_y h)^2 ~ 1e-7 relative through the Magic Formula, only slows
        Newton's convergence on a collocation system (the residual is exact) and moves Floquet multipliers by
        about that much; the linearisation about straight running keeps the five-point stencil."""
        y = np.asarray(y, dtype=float)
        self.difference_jacobians += 1
        f = self.rhs(y, speed)
        J = np.empty((self.n, self.n))
        for j in range(self.n):
            d = np.zeros(self.n)
            d[j] = step
            J[:, j] = (self.rhs(y + d, speed) - self.rhs(y - d, speed)) / (2.0 * step)
        return f, J
