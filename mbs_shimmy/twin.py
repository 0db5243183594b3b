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
the right-hand side alone, against 1-2 s here for everything.

One graph serves a structure (:meth:`TwinData.split`: the fidelity's joints, links, connectors and switches): the
axle's numbers (offsets, masses, inertias, stiffnesses, the user function's constants, the pressure's tyre values)
are an input P of its functions, so another axle or parameter value costs no new graph, and the derivative of the
right-hand side along a change of the numbers is exact (``f_numbers``: a second parameter's derivative).  A
structure evaluated often is compiled to C (:mod:`mbs_shimmy.twin_library`).

The load table's interpolation reads four rows chosen by the load (a lifted wheel reads none: its properties are
constants).  An SX graph has no lookup by a computed
index, so the interval k of each wheel is an input, with its rows: the function also returns each wheel's table
position x and whether x lies in the interval it was given; a call that guessed k wrong is repeated with k from x.
The guess is the last k at the same node of the caller (``key``): in a continuation loads move little.

Coverage: the exact kinematics at a steady speed (every fidelity with ``small_angles`` off).  The first-order
kinematics (``small_angles``) run a Python user function with Exudyn's coordinate connectors and keep difference
derivatives (:func:`twin_of` returns None); at a state whose positive load leaves the load table
(:attr:`~mbs_shimmy.load_table.LoadTable.RANGE`: below 1e-6 or above 10 times the static load) the twin says so
(``ok`` False) and its caller uses differences there.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from mbs_shimmy import compiled_stage, twin_library
from mbs_shimmy.twin_equations import NotCovered, TwinData, applied_forces, kinetic_energy
from mbs_shimmy.load_table import LoadTable, lagrange_weights

OPS = (ca.sin, ca.cos, ca.atan, ca.sqrt, ca.asin, ca.if_else)
# evaluated in CasADi's virtual machine, never compiled: only normal forms ask for them, once per point
VM_ONLY = ("second", "third")


class _WheelInput:
    """The symbols that stand for one wheel's load-table interval: k and its four rows."""

    def __init__(self, name: str, columns: int):
        self.k = ca.SX.sym(f"k_{name}")
        self.rows = ca.SX.sym(f"rows_{name}", 4, columns)
        self.x = None


def _lookup(table: _WheelInput, c, t: int, Fz):
    # a lifted wheel (Fz <= 0) reads no row (compiled_stage.wheel_terms): its x is any finite number, it is ok
    x = (ca.log(ca.if_else(Fz > 0.0, Fz, 1.0)) - c[t + 1]) / c[t + 2]
    table.x = x
    # the load as a fraction of the static load, negative where the wheel is lifted (the table starts at RANGE[0]
    # of the static load: c[t + 1] is its log), for the band about the kink at zero load (Twin._near_kink)
    table.load = Fz * (LoadTable.RANGE[0] * ca.exp(-c[t + 1]))
    k = table.k
    ok = ca.logic_or(Fz <= 0.0, ca.logic_and(x >= k + 1.0, x < k + 2.0))
    w0, w1, w2, w3 = lagrange_weights(x - (k + 1.0))
    r = table.rows
    v = [r[0, j] * w0 + r[1, j] * w1 + r[2, j] * w2 + r[3, j] * w3 for j in range(r.shape[1])]
    v[1] = v[1] * Fz
    if c[t + 4] != 0.0:
        v[4] = v[4] * Fz
    return ok, v


class TwinGraph:
    """The twin's functions for one structure (:meth:`TwinData.split`): inputs the state y, the speed V, the axle's
    numbers P, then each wheel's load-table interval (module docstring).  Every axle and parameter value with that
    structure evaluates these same functions with its own P."""

    def __init__(self, data: TwinData):
        m, n = data.m, data.m + 2
        N = 2 * m + 2
        _, numbers = data.split()
        P = ca.SX.sym("P", len(numbers))
        sym = data.with_numbers(P)
        columns = np.shape(data.tables)[2]
        y = ca.SX.sym("y", N)
        V = ca.SX.sym("V")
        wheels = (_WheelInput("1", columns), _WheelInput("2", columns))
        self.load_dependent = [data.constants[w + compiled_stage.TABLE] != 0.0 for w in compiled_stage.WHEELS]
        q = [y[i] for i in range(m)] + [0.0, 0.0]
        qd = [y[m + i] for i in range(n)]
        qs, qds = ca.SX.sym("q", n), ca.SX.sym("qd", n)
        T = kinetic_energy(sym.trees[0], [qs[i] for i in range(n)], [qds[i] for i in range(n)], OPS)
        M, g = ca.hessian(T, qds)
        h = ca.jtimes(g, qs, qds) - ca.gradient(T, qs)      # d/dt (dT/dq') - dT/dq without q''
        qv = ca.vertcat(*[ca.SX(v) if isinstance(v, float) else v for v in q])
        M = ca.substitute(M, ca.vertcat(qs, qds), ca.vertcat(qv, y[m:]))
        h = ca.substitute(h, ca.vertcat(qs, qds), ca.vertcat(qv, y[m:]))
        ok, Q = applied_forces(sym, q, qd, V, OPS, _lookup, wheels)
        acc = ca.solve(M, ca.vertcat(*Q) - h)
        f = ca.vertcat(y[m:2 * m], acc)
        # per wheel its table position, then its load as a fraction of the static load (Twin._near_kink)
        xs = ca.vertcat(*[w.x if self.load_dependent[i] else ca.SX(0.0) for i, w in enumerate(wheels)],
                        *[w.load if self.load_dependent[i] else ca.SX(0.0) for i, w in enumerate(wheels)])
        inputs = [y, V, P, wheels[0].k, wheels[0].rows, wheels[1].k, wheels[1].rows]
        J = ca.jacobian(f, y)
        u, v = ca.SX.sym("u", N), ca.SX.sym("v", N)
        second = ca.jtimes(ca.jtimes(f, y, u), y, v)
        dP = ca.SX.sym("dP", len(numbers))
        ok = ok if isinstance(ok, ca.SX) else ca.SX(float(ok))
        cse = {"cse": True}
        self.vm = {fn.name(): fn for fn in (
            ca.Function("f", inputs, [f, ok, xs], cse),
            ca.Function("fJ", inputs, [f, J, ca.jacobian(f, V), ok, xs], cse),
            ca.Function("second", inputs + [u, v], [second], cse),
            # f and its derivative along a change dP of the numbers: a second parameter's derivative without a
            # graph per parameter value
            ca.Function("f_numbers", inputs + [dP], [f, ca.jtimes(f, P, dP), ok, xs], cse))}
        self.functions = self.vm
        # the third derivative is built at its first use: only normal forms ask for it, and its graph costs
        self._third_parts = (f, y, u, v, inputs)
        self._compile_tried = False
        self._compile(cached_only=True)
        self.evaluated = 0          # states evaluated in the virtual machine (twin_library.COMPILE_AFTER)
        self._maps = {}

    @property
    def is_compiled(self) -> bool:
        return self.functions is not self.vm

    def function(self, name: str, states: int = 1):
        """The function ``name``, compiled once the structure has evaluated enough states (:mod:`twin_library`)."""
        if name == "third" and name not in self.vm:
            f, y, u, v, inputs = self._third_parts
            w = ca.SX.sym("w", y.numel())
            third = ca.jtimes(ca.jtimes(ca.jtimes(f, y, u), y, v), y, w)
            self.vm["third"] = ca.Function("third", inputs + [u, v, w], [third], {"cse": True})
            self.functions.setdefault("third", self.vm["third"])
        if not self.is_compiled and name not in VM_ONLY:
            self.evaluated += states
            if self.evaluated > twin_library.COMPILE_AFTER and not self._compile_tried:
                self._compile_tried = True
                self._compile(cached_only=False)
        return self.functions[name]

    def _compile(self, cached_only: bool) -> None:
        """Switch to the compiled functions (all but ``second`` and ``third``, which the continuation does not
        evaluate)."""
        built = twin_library.compiled([fn for name, fn in self.vm.items() if name not in VM_ONLY], cached_only)
        if built is not None:
            self.functions, self._maps = {**self.vm, **built}, {}

    def mapped(self, name: str, K: int) -> "_Mapped":
        """The function ``name`` mapped over K states: the state, the load-table inputs and the outputs per
        column, the speed, the numbers and any extra input shared (:class:`_Mapped`)."""
        fn = self.function(name, K)
        found = self._maps.get((name, K))
        if found is None:
            shared = [1, 2] + list(range(7, fn.n_in()))
            found = self._maps[(name, K)] = _Mapped(fn.map(f"{name}_{K}", "serial", K, shared, []))
        return found


class _Mapped:
    """A mapped function evaluated through CasADi's buffer interface: inputs and outputs are numpy memory (in
    CasADi's column-major order of nonzeros), so a call converts no matrices to and from CasADi's; that
    conversion cost about as much as the compiled evaluation itself."""

    def __init__(self, fn):
        self.fn = fn
        self.buffer, self.trigger = fn.buffer()
        self.nonzeros = [np.zeros(fn.nnz_out(j)) for j in range(fn.n_out())]
        self.places = []
        for j, nz in enumerate(self.nonzeros):
            self.buffer.set_res(j, memoryview(nz))
            sp = fn.sparsity_out(j)
            self.places.append((sp.shape, np.array(sp.row()), np.array(sp.get_col())))

    def __call__(self, *args) -> list[np.ndarray]:
        kept = []
        for i, a in enumerate(args):
            a = np.ravel(np.asarray(a, dtype=float), order="F").copy()      # dense inputs, column-major
            if a.size != self.fn.nnz_in(i):
                raise ValueError(f"input {i} of {self.fn.name()}: {a.size} values for {self.fn.nnz_in(i)}")
            kept.append(a)
            self.buffer.set_arg(i, memoryview(a))
        self.trigger()
        out = []
        for nz, (shape, rows, cols) in zip(self.nonzeros, self.places):
            dense = np.zeros(shape)
            dense[rows, cols] = nz
            out.append(dense)
        return out


class Twin:
    """Right-hand side, Jacobian and second derivatives of one assembled system (MBS state order): its structure's
    :class:`TwinGraph` with its numbers; ``key`` names the caller's node for the load-table guess (module
    docstring)."""

    def __init__(self, data: TwinData, graph: TwinGraph | None = None):
        self.data = data
        _, self.numbers = data.split()
        self.graph = graph if graph is not None else TwinGraph(data)
        c = data.constants
        self.tables = np.asarray(data.tables)
        self.table_sizes = [int(c[w + compiled_stage.TABLE + 3]) for w in compiled_stage.WHEELS]
        self.load_dependent = self.graph.load_dependent
        self._k = {}

    def _args(self, k: tuple[int, int]) -> list:
        out = []
        for i, kk in enumerate(k):
            size = self.table_sizes[i]
            kk = min(max(kk, 0), size - 4)
            out += [float(kk), self.tables[i, kk:kk + 4, :]]
        return out

    def _call(self, name: str, y, speed, key):
        """fn's outputs at (y, speed) with the load-table intervals that the loads select (module docstring)."""
        k = self._k.get(key, (0, 0))
        fn = self.graph.function(name)
        for _ in range(3):
            res = fn(y, speed, self.numbers, *self._args(k))
            if bool(res[-2]):
                self._k[key] = k
                return res
            x = np.asarray(res[-1]).ravel()[:2]
            if not np.all(np.isfinite(x)):      # a non-finite load: no table position
                break
            guess = tuple(int(np.floor(v)) - 1 if self.load_dependent[i] else 0 for i, v in enumerate(x))
            if guess == k:
                break
            k = guess
        return res

    def _batch(self, name: str, Y, speed, extra=(), pad: bool = False, keys=None, remember: bool = True):
        """fn's outputs at each state of Y (K, N) in one call of fn mapped over K (a Python call into CasADi
        costs as much as evaluating the equations), with the intervals guessed per row from the cache under its key
        (``keys``, default the row) and the batch evaluated again where a guess was wrong.  ``remember`` False: the
        rows' intervals are not cached (states beside the keyed ones, as a difference stencil about a node)."""
        Y = np.asarray(Y, dtype=float)
        K = len(Y)
        keys = np.arange(K) if keys is None else np.asarray(keys, dtype=int)
        if K > CHUNK:
            # building a map costs about seven of its calls and grows with its size (20 us per state): a violent
            # branch's difference stencils, thousands of states in ever new counts, spent a quarter of their time
            # building; chunks of one size are built once
            parts = [self._batch(name, Y[i:i + CHUNK], speed, extra, pad, keys[i:i + CHUNK], remember)
                     for i in range(0, K, CHUNK)]
            return ([np.concatenate([p[0][j] for p in parts], axis=1) for j in range(len(parts[0][0]))],
                    np.concatenate([p[1] for p in parts]))
        # with ``pad``, padded to a bucket size: a mapped function is built once per size (tens of ms), and the
        # Jacobian rows differenced near a lift-off come in every count (a third of a violent branch's time went
        # to building); a mesh's own count repeats from step to step and is not padded
        Kb = _bucket(K) if pad else K
        if Kb > K:
            Y = np.concatenate([Y, np.repeat(Y[-1:], Kb - K, axis=0)])
        mapped = self.graph.mapped(name, Kb)
        cached = self._k.get
        padding = [cached(int(keys[-1]), (0, 0))] * (Kb - K) if Kb > K else []
        ks = np.array([cached(k, (0, 0)) for k in keys.tolist()] + padding, dtype=int).reshape(Kb, 2)
        dependent = np.asarray(self.load_dependent, dtype=bool)[:, None]
        for _ in range(3):
            inputs = [Y.T, speed, self.numbers]
            for w in range(2):
                k = np.clip(ks[:, w], 0, self.table_sizes[w] - 4)
                rows = self.tables[w][k[:, None] + np.arange(4)[None, :]]          # (K, 4, columns)
                inputs += [k[None, :].astype(float), rows.transpose(1, 0, 2).reshape(4, -1)]
            res = mapped(*inputs, *extra)
            ok = np.asarray(res[-2]).ravel() != 0.0
            x = np.asarray(res[-1], dtype=float).reshape(4, Kb)[:2]
            usable = dependent & np.isfinite(x)
            guess = np.where(usable, np.floor(np.where(usable, x, 0.0)) - 1.0, 0.0).astype(int).T   # (Kb, 2)
            wrong = ~ok & np.any(guess != ks, axis=1)
            if not wrong.any():
                break
            ks[wrong] = guess[wrong]
        if remember:
            good = ok[:K]
            self._k.update(zip(keys[good].tolist(), map(tuple, ks[:K][good].tolist())))
        if Kb > K:      # each output holds its Kb blocks of columns side by side
            res = [np.asarray(r)[:, :np.shape(r)[1] // Kb * K] for r in res]
        return res, ok[:K]

    def rhs_batch(self, Y, speed: float, pad: bool = False, keys=None,
                  remember: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """f (K, N) and ok (K,) at the states Y (K, N); ``pad``: a batch whose size varies from call to call;
        ``keys``, ``remember``: the rows' load-table intervals (:meth:`_batch`)."""
        res, ok = self._batch("f", Y, speed, pad=pad, keys=keys, remember=remember)
        return np.asarray(res[0]).T, ok

    def rhs_and_jacobians(self, Y, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                                          np.ndarray]:
        """f (K, N), df/dy (K, N, N), df/dV (K, N), ok (K,) and near (K,) at the states Y (K, N); near: a
        load-dependent wheel's load lies about its kink at zero load (:meth:`_near_kink`)."""
        res, ok = self._batch("fJ", Y, speed)
        K, N = np.shape(Y)
        J = np.asarray(res[1]).reshape(N, K, N).transpose(1, 0, 2)
        return np.asarray(res[0]).T, J, np.asarray(res[2]).T, ok, self._near_kink(np.asarray(res[-1]))

    def _near_kink(self, x: np.ndarray) -> np.ndarray:
        """Per state (columns of the functions' last output, (4, K)): a load-dependent wheel's load within
        :attr:`~mbs_shimmy.load_table.LoadTable.KINK_BAND` of its static load of zero, on either side (a lifted
        wheel's is negative).  Further from the kink the forces are smooth: a wheel lifted by more than the band
        has its exact Jacobian (a difference stencil of step 1e-4 moves a load by about 0.3 % of the static
        load), and a violent cycle that lifts a wheel for half its period differences only the nodes about its
        lift-off and touch-down."""
        load = np.asarray(x, dtype=float).reshape(4, -1)[2:]
        near = np.zeros(load.shape[1], dtype=bool)
        for w in range(2):
            if self.load_dependent[w]:
                near |= ~(np.abs(load[w]) >= LoadTable.KINK_BAND)
        return near

    def rhs(self, y, speed: float, key=0) -> tuple[np.ndarray, bool]:
        f, ok, _ = self._call("f", y, speed, key)
        return np.asarray(f).ravel(), bool(ok)

    def rhs_and_jacobian(self, y, speed: float, key=0) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        """f, df/dy, df/dV and ok at (y, speed)."""
        f, J, Jv, ok, _ = self._call("fJ", y, speed, key)
        return np.asarray(f).ravel(), np.asarray(J), np.asarray(Jv).ravel(), bool(ok)

    def jacobian_and_near_kink(self, y, speed: float, key=0) -> tuple[np.ndarray, np.ndarray, bool, bool]:
        """df/dy, df/dV, ok and near at (y, speed) from one evaluation; near: a load-dependent wheel's load lies
        about its kink at zero load, lifted or not (:meth:`_near_kink`; where the forces have a kink at zero
        load: :meth:`rhs_and_jacobians`)."""
        _, J, Jv, ok, x = self._call("fJ", y, speed, key)
        return np.asarray(J), np.asarray(Jv).ravel(), bool(ok), bool(self._near_kink(np.asarray(x))[0])

    def second_derivative(self, y, speed: float, u, v, key=0) -> np.ndarray:
        """d/de (df/dy (y + e v)) u, exact (:attr:`second`); NaN where the load leaves the table."""
        if not self.rhs(y, speed, key)[1]:
            return np.full(len(y), np.nan)
        return np.asarray(self.graph.function("second")(y, speed, self.numbers, *self._args(self._k[key]), u, v)).ravel()

    def third_derivative(self, y, speed: float, u, v, w, key=0) -> np.ndarray:
        """D^3 f(y)[u, v, w], exact (built at its first use); NaN where the load leaves the table."""
        if not self.rhs(y, speed, key)[1]:
            return np.full(len(y), np.nan)
        fn = self.graph.function("third")
        return np.asarray(fn(y, speed, self.numbers, *self._args(self._k[key]), u, v, w)).ravel()

    def numbers_derivatives(self, Y, speed: float, dP) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """f (K, N), df/dP dP (K, N) and ok (K,) at the states Y (K, N): the right-hand side's change along a
        change dP of the numbers (:meth:`TwinData.split`), exact."""
        res, ok = self._batch("f_numbers", Y, speed, (np.asarray(dP, dtype=float),))
        return np.asarray(res[0]).T, np.asarray(res[1]).T, ok


CHUNK = 512     # states per mapped call at most (:meth:`Twin._batch`): 1 us of a call per state from a few hundred


def _bucket(K: int) -> int:
    """The batch size a batch of K states is padded to: K rounded up in its fourth significant bit (at most 1/8
    more work; eight sizes per doubling of K)."""
    if K <= 16:
        return K
    step = 1 << (K.bit_length() - 4)
    return -(-K // step) * step


def twin_of(system) -> "Twin | None":
    """The twin of an assembled :class:`~mbs_shimmy.system.MbsSystem`, or None where it has no counterpart
    (module docstring: those keep difference derivatives).  Systems with the same structure share one graph (it
    is what costs, about a second): every axle and parameter value of a fidelity builds it once per process."""
    try:
        data = TwinData.of(system)
    except NotCovered:
        return None
    structure, _ = data.split()
    graph = _GRAPHS.get(structure)
    if graph is None:
        if len(_GRAPHS) >= 16:
            _GRAPHS.pop(next(iter(_GRAPHS)))
        graph = _GRAPHS[structure] = TwinGraph(data)
    return Twin(data, graph)


# graphs by the structure they were generated for (twin_of)
_GRAPHS: dict = {}
