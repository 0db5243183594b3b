"""Eigenvalues of straight running and what moves in each mode (``shimmy modes``).

For the Jacobian A at straight running (reduced-model state order theta1, theta1_dot, theta2, theta2_dot, psi,
psi_dot, alpha1, alpha2, SI), each eigenvalue lambda (one of each complex pair, Im >= 0) gives

* the damped frequency |Im lambda| / 2 pi and the damping ratio zeta = -Re lambda / |lambda| (a linear oscillator
  x'' + 2 zeta w x' + w^2 x = 0 has lambda = -zeta w +- i w sqrt(1 - zeta^2));
* the mode's character from its eigenvector v: the peak kinetic energies of the motion, (m_c/2)|c_dot|^2 of every
  mechanical coordinate c with its inertia m_c (the diagonal of the mass matrix at straight running: I1 for the
  wheels about their kingpins theta1, theta2, I3 for the axle about x, psi, and on the multibody model's full
  geometry the axle's lateral travel y_axle and the steering gear phi_gear), grouped as yaw (theta1, theta2),
  tramp (psi), lateral (y_axle) and gear (phi_gear), give the energy shares; the slip share is the slip angles'
  part of all angles (|alpha1|^2 + |alpha2|^2 over the sum with |theta1|^2 + |theta2|^2 + |psi|^2), as the slip
  states carry no inertia.  A real (non-oscillating) mode is "slip" (tyre relaxation) when the slip share exceeds
  one half; every other mode is named by its largest energy share.  Kinetic energy, not angle, decides: the paper's tramp mode moves psi by a third
  of theta1 (reduced_model.modes), but the axle's inertia I3 = 160 kg m^2 dwarfs the wheels' I1 = 6 kg m^2; and a
  mode whose energy sits in the steering gear is a gear mode however much the wheels turn with it.  The diagonal
  leaves out the inertial coupling of the coordinates, so the shares are a partition of the uncoupled energies
  (modal kinetic-energy fractions, as in structural mode identification; Ewins, Modal Testing, 2nd ed. 2000,
  section 4.3).
* the left wheel's share of the wheel-yaw energy (wheel 2, theta2) and the phase of theta2 against theta1
  (0: the wheels steer together, pi: against each other).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from reduced_model.model import STATE_NAMES

REAL_TOL = 1e-9     # |Im lambda| below this (1/s): a real eigenvalue


@dataclass(frozen=True)
class ModeShape:
    eigenvalue: complex          # 1/s
    frequency_hz: float          # damped frequency; 0 for a real eigenvalue
    damping_ratio: float         # -Re / |lambda|; negative: the mode grows
    character: str               # "slip" or the group of the largest energy share (GROUPS)
    yaw_share: float             # of the peak kinetic energy
    tramp_share: float
    slip_share: float            # of the squared angles
    left_share: float            # left wheel's part of the wheel-yaw kinetic energy
    wheel_phase: float           # phase of theta2 against theta1, rad, (-pi, pi]
    shares: dict = field(default_factory=dict)   # energy share of every group the model has (GROUPS)

    @property
    def stable(self) -> bool:
        return self.eigenvalue.real < 0.0


GROUPS = {"yaw": ("theta1", "theta2"), "tramp": ("psi",), "lateral": ("y_axle",), "bounce": ("z_axle",),
          "gear": ("phi_gear",)}


def reduced_inertias(I1: float, I3: float) -> dict[str, float]:
    """The reduced model's mass matrix, diagonal: I1 for each wheel about its kingpin, I3 for the axle's roll."""
    return {"theta1": I1, "theta2": I1, "psi": I3}


def mode_shape(eigenvalue: complex, vector: np.ndarray, inertias: dict[str, float],
               names: tuple[str, ...] = STATE_NAMES) -> ModeShape:
    """The character of one eigenpair (module docstring).  ``inertias``: the mass matrix's diagonal by mechanical
    coordinate (kg m^2 or kg), each coordinate c having its rate ``c_dot`` among the state ``names``."""
    v = np.asarray(vector, dtype=complex)
    lam = complex(eigenvalue)
    at = {name: k for k, name in enumerate(names)}
    energy = {c: m * abs(v[at[c + "_dot"]]) ** 2 for c, m in inertias.items()}
    kinetic = sum(energy.values())
    shares = {group: float(sum(energy[c] for c in coords if c in energy) / kinetic) if kinetic > 0 else 0.0
              for group, coords in GROUPS.items() if any(c in energy for c in coords)}
    wheels = np.array([energy.get("theta1", 0.0), energy.get("theta2", 0.0)])
    angles = np.abs(v[[at["theta1"], at["theta2"], at["psi"], at["alpha1"], at["alpha2"]]]) ** 2
    slip = float(angles[3:].sum() / angles.sum()) if angles.sum() > 0 else 0.0
    if kinetic == 0.0:   # a mode of the slip states alone: share the wheels by their angles
        wheels = angles[:2]
    left = float(wheels[1] / wheels.sum()) if wheels.sum() > 0 else float("nan")
    t1, t2 = v[at["theta1"]], v[at["theta2"]]
    phase = float(np.angle(t2 / t1)) if abs(t1) > 0 and abs(t2) > 0 else float("nan")
    # The slip states have no inertia: alone they relax, they cannot oscillate.  An oscillating mode takes its
    # inertia from a mechanical coordinate and is named by it, however much the tyres slip (the full geometry's
    # lateral mode, whose travel y_axle is no angle, would otherwise count as slip).
    oscillates = abs(lam.imag) > REAL_TOL
    character = "slip" if slip > 0.5 and not oscillates else max(shares, key=shares.get)
    modulus = abs(lam)
    return ModeShape(eigenvalue=lam, frequency_hz=abs(lam.imag) / (2 * math.pi) if abs(lam.imag) > REAL_TOL
                     else 0.0, damping_ratio=-lam.real / modulus if modulus > 0 else float("nan"),
                     character=character, yaw_share=shares.get("yaw", 0.0), tramp_share=shares.get("tramp", 0.0),
                     slip_share=slip, left_share=left, wheel_phase=phase, shares=shares)


def mode_shapes(A: np.ndarray, I1: float | None = None, I3: float | None = None,
                inertias: dict[str, float] | None = None, names: tuple[str, ...] = STATE_NAMES) -> list[ModeShape]:
    """Every mode of the linear system x' = A x, one per complex pair, least stable first.  The energies weigh the
    rates by ``inertias`` (default: the reduced model's, :func:`reduced_inertias` of ``I1`` and ``I3``)."""
    if inertias is None:
        inertias = reduced_inertias(I1, I3)
    values, vectors = np.linalg.eig(np.asarray(A, dtype=float))
    keep = [k for k in range(len(values)) if values[k].imag >= -REAL_TOL]   # one of each pair, every real one
    shapes = [mode_shape(values[k], vectors[:, k], inertias, names) for k in keep]
    return sorted(shapes, key=lambda m: -m.eigenvalue.real)
