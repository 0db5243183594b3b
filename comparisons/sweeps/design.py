"""The sampling plan of ``shimmy sweep``: which inputs vary, how, and the table of samples (interface units).

``--vary NAME=LO:HI:N`` is a grid (several grids: full factorial, first input slowest); ``--vary NAME=uniform:LO:HI``
or ``NAME=normal:MEAN:SD`` is sampled quasi-randomly with ``--samples N --seed S``: a scrambled Sobol' sequence
(:class:`scipy.stats.qmc.Sobol`) mapped through each input's inverse distribution function.  ``--design saltelli``
arranges the same sequence as Saltelli's A, AB_i, B matrices (Saltelli et al., Comput. Phys. Commun. 181, 2010;
rows in the order :func:`SALib.analyze.sobol.analyze` expects with first and total indices only), so that Sobol'
indices can be estimated; it costs N (D + 2) evaluations for N base samples and D inputs.

Names are axle entries (as ``shimmy params`` prints them, in its units) or ``pressure``, ``pressure_left``,
``pressure_right`` (bar).  Values are not range-checked here: a sample with a meaningless value is evaluated, fails
and is recorded as failed (:mod:`comparisons.sweeps.run`).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import warnings
from dataclasses import dataclass

import numpy as np

from axles.axle import interface_unit
from axles.limits import UsageError
from axles.pressures import PRESSURE_PARAMS

DISTRIBUTIONS = ("uniform", "normal")
DESIGNS = ("sobol", "saltelli")
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True)
class Variation:
    """One varied input: a grid of ``n`` values from ``a`` to ``b``, uniform on [a, b], or normal (mean a, sd b)."""

    name: str
    kind: str          # "grid", "uniform" or "normal"
    a: float
    b: float
    n: int = 0         # grid points

    @property
    def unit(self) -> str:
        return interface_unit(self.name)[0]

    @property
    def random(self) -> bool:
        return self.kind != "grid"

    def grid(self) -> np.ndarray:
        return np.linspace(self.a, self.b, self.n)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """Values for points u in (0, 1) of the unit interval (inverse distribution function)."""
        if self.kind == "uniform":
            return self.a + (self.b - self.a) * u
        from scipy.stats import norm
        return norm.ppf(np.clip(u, 1e-12, 1.0 - 1e-12), loc=self.a, scale=self.b)

    @property
    def bounds(self) -> tuple[float, float]:
        """Where the input's values lie: grid ends, uniform bounds, mean +- 3 sd."""
        if self.kind == "normal":
            return self.a - 3.0 * self.b, self.a + 3.0 * self.b
        return self.a, self.b

    def to_json(self) -> dict:
        out = {"name": self.name, "unit": self.unit, "kind": self.kind}
        if self.kind == "grid":
            out.update(lo=self.a, hi=self.b, n=self.n)
        elif self.kind == "uniform":
            out.update(lo=self.a, hi=self.b)
        else:
            out.update(mean=self.a, sd=self.b)
        return out


