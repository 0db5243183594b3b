"""The tyre properties over the vertical load (assumption ``constant_load`` off): the Magic-Formula factors, the
trail factors, a and sigma follow the actual vertical force.  They are the reduced model's own formulas
(:mod:`reduced_model.tyre`) evaluated once on a grid of loads and interpolated by cubic Lagrange polynomials
(:class:`LoadTable`); the interpolation error is below 1e-10 relative for loads from 5 % to 2.9 times the static
load (``tests/test_mbs_model.py``).  The tyre element (:mod:`mbs_shimmy.tyre_element`), the compiled stage and the
twin read the same table and the same weights (:func:`lagrange_weights`).
"""

from __future__ import annotations

import dataclasses
import math
import types

import numpy as np

from reduced_model import tyre
from reduced_model.model import Effects, WheelTyre, contact_lengths
from axles.parameters import ShimmyParameters


class LoadTable:
    """Tyre properties of one wheel against the vertical load, for fast evaluation at every solver stage.

    Nodes evenly spaced in log(F_z) over :attr:`RANGE`, 1e-6 to 10 times the static load (relative spacing 0.33 %), each
    evaluated with :mod:`reduced_model.tyre` on the parameters with F_z replaced; D_y and D_t are tabulated
    divided by F_z (they are proportional to it up to the df_z terms).  Between nodes cubic Lagrange
    interpolation, outside the grid direct evaluation.  Only the properties the pressure effects make
    load-dependent are interpolated: (B, D, E) always, then (B_t, D_t, E_t0) with ``pt``, a with ``hcl``, sigma
    with ``rl``, in that order (:attr:`layout`).
    """

    # Down to 1e-6 of the static load (0.03 N on the paper's axle): a wheel near lift-off (below 2 %, KINK_BAND)
    # stays in the table, so that the compiled stage and the twin cover it.  Down to 2 % only, every such state fell
    # back to Python and to Exudyn's differences; down to 1e-4, still 2849 Jacobians of a fold curve did, a stencil
    # state of a node near lift-off carrying a few newtons (10 % of the curve's time).  Not lower: the formulas' E
    # grows as 1/F_z^2 (-9e17 at 1e-9), and with the table down to 1e-9 the fold's branch took 43 s instead of 3 s,
    # its Newton iterates wandering to 55 times the static load (measured 2026-12-07).
    # Up to 10 times: violent cycles of plausible axles put 3.3 times the static load on a wheel (a 9.6 deg
    # yaw cycle at 213 km/h, 1.5 bar), and beyond 3 times every state fell back to Exudyn's differences (minutes).
    # The nodes keep their spacing (3445 from 1e-4).
    RANGE = (1e-6, 10.0)
    NODES = 4823
    KINK_BAND = 0.02    # within this fraction of the static load of zero load, the twin's Jacobians are differences

    def __init__(self, params: ShimmyParameters, effects: Effects, wheel: WheelTyre):
        self.params, self.effects, self.pressure = params, effects, wheel.pressure
        self.static = params.Fz
        self.s0 = math.log(self.RANGE[0] * params.Fz)
        self.n = self.NODES
        self.ds = math.log(self.RANGE[1] / self.RANGE[0]) / (self.n - 1)
        self._p = types.SimpleNamespace(**{f_.name: getattr(params, f_.name) for f_ in dataclasses.fields(params)})
        self.layout = (("B", "D", "E") + (("Bt", "Dt", "Et0") if effects.pt else ()) + (("a",) if effects.hcl else ())
                       + (("sigma",) if effects.rl else ()))
        self.columns = tuple(("B", "D", "E", "Bt", "Dt", "Et0", "a", "sigma").index(k) for k in self.layout)
        self._per_load = tuple(i for i, k in enumerate(self.layout) if k in ("D", "Dt"))
        self._short = len(self.layout) == 3
        # every node in one evaluation of the formulas on an array of loads (they are numpy-generic): a table per
        # pressure of a Hopf curve's family, where a loop over the nodes was half the curve's time
        loads = np.exp(self.s0 + np.arange(self.n) * self.ds)
        values = self.direct(loads)
        columns = [np.broadcast_to(values[i], loads.shape) for i in self.columns]
        for i in self._per_load:
            columns[i] = columns[i] / loads
        self.rows = [tuple(float(v) for v in row) for row in zip(*columns)]
        # the same as one array, for the compiled stage and the twin (a system per Newton iteration of a fold curve
        # in t0 converted the list again: 2 ms of its 9)
        self.array = np.array(self.rows, dtype=float)
        self.array.flags.writeable = False

    def direct(self, load: float) -> tuple[float, ...]:
        """(B, D, E, Bt, Dt, Et0, a, sigma) at this load from the reduced model's formulas."""
        p = self._p
        p.Fz = load
        return tyre_properties(p, self.effects, self.pressure)

    def at(self, load: float) -> list[float]:
        """The :attr:`layout` values at this load (N, positive)."""
        x = (math.log(load) - self.s0) / self.ds
        k = int(x) - 1
        if k < 0 or k > self.n - 4:
            values = self.direct(load)
            return [values[i] for i in self.columns]
        w0, w1, w2, w3 = lagrange_weights(x - (k + 1.0))
        r = self.rows
        if self._short:               # (B, D/F_z, E): the section 3 model, unrolled
            p, q, u, v = r[k], r[k + 1], r[k + 2], r[k + 3]
            return [p[0] * w0 + q[0] * w1 + u[0] * w2 + v[0] * w3,
                    (p[1] * w0 + q[1] * w1 + u[1] * w2 + v[1] * w3) * load,
                    p[2] * w0 + q[2] * w1 + u[2] * w2 + v[2] * w3]
        out = [p * w0 + q * w1 + u * w2 + v * w3 for p, q, u, v in zip(r[k], r[k + 1], r[k + 2], r[k + 3])]
        for i in self._per_load:
            out[i] *= load
        return out

    def values(self, load: float) -> tuple[float, ...]:
        """(B, D, E, Bt, Dt, Et0, a, sigma) at this load by interpolation (the others from the static wheel)."""
        got = dict(zip(self.layout, self.at(load)))
        return tuple(got.get(k, math.nan) for k in ("B", "D", "E", "Bt", "Dt", "Et0", "a", "sigma"))


