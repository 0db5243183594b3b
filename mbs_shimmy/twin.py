"""The differentiable twin of the multibody axle: Exudyn's equations of motion as a CasADi graph, for exact
derivatives.

Exudyn stays the model: every right-hand side a reported result rests on is Exudyn's.  The twin gives what
differences of Exudyn's right-hand side gave before, at a fraction of the cost and to rounding: the Jacobian, the
derivative in the speed and directional second derivatives.  It is generated from the assembled Exudyn system
itself (:mod:`mbs_shimmy.twin_equations`: its kinematic trees, markers and connectors as Exudyn stores them, and
the compiled user function's own generic text and constants), never typed from the model again;
``tests/mbs/test_mbs_twin.py`` checks that its right-hand side equals Exudyn's to 1e-10 relative and its Jacobian
Exudyn's differences.  CasADi builds the SX graph of the equations, differentiates it (Lagrange's equations from
the kinetic energy, then the Jacobian) and evaluates it in its virtual machine; JAX was measured against it
(``tools/twin_candidates.py``, numbers in the commit that chose CasADi): its compile time per axle was 12 s for
the right-hand side alone, against 1-2 s here for everything, and every new parameter value is a new axle.

The load table's interpolation reads four rows chosen by the load.  An SX graph has no lookup by a computed
index, so the interval k of each wheel is an input, with its rows: the function also returns each wheel's table
position x and whether x lies in the interval it was given; a call that guessed k wrong is repeated with k from x.
The guess is the last k at the same node of the caller (``key``): in a continuation loads move little.

Coverage: the exact kinematics at a steady speed (every fidelity with ``small_angles`` off).  The first-order
kinematics (``small_angles``) run a Python user function with Exudyn's coordinate connectors and keep difference
derivatives (:func:`twin_of` returns None); at a state whose load leaves the load table the twin says so
(``ok`` False) and its caller uses differences there.
"""

from __future__ import annotations

import hashlib

import casadi as ca
import numpy as np

from mbs_shimmy import compiled_stage
from mbs_shimmy.twin_equations import NotCovered, TwinData, applied_forces, kinetic_energy
from mbs_shimmy.tyre_element import lagrange_weights

OPS = (ca.sin, ca.cos, ca.atan, ca.sqrt, ca.asin, ca.if_else)


class _WheelInput:
    """The symbols that stand for one wheel's load-table interval: k and its four rows."""

    def __init__(self, name: str, columns: int):
        self.k = ca.SX.sym(f"k_{name}")
        self.rows = ca.SX.sym(f"rows_{name}", 4, columns)
        self.x = None


def _lookup(table: _WheelInput, c, t: int, Fz):
    x = (ca.log(Fz) - c[t + 1]) / c[t + 2]
    table.x = x
    k = table.k
    ok = ca.logic_and(ca.logic_and(Fz > 0.0, x >= k + 1.0), x < k + 2.0)
    w0, w1, w2, w3 = lagrange_weights(x - (k + 1.0))
    r = table.rows
    v = [r[0, j] * w0 + r[1, j] * w1 + r[2, j] * w2 + r[3, j] * w3 for j in range(r.shape[1])]
    v[1] = v[1] * Fz
    if c[t + 4] != 0.0:
        v[4] = v[4] * Fz
    return ok, v


