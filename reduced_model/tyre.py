"""Pressure-dependent tyre of the shimmy model: the one copy of every tyre formula in the project.

Equations of Yang, Knowles & Mavros (The ANZIAM Journal, 2025; reading notes in
``docs/paper-notes.md``):
lateral force (2.4)-(2.9) after Pacejka's pressure-extended Magic Formula (Tyre and Vehicle Dynamics, 3rd ed.,
section 4.3.2) with the E_y pressure polynomial of Hopping; half contact length (4.1) after Guo; pneumatic trail
(4.2)-(4.8); relaxation length (4.9) and vertical stiffness (4.10) after Besselink.  Under braking: the MF 6.1
longitudinal force and the combined-slip weighting functions of Pacejka (2012), section 4.3.2, (4.E9)-(4.E18) and
(4.E50)-(4.E67) (:class:`CombinedSlip`; decisions in docs/numerics.md, "Braking").

All functions are pure and accept numpy arrays (real or complex, so that complex-step and Cauchy-integral
derivatives pass through).  Pressures are in Pa, forces in N, lengths in m, slip angles in rad.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from bifurcation.messages import Message, Quantity
from axles.parameters import ParameterError, ShimmyParameters


def value(x):
    """One value as a float; an array (the loads of the MBS's load table, evaluated at once) as it is."""
    return float(x) if np.ndim(x) == 0 else np.asarray(x)


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
    return MagicFormula(B=value(B), C=value(C), D=value(D), E=value(E))


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
    return TrailFormula(Bt=value(Bt), Ct=params.q_cz1, Dt=value(Dt), Et0=value(Et0), q_ez4=params.q_ez4)


def pneumatic_trail(params: ShimmyParameters, alpha, pressure: float):
    """Pneumatic trail t(alpha, p_i), eqs. (4.2)-(4.8), m."""
    return trail_formula(params, pressure).trail(alpha)


def half_contact_length(params: ShimmyParameters, pressure: float) -> float:
    """a(p_i), eq. (4.1): a0 sqrt(Fz/Fz0) sqrt(p_i0/p_i), m."""
    return value(params.a0 * np.sqrt(params.Fz / params.Fz0) * np.sqrt(params.pi0 / pressure))


def relaxation_length(params: ShimmyParameters, pressure: float) -> float:
    """sigma(p_i), eq. (4.9): K_ya / (c_y0 (1 + p_cy1 dp_i)), m."""
    dp = pressure_increment(params, pressure)
    return value(cornering_stiffness(params, pressure) / (params.c_y0 * (1.0 + params.p_cy1_rl * dp)))


def vertical_stiffness(params: ShimmyParameters, pressure: float) -> float:
    """k5(p_i), eq. (4.10): k5_0 (1 + p_fz1 dp_i), N/m."""
    return float(params.k5_0 * (1.0 + params.p_fz1 * pressure_increment(params, pressure)))


# --- longitudinal force and combined slip (MF 6.1), for a braking wheel ---------------------------------------
# Pacejka, Tire and Vehicle Dynamics, 3rd ed. (2012), section 4.3.2: the pure longitudinal force (4.E9)-(4.E18)
# and the combined-slip weighting functions G_xa, G_yk with the slip-induced side force S_Vyk (4.E50)-(4.E67), at
# zero camber.  Slip kappa is ISO's (braking negative), alpha the models' slip angle (MF's tan-slip alpha*, the
# same sign as the lateral force of (2.4)-(2.5) takes it).  Decisions (docs/numerics.md, "Braking"): the pure
# longitudinal force has no shifts S_Hx, S_Vx (as the paper's lateral force has no S_Hy, S_Vy); df_z is the
# paper's (F_z - F_z0)/F_z, as in (2.7)-(2.9); the combined-slip shifts r_Hx1, r_Hy1, r_Hy2, r_By3 and the side force
# S_Vyk are kept.


def mf_sine(B, C, D, E, x, sin, atan):
    """D sin(C arctan(B x - E (B x - arctan(B x)))): the Magic Formula's sine form, (4.E9)."""
    bx = B * x
    return D * sin(C * atan(bx - E * (bx - atan(bx))))


def mf_weight(B, C, E, x, shift, cos, atan):
    """cos(C arctan(B x_s - E (B x_s - arctan(B x_s)))) / (the same at x = 0), x_s = x + shift: the combined-slip
    weighting function G of (4.E51)-(4.E53) (G_xa, x = alpha) and (4.E59)-(4.E61) (G_yk, x = kappa)."""
    xs = x + shift
    bx, b0 = B * xs, B * shift
    return cos(C * atan(bx - E * (bx - atan(bx)))) / cos(C * atan(b0 - E * (b0 - atan(b0))))


@dataclass(frozen=True)
class LongitudinalFormula:
    """Factors of the pure longitudinal force (4.E9)-(4.E16) at one load and pressure (no shifts); ``E0`` is E_x
    before its driving/braking asymmetry (1 - p_ex4 sgn kappa)."""

    B: float
    C: float
    D: float
    E0: float
    p_ex4: float

    def force(self, kappa: float) -> float:
        """F_x0(kappa), N (ISO: braking, kappa < 0, gives F_x0 < 0)."""
        E = self.E0 * (1.0 - self.p_ex4 * math.copysign(1.0, kappa)) if kappa != 0.0 else self.E0
        return float(mf_sine(self.B, self.C, self.D, E, kappa, math.sin, math.atan))


def longitudinal_formula(params: ShimmyParameters, pressure: float) -> LongitudinalFormula:
    """F_x0's factors at the parameter set's load and the given pressure, (4.E11)-(4.E16) with the pressure terms
    of Besselink, Schmeitz & Pacejka (2010) and zero camber."""
    dp = pressure_increment(params, pressure)
    dfz = load_increment(params)
    P = params
    C = P.p_cx1
    D = P.Fz * (P.p_dx1 + P.p_dx2 * dfz) * (1.0 + P.p_px3 * dp + P.p_px4 * dp ** 2)
    K = P.Fz * (P.p_kx1 + P.p_kx2 * dfz) * math.exp(P.p_kx3 * dfz) * (1.0 + P.p_px1 * dp + P.p_px2 * dp ** 2)
    E0 = P.p_ex1 + P.p_ex2 * dfz + P.p_ex3 * dfz ** 2
    return LongitudinalFormula(B=float(K / (C * D)), C=float(C), D=float(D), E0=float(E0), p_ex4=P.p_ex4)


def combined_weights(c: tuple, alpha, cos, atan):
    """(G_xa, G_yk, S_Vyk) at slip angle alpha of the combined-slip constants ``c`` (:attr:`CombinedSlip.constants`),
    (4.E51)-(4.E57) and (4.E59)-(4.E67), with the given cos and atan (numpy's, math's, or the compiled stage's and
    the twin's: the one text of these laws)."""
    Gxa = mf_weight(c[1], c[2], c[3], alpha, c[4], cos, atan)
    Byk = c[5] * cos(atan(c[6] * (alpha - c[7])))
    Gyk = mf_weight(Byk, c[8], c[9], c[11], c[10], cos, atan)
    SVyk = c[12] * cos(atan(c[13] * alpha)) * c[14]
    return Gxa, Gyk, SVyk


def trail_slip(c: tuple, alpha, sqrt, choose):
    """alpha_t,eq = sgn(alpha) sqrt(alpha^2 + (K_xk / K_ya)^2 kappa^2), (4.E77) with the paper's zero shift S_Ht: the
    slip angle the pneumatic trail is evaluated at under combined slip; alpha itself, bit for bit, at kappa = 0.
    sgn(0) is taken as +1: at alpha = 0 the trail multiplies F_y0(0) = 0."""
    k = c[15]
    return choose(k == 0.0, alpha, choose(alpha < 0.0, -1.0, 1.0) * sqrt(alpha * alpha + k * k))


def combined_forces(c: tuple, alpha, fy0, dfy, mzr, t_eq, cos, atan):
    """(F_x, F_y, M_z) of MF 6.1's combined slip at slip angle alpha, from the pure slip force F_y0 = ``fy0``, the
    camber force and moment ``dfy``, ``mzr`` (0 without camber terms) and the trail ``t_eq`` at alpha_t,eq
    (:func:`trail_slip`):

        F_x = G_xa F_x0                                   (4.E50)
        F_y = G_yk (F_y0 + dF_y) + S_Vyk                  (4.E58)
        M_z = -t(alpha_t,eq) G_yk F_y0 + G_yk M_zr + s F_x,   s = R (SSZ1 + SSZ2 F_y / F_z0)   (4.E71)-(4.E76)

    The paper's aligning moment is the trail's, -t F_y0 (no residual moment M_zr: its D_r is 0), so F'_y = F_y -
    S_Vyk of (4.E74) is G_yk F_y0; the camber terms (the multibody model's, where on) are weighted by G_yk as F_y0.
    At kappa = 0: F_x = 0, F_y = F_y0 + dF_y and M_z = -t F_y0 + M_zr bit for bit."""
    Gxa, Gyk, SVyk = combined_weights(c, alpha, cos, atan)
    fx = Gxa * c[0]
    fy = Gyk * (fy0 + dfy) + SVyk
    return fx, fy, -t_eq * (Gyk * fy0) + Gyk * mzr + (c[16] + c[17] * fy) * fx


def braked_relaxation_length(c: tuple, sigma):
    """The relaxation length under braking: the paper's law (4.9), sigma = K_ya / C_y after Besselink (cornering
    stiffness over the carcass's lateral stiffness, the stretched string's and von Schlippe's relation; Pacejka
    2012, chapter 5), with the cornering stiffness of the braking tyre, dF_y/dalpha at alpha = 0 = G_yk(0; kappa) K_ya
    (F_y0(0) = 0, and S_Vyk is even in alpha there), and C_y unchanged: sigma G_yk(0; kappa).  The factor is 1 where
    the relaxation length follows nothing (the section 3 model's constant sigma0, ``rl`` off) and at kappa = 0."""
    return sigma * c[18]


@dataclass(frozen=True)
class CombinedSlip:
    """One wheel's forces at a fixed longitudinal slip ``kappa`` (ISO) against its slip angle: F_x = G_xa F_x0
    (4.E50), F_y = G_yk F_y0 + S_Vyk (4.E58) and the aligning moment of (4.E71)-(4.E77), at one load and pressure
    (:func:`combined_forces`).

    ``mirrored``: the tyre turned round for the other side of the axle (MF's TYRESIDE): F_y(alpha) becomes
    -F_y(-alpha), F_x(alpha) becomes F_x(-alpha) and M_z(alpha) becomes -M_z(-alpha), which flips the signs of r_By3,
    r_Vy1, r_Vy2, r_Hx1 and s_Sz1 (the paper's F_y0 is odd in alpha and unchanged; its trail is not mirrored, as
    without braking)."""

    kappa: float
    Fx0: float                 # F_x0(kappa), N
    Bxa: float                 # (4.E54) at kappa, zero camber
    Cxa: float
    Exa: float
    SHxa: float
    r_by1: float
    r_by2: float
    r_by3: float
    Cyk: float
    Eyk: float
    SHyk: float
    DVyk0: float               # mu_y F_z (r_Vy1 + r_Vy2 df_z), N (4.E67 without its cosine)
    r_vy4: float
    SVyk_sine: float           # sin(r_Vy5 arctan(r_Vy6 kappa)) of (4.E66)
    kappa_t: float = 0.0       # (K_xk / K_ya) kappa of alpha_t,eq (4.E77), rad
    s0: float = 0.0            # R s_Sz1 (mirrored), m
    s1: float = 0.0            # R s_Sz2 / F_z0, m/N
    sigma_factor: float = 1.0  # the relaxation length's factor under braking (:func:`braked_relaxation_length`)

    @functools.cached_property
    def constants(self) -> tuple[float, ...]:
        """The floats :func:`combined_weights`, :func:`trail_slip`, :func:`combined_forces` and
        :func:`braked_relaxation_length` read, in order."""
        return (self.Fx0, self.Bxa, self.Cxa, self.Exa, self.SHxa, self.r_by1, self.r_by2, self.r_by3, self.Cyk,
                self.Eyk, self.SHyk, self.kappa, self.DVyk0, self.r_vy4, self.SVyk_sine, self.kappa_t, self.s0,
                self.s1, self.sigma_factor)

    def following_braking(self) -> "CombinedSlip":
        """This wheel with the relaxation length following the braking: the factor G_yk(alpha = 0; kappa) of
        :func:`braked_relaxation_length`."""
        return dataclasses.replace(self, sigma_factor=float(self.weights(0.0, math.cos, math.atan)[1]))

    def weights(self, alpha, cos=np.cos, atan=np.arctan):
        """(G_xa, G_yk, S_Vyk) at slip angle alpha (array or complex too)."""
        return combined_weights(self.constants, alpha, cos, atan)

    def forces(self, fy0, alpha, cos=np.cos, atan=np.arctan):
        """(F_x, F_y) at slip angle alpha from the pure lateral force ``fy0`` = F_y0(alpha)."""
        Gxa, Gyk, SVyk = self.weights(alpha, cos, atan)
        return Gxa * self.Fx0, Gyk * fy0 + SVyk

    def trail_slip(self, alpha):
        """alpha_t,eq of :func:`trail_slip` for numpy arrays (real or complex: the sign is the real part's)."""
        return trail_slip(self.constants, alpha, np.sqrt, lambda cond, a, b: np.where(np.real(cond), a, b))

    def moment_and_forces(self, fy0, alpha, trail):
        """(F_x, F_y, M_z) of :func:`combined_forces` for numpy arrays, ``trail(alpha)`` the wheel's trail law."""
        return combined_forces(self.constants, alpha, fy0, 0.0, 0.0, trail(self.trail_slip(alpha)), np.cos,
                               np.arctan)


def combined_slip(params: ShimmyParameters, pressure: float, kappa: float, mirrored: bool = False) -> CombinedSlip:
    """:class:`CombinedSlip` of a wheel at the parameter set's load, the given pressure and slip ``kappa`` (ISO:
    braking negative)."""
    P = params
    dfz = load_increment(P)
    m = -1.0 if mirrored else 1.0
    mu_y_fz = magic_formula(P, pressure).D
    lf = longitudinal_formula(P, pressure)
    return CombinedSlip(
        kappa=float(kappa), Fx0=lf.force(kappa),
        Bxa=P.r_bx1 * math.cos(math.atan(P.r_bx2 * kappa)), Cxa=P.r_cx1, Exa=P.r_ex1 + P.r_ex2 * dfz,
        SHxa=m * P.r_hx1, r_by1=P.r_by1, r_by2=P.r_by2, r_by3=m * P.r_by3, Cyk=P.r_cy1,
        Eyk=P.r_ey1 + P.r_ey2 * dfz, SHyk=P.r_hy1 + P.r_hy2 * dfz,
        DVyk0=m * mu_y_fz * (P.r_vy1 + P.r_vy2 * dfz), r_vy4=P.r_vy4,
        SVyk_sine=math.sin(P.r_vy5 * math.atan(P.r_vy6 * kappa)),
        kappa_t=float(lf.B * lf.C * lf.D / cornering_stiffness(P, pressure) * kappa),
        s0=m * P.R * P.s_sz1, s1=P.R * P.s_sz2 / P.Fz0)


def peak_brake_slip(params: ShimmyParameters, pressure: float, driving: bool = False) -> tuple[float, float]:
    """(brake slip, brake force N) at the peak of -F_x0 for braking: the largest steady brake force the tyre gives
    at straight running; ``driving``: at the peak of F_x0 for driving, both then negative (ISO kappa = -slip > 0;
    E_x's asymmetry p_ex4 makes the two peaks differ)."""
    from scipy.optimize import minimize_scalar
    lf = longitudinal_formula(params, pressure)
    sign = -1.0 if driving else 1.0
    res = minimize_scalar(lambda s: sign * lf.force(-sign * s), bounds=(1e-6, 1.0), method="bounded",
                          options={"xatol": 1e-12})
    return float(sign * res.x), float(-lf.force(-sign * res.x))


def brake_slip_for_force(params: ShimmyParameters, pressure: float, force: float) -> float:
    """The brake slip (positive braking, negative driving; ISO kappa = -slip) at which the tyre gives the brake
    force ``force`` (N, rearward; negative: a drive force, forward) at straight running (alpha = 0, where
    G_xa = 1); at most the peak's, or a :class:`ParameterError`."""
    from scipy.optimize import brentq
    if force == 0.0:
        return 0.0
    driving = force < 0.0
    s_peak, f_peak = peak_brake_slip(params, pressure, driving)
    if not abs(force) < abs(f_peak):
        what = "drive force" if driving else "brake force"
        raise ParameterError(Message.of(f"{what} = {abs(force):.6g} N is beyond the tyre's grip: at most "
                                        f"{abs(f_peak):.6g} N at ", Quantity("pressure", pressure, 10),
                                        f" ({'drive' if driving else 'brake'} slip {abs(s_peak):.4g})"))
    lf = longitudinal_formula(params, pressure)
    return float(brentq(lambda s: -lf.force(-s) - force, min(0.0, s_peak), max(0.0, s_peak), xtol=1e-15,
                        rtol=1e-15))
