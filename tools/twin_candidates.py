"""Measure the candidates for the MBS twin (:mod:`mbs_shimmy.twin`) on this machine: CasADi (chosen) and JAX.

Both trace the same generic equations (:mod:`mbs_shimmy.twin_equations`); this script times, on the full geometry
at 1.5 bar: build/compile, one right-hand side, one right-hand side with Jacobian, the same for 100 states in one
call, one directional second derivative, and Exudyn's right-hand side for scale.  JAX is not a dependency of the
project: ``.venv/bin/pip install jax jaxlib`` to run its half (``--jax``; its Jacobian compile did not finish in
8 minutes when measured, so ``--jax-jacobian`` is separate).

    .venv/bin/python tools/twin_candidates.py [--jax] [--jax-jacobian]
"""

from __future__ import annotations

import jax

jax.config.update("jax_enable_x64", True)     # before any array is made: the twin must work in double

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from mbs_shimmy.load_table import lagrange_weights  # noqa: E402
from mbs_shimmy.twin_equations import TwinData, applied_forces, kinetic_energy  # noqa: E402

OPS = (jnp.sin, jnp.cos, jnp.arctan, jnp.sqrt, jnp.arcsin, jnp.where)


def lookup(table, c, t: int, Fz):
    """:func:`mbs_shimmy.compiled_stage.table_row` on traced values: the same grid test, nodes and weights, the
    rows read by a traced index (clamped into the table where ``ok`` is False)."""
    n = int(c[t + 3])
    positive = Fz > 0.0
    x = (jnp.log(jnp.where(positive, Fz, 1.0)) - c[t + 1]) / c[t + 2]
    ok = positive & (x >= 1.0) & (x < n - 2.0)
    x = jnp.where(ok, x, jnp.clip(x, 1.0, n - 2.5))
    k = jnp.floor(x).astype(jnp.int32) - 1
    w0, w1, w2, w3 = lagrange_weights(x - (k + 1.0))
    rows = jax.lax.dynamic_slice(jnp.asarray(table), (k, jnp.int32(0)), (4, table.shape[1]))
    v = rows[0] * w0 + rows[1] * w1 + rows[2] * w2 + rows[3] * w3
    per_load = [1.0] * table.shape[1]
    per_load[1] = Fz                              # D and D_t are tabulated divided by the load
    if c[t + 4] != 0.0:
        per_load[4] = Fz
    return ok, v * jnp.stack([jnp.asarray(s, dtype=v.dtype) for s in per_load])


def equations(data: TwinData):
    """f(y, speed) -> (y', ok) of the MBS state y = (q, q', alpha1, alpha2) (:class:`~mbs_shimmy.layout.Layout`),
    Lagrange's equations of the kinematic tree with Exudyn's applied forces."""
    m = data.m
    n = m + 2

    def energy(q, qd):
        return kinetic_energy(data.trees[0], [q[i] for i in range(n)], [qd[i] for i in range(n)], OPS)

    grad_v = jax.grad(energy, argnums=1)

    def f(y, speed):
        q = jnp.concatenate([y[:m], jnp.zeros(2, dtype=y.dtype)])
        qd = y[m:]
        M = jax.jacfwd(grad_v, argnums=1)(q, qd)
        h = jax.jacfwd(grad_v, argnums=0)(q, qd) @ qd - jax.grad(energy, argnums=0)(q, qd)
        ok, Q = applied_forces(data, [q[i] for i in range(n)], [qd[i] for i in range(n)], speed, OPS, lookup)
        acc = jnp.linalg.solve(M, jnp.stack([jnp.asarray(v, dtype=y.dtype) for v in Q]) - h)
        return jnp.concatenate([y[m:2 * m], acc]), ok
    return f


