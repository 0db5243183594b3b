"""The Magic Formula's camber terms for the tyre element (assumption ``no_camber_force`` off).

The paper's tyre (eqs. 2.4-2.9) is Pacejka's 205/60R15 91V example tyre without its camber terms.  With the switch
off the lateral force and the aligning moment carry them, in the form of MF-Tyre 6.1 (Pacejka, Tire and Vehicle
Dynamics, 3rd ed., 2012, section 4.3.2, pure side slip), in the ISO/TYDEX W-axis signs the multibody model uses
(slip angle positive for a contact point sliding to the left, camber gamma positive with the top of the wheel to
the right, both wheels alike):

* cornering stiffness K(gamma) = K (1 - p_Ky3 |gamma|), K = B C D of the paper's formula at the actual load;
* camber stiffness K_ygamma0 = F_z (p_Ky6 + p_Ky7 df_z) and vertical shift S_Vgamma = F_z (p_Vy3 + p_Vy4 df_z) gamma;
* horizontal shift S_Hy = (K_ygamma0 gamma - S_Vgamma) / K_ya with K_ya = -K(gamma) (the ISO sign), so that
  F_y = F_y,paper(alpha + S_Hy) + S_Vgamma has dF_y/dgamma = K_ygamma0 at zero slip;
* the camber moment as MF 6.1's residual torque, M_zr = F_z R (q_Dz8 + q_Dz9 df_z) gamma cos(arctan(q_Bz9 alpha_r)),
  alpha_r = alpha + S_Hy + S_Vgamma / K_ya; the pneumatic trail acts on the slip force alone (MF 6.1 applies the
  trail to the force at gamma = 0), so the camber thrust itself has no trail.

df_z = (F_z - F_z0) / F_z0 (MF 6.1's definition).  R is Table 1's radius, which also scales the paper's trail.  What
is left out, and why: the curvature's camber factor p_Ey4 (the paper's E_y is Hopping's pressure polynomial, which
has no place for it; curvature acts at third order in slip), the trail's camber shifts q_Hz3, q_Hz4, q_Bz5, q_Dz3 (no
linear effect: the trail multiplies the slip force, which is zero at zero slip), the pressure factor p_py5 (0 for
this tyre).  The camber force follows the camber without lag (no relaxation of its own).
"""

from __future__ import annotations

from dataclasses import dataclass

from reduced_model import tyre

# the paper's F_y = -D sin(C arctan(B a - E (B a - arctan(B a)))): the one copy in reduced_model.tyre
_force = tyre.mf_force


@dataclass(frozen=True)
class CamberTerms:
    """MF 6.1 camber coefficients (1/rad) and the scales they need."""

    p_ky3: float
    p_ky6: float
    p_ky7: float
    p_vy3: float
    p_vy4: float
    q_dz8: float
    q_dz9: float
    q_bz9: float
    Fz0: float
    R: float

    @classmethod
    def of(cls, dims, params) -> "CamberTerms":
        return cls(dims.camber_p_ky3, dims.camber_p_ky6, dims.camber_p_ky7, dims.camber_p_vy3, dims.camber_p_vy4,
                   dims.camber_q_dz8, dims.camber_q_dz9, dims.camber_q_bz9, params.Fz0, params.R)

    @property
    def neutral(self) -> bool:
        return not any((self.p_ky3, self.p_ky6, self.p_ky7, self.p_vy3, self.p_vy4, self.q_dz8, self.q_dz9))

    @property
    def coefficients(self) -> tuple[float, ...]:
        """The fields in order: the first argument of :func:`camber_terms`."""
        return (self.p_ky3, self.p_ky6, self.p_ky7, self.p_vy3, self.p_vy4, self.q_dz8, self.q_dz9, self.q_bz9,
                self.Fz0, self.R)


def camber_terms(coefficients: tuple, B: float, C: float, D: float, E: float, alpha: float, load: float,
                 gamma: float, plain: float, ops: tuple) -> tuple[float, float]:
    """(F_y with camber less F_y without, camber moment M_zr) at slip alpha, vertical load and camber gamma;
    ``coefficients`` are :attr:`CamberTerms.coefficients`, B, C, D, E the paper's factors at that load and ``plain``
    its F_y(alpha) (already computed by the tyre element: one Magic-Formula evaluation less per stage).

    Generic over the elementary functions ``ops`` (:mod:`mbs_shimmy.scalar_ops`): the tyre element calls it with
    :mod:`math`, the compiled solver stage (:mod:`mbs_shimmy.compiled_stage`) compiles it, the differentiable twin
    (:mod:`mbs_shimmy.twin`) traces it."""
    sin, _, atan, sqrt, _, choose = ops
    p_ky3, p_ky6, p_ky7, p_vy3, p_vy4, q_dz8, q_dz9, q_bz9, Fz0, R = coefficients
    dfz = (load - Fz0) / Fz0
    # MF 6.1's factor would reach zero at |gamma| = 1 / p_Ky3 (2.7 rad for this tyre, beyond the model's 1 rad
    # divergence limit); it is kept positive so that the cornering stiffness never changes sign
    reduction = 1.0 - p_ky3 * abs(gamma)
    reduction = choose(reduction < 0.05, 0.05, reduction)
    Br = B * reduction
    K = Br * C * D
    s_v = load * (p_vy3 + p_vy4 * dfz) * gamma
    s_h = (s_v - load * (p_ky6 + p_ky7 * dfz) * gamma) / K
    shifted = _force(Br, C, D, E, alpha + s_h, sin, atan) + s_v
    fade = q_bz9 * (alpha + s_h - s_v / K)         # cos(arctan(x)) = 1 / sqrt(1 + x^2)
    mzr = load * R * (q_dz8 + q_dz9 * dfz) * gamma / sqrt(1.0 + fade * fade)
    lifted = load <= 0.0
    return choose(lifted, 0.0, shifted - plain), choose(lifted, 0.0, mzr)