def lagrange_weights(x: float) -> tuple[float, float, float, float]:
    """Cubic Lagrange weights on the nodes k .. k+3 at x in [0, 1) between nodes k+1 and k+2."""
    xm, x1, x2 = x + 1.0, x - 1.0, x - 2.0
    return -x * x1 * x2 / 6.0, xm * x1 * x2 / 2.0, -xm * x * x2 / 2.0, xm * x * x1 / 6.0


def tyre_properties(p, effects: Effects, pressure: float) -> tuple[float, ...]:
    """(B, D, E, Bt, Dt, Et0, a, sigma) of a tyre with the parameters ``p`` (its load ``p.Fz``) at ``pressure``."""
    mf = tyre.magic_formula(p, pressure)
    tr = tyre.trail_formula(p, pressure)
    a, sigma = contact_lengths(p, effects, pressure)
    return (mf.B, mf.D, mf.E, tr.Bt, tr.Dt, tr.Et0, a, sigma)


class _Reads:
    """A parameter set that records which of its entries are read."""

    def __init__(self, params: ShimmyParameters):
        self._params, self.names = params, set()

    def __getattr__(self, name: str):
        self.names.add(name)
        return getattr(self._params, name)


_TABLES: dict[tuple, LoadTable] = {}
TABLES_KEPT = 32


def load_table(params: ShimmyParameters, effects: Effects, wheel: WheelTyre) -> LoadTable:
    """One table per (the entries its formulas read, effects, pressure): both wheels, successive runs, and the
    systems of a family along an entry no tyre formula reads (t0 along a fold curve: a new system at every Newton
    iteration) share it.  The entries are those one evaluation reads (:class:`_Reads`), so an entry a formula
    takes up later is in the key without a list to keep."""
    reads = _Reads(params)
    tyre_properties(reads, effects, wheel.pressure)
    key = (effects, wheel.pressure, params.Fz) + tuple(sorted((n, getattr(params, n)) for n in reads.names))
    table = _TABLES.get(key)
    if table is None:
        if len(_TABLES) >= TABLES_KEPT:
            _TABLES.pop(next(iter(_TABLES)))
        table = _TABLES[key] = LoadTable(params, effects, wheel)
    return table
