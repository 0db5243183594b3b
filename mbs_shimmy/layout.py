"""Which coordinates the multibody tree has for a set of switches, and the maps between its state order and the
extended reduced-model order (shared by the system builder, the force element and the linearisation).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from reduced_model.model import STATE_NAMES, STATE_UNITS

EXTRA_COORDINATES = ("y_axle", "z_axle", "phi_gear")
EXTRA_UNITS = {"y_axle": "m", "z_axle": "m", "phi_gear": "rad"}


@dataclass(frozen=True)
class Layout:
    """Which coordinates the tree has, and the maps between its states and the extended reduced-model order.

    MBS state ``y = (q, q', alpha1, alpha2)`` with q the mechanical coordinates in tree order; extended state
    ``x = (theta1, theta1', theta2, theta2', psi, psi', alpha1, alpha2, [y_axle, y_axle'], [z_axle, z_axle'],
    [phi_gear, phi_gear'])``:
    the reduced model's state order (:data:`reduced_model.model.STATE_NAMES`) followed by the new coordinates.
    """

    lateral: bool
    gear: bool
    vertical: bool = False

    @property
    def coordinates(self) -> tuple[str, ...]:
        return (("y_axle",) if self.lateral else ()) + (("z_axle",) if self.vertical else ()) + (
            "psi", "theta1", "theta2") + (
            ("phi_gear",) if self.gear else ())

    @property
    def extras(self) -> tuple[str, ...]:
        return tuple(n for n in EXTRA_COORDINATES if n in self.coordinates)

    @property
    def n_mech(self) -> int:
        return len(self.coordinates)

    @property
    def n(self) -> int:
        return 2 * self.n_mech + 2

    @property
    def state_names(self) -> tuple[str, ...]:
        return STATE_NAMES + tuple(x for n in self.extras for x in (n, n + "_dot"))

    @property
    def state_units(self) -> tuple[str, ...]:
        """SI unit of each state of :attr:`state_names`."""
        return STATE_UNITS + tuple(u for n in self.extras for u in (EXTRA_UNITS[n], EXTRA_UNITS[n] + "/s"))

    def index(self, name: str) -> int:
        return self.coordinates.index(name)

    @cached_property
    def y_to_x(self) -> np.ndarray:
        """x[k] = y[y_to_x[k]] (computed once: every right-hand side the families evaluate maps its state; read
        only)."""
        m = self.n_mech
        i = self.index
        order = [i("theta1"), m + i("theta1"), i("theta2"), m + i("theta2"), i("psi"), m + i("psi"), 2 * m, 2 * m + 1]
        for n in self.extras:
            order += [i(n), m + i(n)]
        out = np.array(order)
        out.setflags(write=False)
        return out

    @cached_property
    def x_to_y(self) -> np.ndarray:
        out = np.argsort(self.y_to_x)
        out.setflags(write=False)
        return out