class Twin:
    """Right-hand side, Jacobian and second derivatives of one assembled system (MBS state order); ``key`` names
    the caller's node for the load-table guess (module docstring)."""

    def __init__(self, data: TwinData):
        self.data = data
        m, n = data.m, data.m + 2
        N = 2 * m + 2
        c = data.constants
        tables = np.asarray(data.tables)
        self.tables = tables
        self.table_sizes = [int(c[w + compiled_stage.TABLE + 3]) for w in compiled_stage.WHEELS]
        self.load_dependent = [c[w + compiled_stage.TABLE] != 0.0 for w in compiled_stage.WHEELS]
        y = ca.SX.sym("y", N)
        V = ca.SX.sym("V")
        wheels = (_WheelInput("1", tables.shape[2]), _WheelInput("2", tables.shape[2]))
        q = [y[i] for i in range(m)] + [0.0, 0.0]
        qd = [y[m + i] for i in range(n)]
        qs, qds = ca.SX.sym("q", n), ca.SX.sym("qd", n)
        T = kinetic_energy(data.trees[0], [qs[i] for i in range(n)], [qds[i] for i in range(n)], OPS)
        M, g = ca.hessian(T, qds)
        h = ca.jtimes(g, qs, qds) - ca.gradient(T, qs)      # d/dt (dT/dq') - dT/dq without q''
        qv = ca.vertcat(*[ca.SX(v) if isinstance(v, float) else v for v in q])
        M = ca.substitute(M, ca.vertcat(qs, qds), ca.vertcat(qv, y[m:]))
        h = ca.substitute(h, ca.vertcat(qs, qds), ca.vertcat(qv, y[m:]))
        ok, Q = applied_forces(data, q, qd, V, OPS, _lookup, wheels)
        acc = ca.solve(M, ca.vertcat(*Q) - h)
        f = ca.vertcat(y[m:2 * m], acc)
        xs = ca.vertcat(*[w.x if self.load_dependent[i] else ca.SX(0.0) for i, w in enumerate(wheels)])
        inputs = [y, V, wheels[0].k, wheels[0].rows, wheels[1].k, wheels[1].rows]
        J = ca.jacobian(f, y)
        u, v = ca.SX.sym("u", N), ca.SX.sym("v", N)
        second = ca.jtimes(ca.jtimes(f, y, u), y, v)
        ok = ok if isinstance(ok, ca.SX) else ca.SX(float(ok))
        cse = {"cse": True}
        self.f = ca.Function("f", inputs, [f, ok, xs], cse)
        self.fJ = ca.Function("fJ", inputs, [f, J, ca.jacobian(f, V), ok, xs], cse)
        self.second = ca.Function("second", inputs + [u, v], [second], cse)
        self._k = {}
        self._maps = {}

    def _args(self, k: tuple[int, int]) -> list:
        out = []
        for i, kk in enumerate(k):
            size = self.table_sizes[i]
            kk = min(max(kk, 0), size - 4)
            out += [float(kk), self.tables[i, kk:kk + 4, :]]
        return out

    def _call(self, fn, y, speed, key):
        """fn's outputs at (y, speed) with the load-table intervals that the loads select (module docstring)."""
        k = self._k.get(key, (0, 0))
        for _ in range(3):
            res = fn(y, speed, *self._args(k))
            if bool(res[-2]):
                self._k[key] = k
                return res
            x = np.asarray(res[-1]).ravel()
            if not np.all(np.isfinite(x)):      # a lifted wheel: no load to read the table at
                break
            guess = tuple(int(np.floor(v)) - 1 if self.load_dependent[i] else 0 for i, v in enumerate(x))
            if guess == k:
                break
            k = guess
        return res

    def _batch(self, fn, Y, speed):
        """fn's outputs at each state of Y (K, N) in one call of fn mapped over K (a Python call into CasADi
        costs as much as evaluating the equations), with the intervals guessed per row (key = row) and
        corrected rows evaluated again."""
        Y = np.asarray(Y, dtype=float)
        K = len(Y)
        mapped = self._maps.get((fn.name(), K))
        if mapped is None:
            mapped = self._maps[(fn.name(), K)] = fn.map(K)
        ks = [self._k.get(i, (0, 0)) for i in range(K)]
        for _ in range(3):
            inputs = [Y.T, speed]
            for w in range(2):
                k = np.clip([kk[w] for kk in ks], 0, self.table_sizes[w] - 4)
                rows = self.tables[w][k[:, None] + np.arange(4)[None, :]]          # (K, 4, columns)
                inputs += [k[None, :].astype(float), rows.transpose(1, 0, 2).reshape(4, -1)]
            res = mapped(*inputs)
            ok = np.asarray(res[-2]).ravel() != 0.0
            x = np.asarray(res[-1])
            wrong = False
            for i in range(K):
                if ok[i]:
                    self._k[i] = ks[i]
                    continue
                guess = tuple(int(np.floor(v)) - 1 if self.load_dependent[w] and np.isfinite(v) else 0
                              for w, v in enumerate(x[:, i]))
                if guess != ks[i]:
                    ks[i], wrong = guess, True
            if not wrong:
                break
        return res, ok

    def rhs_batch(self, Y, speed: float) -> tuple[np.ndarray, np.ndarray]:
        """f (K, N) and ok (K,) at the states Y (K, N)."""
        res, ok = self._batch(self.f, Y, speed)
        return np.asarray(res[0]).T, ok

    def rhs_and_jacobians(self, Y, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """f (K, N), df/dy (K, N, N), df/dV (K, N) and ok (K,) at the states Y (K, N)."""
        res, ok = self._batch(self.fJ, Y, speed)
        K, N = np.shape(Y)
        J = np.asarray(res[1]).reshape(N, K, N).transpose(1, 0, 2)
        return np.asarray(res[0]).T, J, np.asarray(res[2]).T, ok

    def rhs(self, y, speed: float, key=0) -> tuple[np.ndarray, bool]:
        f, ok, _ = self._call(self.f, y, speed, key)
        return np.asarray(f).ravel(), bool(ok)

    def rhs_and_jacobian(self, y, speed: float, key=0) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        """f, df/dy, df/dV and ok at (y, speed)."""
        f, J, Jv, ok, _ = self._call(self.fJ, y, speed, key)
        return np.asarray(f).ravel(), np.asarray(J), np.asarray(Jv).ravel(), bool(ok)

    def second_derivative(self, y, speed: float, u, v, key=0) -> np.ndarray:
        """d/de (df/dy (y + e v)) u, exact (:attr:`second`); NaN where the load leaves the table."""
        if not self.rhs(y, speed, key)[1]:
            return np.full(len(y), np.nan)
        return np.asarray(self.second(y, speed, *self._args(self._k[key]), u, v)).ravel()


def twin_of(system) -> "Twin | None":
    """The twin of an assembled :class:`~mbs_shimmy.system.MbsSystem`, or None where it has no counterpart
    (module docstring: those keep difference derivatives).  Systems with the same items share one twin (its graph
    is what costs, about a second: a family rebuilt for the same axle and pressure, as in repeated runs, builds it
    once per process)."""
    try:
        data = TwinData.of(system)
    except NotCovered:
        return None
    key = (data.trees, data.knuckles, data.springs, data.m, data.constants.tobytes(),
           hashlib.sha256(np.ascontiguousarray(data.tables).tobytes()).hexdigest())
    found = _BUILT.get(key)
    if found is None:
        if len(_BUILT) >= 16:
            _BUILT.pop(next(iter(_BUILT)))
        found = _BUILT[key] = Twin(data)
    return found


# twins by the items they were generated from (twin_of)
_BUILT: dict = {}
