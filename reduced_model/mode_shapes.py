"""Eigenvalues of straight running and what moves in each mode (``shimmy modes``).

For the Jacobian A at straight running (reduced-model state order theta1, theta1_dot, theta2, theta2_dot, psi,
psi_dot, alpha1, alpha2, SI), each eigenvalue lambda (one of each complex pair, Im >= 0) gives

* the damped frequency |Im lambda| / 2 pi and the damping ratio zeta = -Re lambda / |lambda| (a linear oscillator
  x'' + 2 zeta w x' + w^2 x = 0 has lambda = -zeta w +- i w sqrt(1 - zeta^2));
* the mode's character from its eigenvector v: the peak kinetic energies of the motion, (I1/2)|theta1_dot|^2 and
  (I1/2)|theta2_dot|^2 of the wheels about their kingpins (yaw) and (I3/2)|psi_dot|^2 of the axle about x (tramp),
  give the yaw and tramp shares; the slip share is the slip angles' part of all angles (|alpha1|^2 + |alpha2|^2
  over the sum with |theta1|^2 + |theta2|^2 + |psi|^2), as the slip states carry no inertia.  A mode is "slip"
  (tyre relaxation) when the slip share exceeds one half, else "yaw" or "tramp" by the larger energy share.
  Kinetic energy, not angle, decides yaw against tramp: the paper's tramp mode moves psi by a third of theta1
  (reduced_model.modes), but the axle's inertia I3 = 160 kg m^2 dwarfs the wheels' I1 = 6 kg m^2.
* the left wheel's share of the wheel-yaw energy (wheel 2, theta2) and the phase of theta2 against theta1
  (0: the wheels steer together, pi: against each other).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from reduced_model.model import STATE_NAMES

_I = {name: STATE_NAMES.index(name) for name in STATE_NAMES}
REAL_TOL = 1e-9     # |Im lambda| below this (1/s): a real eigenvalue


@dataclass(frozen=True)
class ModeShape:
    eigenvalue: complex          # 1/s
    frequency_hz: float          # damped frequency; 0 for a real eigenvalue
    damping_ratio: float         # -Re / |lambda|; negative: the mode grows
    character: str               # "yaw", "tramp" or "slip"
    yaw_share: float             # of the peak kinetic energy
    tramp_share: float
    slip_share: float            # of the squared angles
    left_share: float            # left wheel's part of the wheel-yaw kinetic energy
    wheel_phase: float           # phase of theta2 against theta1, rad, (-pi, pi]

    @property
    def stable(self) -> bool:
        return self.eigenvalue.real < 0.0


def mode_shape(eigenvalue: complex, vector: np.ndarray, I1: float, I3: float) -> ModeShape:
    """The character of one eigenpair (module docstring); ``I1`` wheel inertia about the kingpin, ``I3`` axle
    inertia about x, kg m^2."""
    v = np.asarray(vector, dtype=complex)
    lam = complex(eigenvalue)
    wheels = np.array([I1 * abs(v[_I["theta1_dot"]]) ** 2, I1 * abs(v[_I["theta2_dot"]]) ** 2])
    tramp = I3 * abs(v[_I["psi_dot"]]) ** 2
    kinetic = wheels.sum() + tramp
    angles = np.abs(v[[_I["theta1"], _I["theta2"], _I["psi"], _I["alpha1"], _I["alpha2"]]]) ** 2
    slip = float(angles[3:].sum() / angles.sum()) if angles.sum() > 0 else 0.0
    yaw_share = float(wheels.sum() / kinetic) if kinetic > 0 else 0.0
    tramp_share = float(tramp / kinetic) if kinetic > 0 else 0.0
    if kinetic == 0.0:   # a mode of the slip states alone: share the wheels by their angles
        wheels = angles[:2]
    left = float(wheels[1] / wheels.sum()) if wheels.sum() > 0 else float("nan")
    t1, t2 = v[_I["theta1"]], v[_I["theta2"]]
    phase = float(np.angle(t2 / t1)) if abs(t1) > 0 and abs(t2) > 0 else float("nan")
    character = "slip" if slip > 0.5 else ("tramp" if tramp_share > yaw_share else "yaw")
    modulus = abs(lam)
    return ModeShape(eigenvalue=lam, frequency_hz=abs(lam.imag) / (2 * math.pi) if abs(lam.imag) > REAL_TOL
                     else 0.0, damping_ratio=-lam.real / modulus if modulus > 0 else float("nan"),
                     character=character, yaw_share=yaw_share, tramp_share=tramp_share, slip_share=slip,
                     left_share=left, wheel_phase=phase)


def mode_shapes(A: np.ndarray, I1: float, I3: float) -> list[ModeShape]:
    """Every mode of the linear system x' = A x, one per complex pair, least stable first."""
    values, vectors = np.linalg.eig(np.asarray(A, dtype=float))
    keep = [k for k in range(len(values)) if values[k].imag >= -REAL_TOL]   # one of each pair, every real one
    shapes = [mode_shape(values[k], vectors[:, k], I1, I3) for k in keep]
    return sorted(shapes, key=lambda m: -m.eigenvalue.real)