def _float(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{what}: '{text}' is not a number") from None
    if not math.isfinite(value):
        raise UsageError(f"{what}: {text} is not a finite number")
    return value


def parse_vary(text: str) -> Variation:
    """``NAME=LO:HI:N``, ``NAME=uniform:LO:HI`` or ``NAME=normal:MEAN:SD``; :class:`UsageError` on bad input."""
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not name or not spec.strip():
        raise UsageError(f"--vary expects NAME=LO:HI:N, NAME=uniform:LO:HI or NAME=normal:MEAN:SD, got '{text}'")
    if name not in PRESSURE_PARAMS:
        from axles.axle import entries
        if name not in entries():
            import difflib
            close = difflib.get_close_matches(name, [*PRESSURE_PARAMS, *entries()], n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else " (see 'shimmy params'; pressures: pressure, " \
                                                                   "pressure_left, pressure_right)"
            raise UsageError(f"--vary: unknown input '{name}'{hint}")
    parts = [s.strip() for s in spec.split(":")]
    what = f"--vary {name}"
    if parts[0] in DISTRIBUTIONS:
        if len(parts) != 3:
            raise UsageError(f"{what}: expected {parts[0]}:{'LO:HI' if parts[0] == 'uniform' else 'MEAN:SD'}, "
                             f"got '{spec}'")
        a, b = _float(parts[1], what), _float(parts[2], what)
        if parts[0] == "uniform" and not a < b:
            raise UsageError(f"{what}: uniform needs LO < HI, got {a:g} and {b:g}")
        if parts[0] == "normal" and not b > 0.0:
            raise UsageError(f"{what}: normal needs a positive standard deviation, got {b:g}")
        return Variation(name, parts[0], a, b)
    if len(parts) != 3:
        raise UsageError(f"{what}: expected LO:HI:N, uniform:LO:HI or normal:MEAN:SD, got '{spec}'")
    a, b = _float(parts[0], what), _float(parts[1], what)
    try:
        n = int(parts[2])
    except ValueError:
        raise UsageError(f"{what}: the number of grid points must be an integer, got '{parts[2]}'") from None
    if n < 1 or (n == 1 and a != b) or (n > 1 and not a < b):
        raise UsageError(f"{what}: a grid needs LO < HI and N >= 2 (or LO = HI and N = 1), got {spec}")
    return Variation(name, "grid", a, b, n)


@dataclass(frozen=True)
class Design:
    """The samples: ``values[i, j]`` is input ``variations[j]`` of sample i (interface units)."""

    variations: tuple[Variation, ...]
    kind: str                      # "grid", "sobol" or "saltelli"
    values: np.ndarray
    seed: int | None
    base_samples: int | None       # saltelli: N

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.variations)

    def __len__(self) -> int:
        return len(self.values)

    def to_json(self) -> dict:
        return {"kind": self.kind, "samples": len(self), "seed": self.seed, "base_samples": self.base_samples,
                "inputs": [v.to_json() for v in self.variations]}

    def fingerprint(self) -> str:
        """Changes whenever any sample would: checked before a sweep is resumed."""
        h = hashlib.sha256(json.dumps(self.to_json(), sort_keys=True).encode())
        h.update(np.ascontiguousarray(self.values, dtype=np.float64).tobytes())
        return h.hexdigest()


def _sobol_points(d: int, n: int, seed: int) -> np.ndarray:
    from scipy.stats import qmc
    engine = qmc.Sobol(d=d, scramble=True, rng=np.random.default_rng(seed))
    with warnings.catch_warnings():
        # Balance properties need n a power of two; other sizes are still a fine low-discrepancy sample.
        warnings.simplefilter("ignore", UserWarning)
        return engine.random(n)


def make_design(variations: list[Variation], samples: int | None, seed: int | None,
                design: str | None = None) -> Design:
    """The full-factorial grid, or N quasi-random samples (or Saltelli's N (D + 2) rows) from ``seed``."""
    if not variations:
        raise UsageError("give at least one --vary NAME=...")
    names = [v.name for v in variations]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise UsageError(f"--vary {dup[0]} is given twice")
    random = [v for v in variations if v.random]
    if random and len(random) != len(variations):
        raise UsageError("--vary mixes grids (LO:HI:N) with distributions (uniform/normal): use one kind per sweep")
    if not random:
        if samples is not None or design not in (None, "grid"):
            raise UsageError("--samples and --design apply to uniform/normal inputs; a grid has N points per input")
        total = math.prod(v.n for v in variations)
        if total > MAX_SAMPLES:
            raise UsageError(f"the grid has {total} samples, more than {MAX_SAMPLES}")
        values = np.array(list(itertools.product(*(v.grid() for v in variations))), dtype=float)
        return Design(tuple(variations), "grid", values.reshape(total, len(variations)), None, None)
    design = design or "sobol"
    if design not in DESIGNS:
        raise UsageError(f"--design must be one of {', '.join(DESIGNS)}, got '{design}'")
    if samples is None or samples < 1:
        raise UsageError("uniform/normal inputs need --samples N (N >= 1)")
    seed = 0 if seed is None else seed
    if seed < 0:
        raise UsageError(f"--seed must not be negative, got {seed}")
    d = len(variations)
    if design == "sobol":
        if samples > MAX_SAMPLES:
            raise UsageError(f"--samples {samples} is more than {MAX_SAMPLES}")
        u = _sobol_points(d, samples, seed)
        base = None
    else:
        if samples * (d + 2) > MAX_SAMPLES:
            raise UsageError(f"--samples {samples} with --design saltelli gives {samples * (d + 2)} rows, more "
                             f"than {MAX_SAMPLES}")
        ab = _sobol_points(2 * d, samples, seed)
        A, B = ab[:, :d], ab[:, d:]
        blocks = [A]
        for j in range(d):
            AB = A.copy()
            AB[:, j] = B[:, j]
            blocks.append(AB)
        blocks.append(B)
        # row order per base sample i: A_i, AB_1i, ..., AB_Di, B_i
        u = np.stack(blocks, axis=1).reshape(samples * (d + 2), d)
        base = samples
    values = np.column_stack([v.from_unit(u[:, j]) for j, v in enumerate(variations)])
    return Design(tuple(variations), design, values, seed, base)