class Twin:
    """The compiled twin of one assembled system: right-hand side, Jacobian and directional second derivatives
    (MBS state order), each also for a stack of states in one call."""

    def __init__(self, data: TwinData):
        self.data = data
        f = equations(data)
        self._f = f

        def rhs(y, speed):
            return f(y, speed)[0]

        def jac(y, speed):
            J = jax.jacfwd(rhs)(y, speed)
            out, ok = f(y, speed)
            return out, J, ok

        def second(y, speed, u, v):
            """d/de J(y + e v) u: the Jacobian's derivative along v applied to u."""
            return jax.jvp(lambda z: jax.jacfwd(rhs)(z, speed) @ u, (y,), (v,))[1]
        self._rhs = jax.jit(f)
        self._jac = jax.jit(jac)
        self._jacs = jax.jit(jax.vmap(jac, in_axes=(0, None)))
        self._second = jax.jit(second)

    def rhs(self, y, speed: float) -> tuple[np.ndarray, bool]:
        out, ok = self._rhs(jnp.asarray(y, dtype=jnp.float64), float(speed))
        return np.asarray(out), bool(ok)

    def rhs_and_jacobian(self, y, speed: float) -> tuple[np.ndarray, np.ndarray, bool]:
        out, J, ok = self._jac(jnp.asarray(y, dtype=jnp.float64), float(speed))
        return np.asarray(out), np.asarray(J), bool(ok)

    def rhs_and_jacobians(self, Y, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """f (k, n), df/dy (k, n, n) and ok (k,) at the states Y (k, n)."""
        out, J, ok = self._jacs(jnp.asarray(Y, dtype=jnp.float64), float(speed))
        return np.asarray(out), np.asarray(J), np.asarray(ok)

    def second_derivative(self, y, speed: float, u, v) -> np.ndarray:
        """d^2 f/dy^2 [u, v] (exact)."""
        return np.asarray(self._second(jnp.asarray(y, dtype=jnp.float64), float(speed),
                                       jnp.asarray(u, dtype=jnp.float64), jnp.asarray(v, dtype=jnp.float64)))




def _time(fn, number):
    import timeit
    return timeit.timeit(fn, number=number) / number


def main(argv=None) -> int:
    import argparse
    import time

    from axles.pressures import TyrePressures
    from mbs_shimmy.fidelity import Fidelity
    from mbs_shimmy.evaluator import MbsEvaluator, speed_is_time
    from mbs_shimmy.model import MbsModel
    from mbs_shimmy.twin import Twin as CasadiTwin

    parser = argparse.ArgumentParser(description="time the MBS twin's candidates")
    parser.add_argument("--jax", action="store_true")
    parser.add_argument("--jax-jacobian", action="store_true")
    args = parser.parse_args(argv)
    system = MbsModel(fidelity=Fidelity.full()).system(TyrePressures.uniform(1.5e5), speed_is_time)
    data = TwinData.of(system)
    exudyn = MbsEvaluator(system)
    rng = np.random.default_rng(0)
    m = system.layout.n_mech
    Y = np.concatenate([rng.uniform(-0.003, 0.003, (100, m)), rng.uniform(-0.1, 0.1, (100, m)),
                        rng.uniform(-0.05, 0.05, (100, 2))], axis=1)
    y, u = Y[0], rng.normal(size=Y.shape[1])
    rows = [("Exudyn rhs (us)", 1e6 * _time(lambda: exudyn.rhs(y, 20.0), 300))]
    t0 = time.perf_counter()
    c = CasadiTwin(data)
    rows.append(("CasADi build: rhs, Jacobian, second derivative (s)", time.perf_counter() - t0))
    c.rhs(y, 20.0)
    rows += [("CasADi rhs (us)", 1e6 * _time(lambda: c.rhs(y, 20.0), 300)),
             ("CasADi rhs + Jacobian (us)", 1e6 * _time(lambda: c.rhs_and_jacobian(y, 20.0), 300)),
             ("CasADi rhs + Jacobian, 100 states in one call, per state (us)",
              1e4 * _time(lambda: c.rhs_and_jacobians(Y, 20.0), 10)),
             ("CasADi rhs, 100 states in one call, per state (us)", 1e4 * _time(lambda: c.rhs_batch(Y, 20.0), 10)),
             ("CasADi second derivative d2f[u, u] (us)", 1e6 * _time(lambda: c.second_derivative(y, 20.0, u, u), 100))]
    if args.jax or args.jax_jacobian:
        j = Twin(data)
        t0 = time.perf_counter()
        j.rhs(y, 20.0)
        rows += [("JAX rhs compile (s)", time.perf_counter() - t0),
                 ("JAX rhs (us)", 1e6 * _time(lambda: j.rhs(y, 20.0), 300))]
        if args.jax_jacobian:
            t0 = time.perf_counter()
            j.rhs_and_jacobian(y, 20.0)
            rows += [("JAX Jacobian compile (s)", time.perf_counter() - t0),
                     ("JAX rhs + Jacobian (us)", 1e6 * _time(lambda: j.rhs_and_jacobian(y, 20.0), 300))]
    for label, value in rows:
        print(f"{label:70s} {value:10.3g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
