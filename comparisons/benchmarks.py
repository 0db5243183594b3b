"""Performance benchmarks run by ``shimmy bench`` (never as timed unit tests).

Each benchmark is timed several times; the median is reported together with its ratio to a fixed baseline
workload timed in the same process (1000 eigenvalue decompositions of a random 8 x 8 matrix), so that numbers
from different machines can be compared.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class BenchResult:
    name: str
    description: str
    median_s: float
    runs: tuple[float, ...]
    baseline_s: float
    target_s: float | None

    @property
    def ratio(self) -> float:
        return self.median_s / self.baseline_s

    @property
    def meets_target(self) -> bool | None:
        return None if self.target_s is None else self.median_s <= self.target_s


@dataclass(frozen=True)
class Benchmark:
    name: str
    description: str
    target_s: float | None
    setup: Callable[[], Callable[[], object]]  # returns the timed callable (setup work is not timed)
    repeats: int = 7


def baseline_workload() -> None:
    rng = np.random.default_rng(0)
    A = rng.standard_normal((8, 8))
    for _ in range(1000):
        np.linalg.eigvals(A)


def median_time(fn: Callable[[], object], repeats: int) -> tuple[float, tuple[float, ...]]:
    fn()  # warm caches and imports
    runs = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        runs.append(time.perf_counter() - t0)
    return statistics.median(runs), tuple(runs)


def _hopf_one_pressure():
    from reduced_model.family import SpeedFamily
    from reduced_model.hopf import hopf_points
    from reduced_model.model import ShimmyModel

    def run():
        # A fresh model each run: no tyre cache carried over between runs.
        return hopf_points(SpeedFamily(ShimmyModel()), 1.5e5, 0.0, 400 / 3.6)
    return run


def _figure5():
    from reduced_model.family import SpeedFamily
    from reduced_model.hopf_curves import hopf_diagram
    from reduced_model.model import ShimmyModel

    def run():
        return hopf_diagram(SpeedFamily(ShimmyModel(), "pressure"), 0.05e5, 3e5, 0.0, 400 / 3.6)
    return run


BENCHMARKS: list[Benchmark] = [
    Benchmark("hopf_points_1.5bar", "all Hopf points at 1.5 bar, 0-400 km/h, with l1", 0.020, _hopf_one_pressure),
    Benchmark("figure5_diagram", "figure 5: Hopf curves 0.05-3 bar, 0-400 km/h, with special points", 1.0,
              _figure5, repeats=5),
]


def run_benchmarks(names: list[str] | None = None, progress=None) -> list[BenchResult]:
    chosen = [b for b in BENCHMARKS if not names or b.name in names]
    baseline, _ = median_time(baseline_workload, 7)
    results = []
    for i, b in enumerate(chosen):
        median, runs = median_time(b.setup(), b.repeats)
        results.append(BenchResult(b.name, b.description, median, runs, baseline, b.target_s))
        if progress is not None:
            progress(i + 1, len(chosen))
    return results
