"""Pressure-dependent tyre of the shimmy model: the one copy of every tyre formula in the project.

Equations of Yang, Knowles & Mavros (The ANZIAM Journal, 2025; reading notes in
``docs/paper-notes.md``):
lateral force (2.4)-(2.9) after Pacejka's pressure-extended Magic Formula (Tyre and Vehicle Dynamics, 3rd ed.,
section 4.3.2) with the E_y pressure polynomial of Hopping; half contact length (4.1) after Guo; pneumatic trail
(4.2)-(4.8); relaxation length (4.9) and vertical stiffness (4.10) after Besselink.

All functions are pure and accept numpy arrays (real or complex, so that complex-step and Cauchy-integral
derivatives pass through).  Pressures are in Pa, forces in N, lengths in m, slip angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from axles.parameters import ShimmyParameters


def pressure_increment(params: ShimmyParameters, pressure: float) -> float:
    """dp_i = (p_i - p_i0) / p_i0."""
    return (pressure - params.pi0) / params.pi0


def load_increment(params: ShimmyParameters) -> float:
    """df_z as printed below eq. (2.9): (F_z - F_z0) / F_z (zero in every analysis of the paper)."""
    return (params.Fz - params.Fz0) / params.Fz


def mf_force(B, C, D, E, alpha, sin, atan):
    """F_y of eqs. (2.4)-(2.5) with the given sin and atan (numpy's for arrays, math's for one float; the MBS's
    compiled solver stage, :mod:`mbs_shimmy.compiled_stage`, compiles this function itself with math's)."""
    ba = B * alpha
    return -D * sin(C * atan(ba - E * (ba - atan(ba))))


def mf_trail(Bt, Ct, Dt, Et0, q_ez4, alpha, cos, atan):
    """t(alpha) of eqs. (4.2)-(4.3) with E_t from (4.7)-(4.8), with the given cos and atan (as :func:`mf_force`)."""
    bta = Bt * alpha
    Et = Et0 * (1.0 + 2.0 * q_ez4 / math.pi * atan(Bt * Ct * alpha))
    return Dt * cos(Ct * atan(bta - Et * (bta - atan(bta))))


@dataclass(frozen=True)
class MagicFormula:
    """Factors B, C, D, E of the lateral Magic Formula at one load and pressure; ``K`` = B C D."""

    B: float
    C: float
    D: float
    E: float

    @property
    def K(self) -> float:
        return self.B * self.C * self.D

    def force(self, alpha):
        """Lateral force, eqs. (2.4)-(2.5): F_y = -D sin(C arctan(B a - E (B a - arctan(B a))))."""
        return mf_force(self.B, self.C, self.D, self.E, alpha, np.sin, np.arctan)


def cornering_stiffness(params: ShimmyParameters, pressure: float) -> float:
    """K_ya of eq. (2.8), N/rad."""
    dp = pressure_increment(params, pressure)
    return (params.p_ky1 * params.Fz0 * (1.0 + params.p_py1 * dp)
            * np.sin(params.p_ky3 * np.arctan(params.Fz / (params.p_ky2 * (1.0 + params.p_py2 * dp)
                                                           * params.Fz0))))


def magic_formula(params: ShimmyParameters, pressure: float) -> MagicFormula:
    """Lateral Magic-Formula factors at the parameter set's load and the given pressure, eqs. (2.6)-(2.9)."""
    dp = pressure_increment(params, pressure)
    dfz = load_increment(params)
    C = params.p_cy1
    D = params.Fz * (params.p_dy1 + params.p_dy2 * dfz) * (1.0 + params.p_py3 * dp + params.p_py4 * dp ** 2)
    B = cornering_stiffness(params, pressure) / (C * D)
    E = (params.p_ey1 + params.p_ey2 * dfz + params.p_ey3 * dfz ** 2 + params.p_epy1 * dp
         + params.p_epy2 * dp ** 2 + params.p_epey1 * dfz * dp)
    return MagicFormula(B=float(B), C=float(C), D=float(D), E=float(E))


def lateral_force(params: ShimmyParameters, alpha, pressure: float):
    """F_y(alpha, p_i), eqs. (2.4)-(2.9)."""
    return magic_formula(params, pressure).force(alpha)


@dataclass(frozen=True)
class TrailFormula:
    """Factors of the pneumatic-trail formula (4.2)-(4.8) at one load and pressure."""

    Bt: float
    Ct: float
    Dt: float
    Et0: float
    q_ez4: float

    def trail(self, alpha):
        """t(alpha), eqs. (4.2)-(4.3) with E_t from (4.7)-(4.8)."""
        return mf_trail(self.Bt, self.Ct, self.Dt, self.Et0, self.q_ez4, alpha, np.cos, np.arctan)


def trail_formula(params: ShimmyParameters, pressure: float) -> TrailFormula:
    dp = pressure_increment(params, pressure)
    dfz = load_increment(params)
    Dt = params.Fz * params.R / params.Fz0 * (params.q_dz1 + params.q_dz2 * dfz) * (1.0 - params.p_pz1 * dp)
    Bt = params.q_bz1 + params.q_bz2 * dfz + params.q_bz3 * dfz ** 2
    Et0 = params.q_ez1 + params.q_ez2 * dfz + params.q_ez3 * dfz ** 2
    return TrailFormula(Bt=float(Bt), Ct=params.q_cz1, Dt=float(Dt), Et0=float(Et0), q_ez4=params.q_ez4)


def pneumatic_trail(params: ShimmyParameters, alpha, pressure: float):
    """Pneumatic trail t(alpha, p_i), eqs. (4.2)-(4.8), m."""
    return trail_formula(params, pressure).trail(alpha)


def half_contact_length(params: ShimmyParameters, pressure: float) -> float:
    """a(p_i), eq. (4.1): a0 sqrt(Fz/Fz0) sqrt(p_i0/p_i), m."""
    return float(params.a0 * np.sqrt(params.Fz / params.Fz0) * np.sqrt(params.pi0 / pressure))


def relaxation_length(params: ShimmyParameters, pressure: float) -> float:
    """sigma(p_i), eq. (4.9): K_ya / (c_y0 (1 + p_cy1 dp_i)), m."""
    dp = pressure_increment(params, pressure)
    return float(cornering_stiffness(params, pressure) / (params.c_y0 * (1.0 + params.p_cy1_rl * dp)))


def vertical_stiffness(params: ShimmyParameters, pressure: float) -> float:
    """k5(p_i), eq. (4.10): k5_0 (1 + p_fz1 dp_i), N/m."""
    return float(params.k5_0 * (1.0 + params.p_fz1 * pressure_increment(params, pressure)))
