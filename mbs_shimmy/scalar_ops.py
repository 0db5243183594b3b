"""The elementary functions the shared force laws take as an argument, so that one text of each law serves every
evaluator: Exudyn's Python user function (:mod:`math` on floats), the compiled solver stage (numba compiles the same
functions, with the same tuple built inside the compiled code) and the differentiable twin
(:mod:`mbs_shimmy.twin`: JAX's or CasADi's functions on traced values).

``ops`` is the tuple ``(sin, cos, atan, sqrt, asin, choose)``; ``choose(condition, a, b)`` is ``a`` where the
condition holds, else ``b`` (a branch on a state-dependent value; branches on constants stay Python ``if``).
Builtin ``abs`` and the arithmetic operators work on all of them and are used directly.
"""

from __future__ import annotations

import math


def choose(condition, a, b):
    """``a`` if ``condition`` else ``b``, for floats (the compiled stage compiles this function)."""
    return a if condition else b


MATH = (math.sin, math.cos, math.atan, math.sqrt, math.asin, choose)
