"""The MF 6.1 longitudinal and combined-slip forces and aligning moment (reduced_model.tyre) against a second,
independent evaluation of the published equations (Pacejka, Tire and Vehicle Dynamics, 3rd ed., 2012, (4.E9)-(4.E18),
(4.E19)-(4.E30), (4.E31)-(4.E46), (4.E50)-(4.E67) and (4.E71)-(4.E78)) written out below from the raw numbers of
the MF 6.1 example file, in ISO signs (PKY1 negative), and their limits.

The second method shares no code with the models: it parses the .tir file with a few lines of its own, keeps MF
6.1's own names and signs, and applies the equations term by term.  It makes the same modelling decisions the models
state (docs/numerics.md, "Braking"): zero camber, no pure-slip shifts S_Hx, S_Vx, S_Hy, S_Vy, no E_y asymmetry PEY3,
and the paper's E_y and df_z = (F_z - F_z0)/F_z (at F_z = F_z0, the first load checked, it is MF 6.1's too); for
M_z no trail shift S_Ht, no cos'(alpha) and no residual moment M_zr (the paper's aligning moment is the trail's).
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest

from axles.axle import paper_axle
from axles.parameters import YANG2024
from axles.tyre_file import apply_tyre, read_tir
from reduced_model import tyre

EXAMPLE = Path(__file__).resolve().parents[1] / "data" / "mf61-205-60R15-example.tir"


def raw_coefficients(path: Path) -> dict[str, float]:
    """KEY = number lines of a .tir file, every section (the example's keys are unique across sections)."""
    out = {}
    for line in path.read_text().splitlines():
        m = re.match(r"^\s*([A-Z][A-Z0-9_]*)\s*=\s*([-+0-9.eE]+)", line)
        if m:
            out[m.group(1)] = float(m.group(2))
    return out


def published(c: dict, Fz: float, p: float, alpha: float, kappa: float, mirrored: bool = False):
    """(F_x, F_y) of MF 6.1 at zero camber, term by term, in ISO signs."""
    Fz0, pi0 = c["FNOMIN"], c["NOMPRES"]
    dfz = (Fz - Fz0) / Fz            # the paper's load increment (as the models; MF 6.1's at Fz = Fz0)
    dpi = (p - pi0) / pi0
    sgn = -1.0 if mirrored else 1.0
    # pure longitudinal (4.E9)-(4.E16), S_Hx = S_Vx = 0
    Cx = c["PCX1"]
    mux = (c["PDX1"] + c["PDX2"] * dfz) * (1 + c["PPX3"] * dpi + c["PPX4"] * dpi ** 2)
    Dx = mux * Fz
    Ex = (c["PEX1"] + c["PEX2"] * dfz + c["PEX3"] * dfz ** 2) * (1 - c["PEX4"] * np.sign(kappa))
    Kx = Fz * (c["PKX1"] + c["PKX2"] * dfz) * math.exp(c["PKX3"] * dfz) * (1 + c["PPX1"] * dpi + c["PPX2"] * dpi ** 2)
    Bx = Kx / (Cx * Dx)
    Fx0 = Dx * math.sin(Cx * math.atan(Bx * kappa - Ex * (Bx * kappa - math.atan(Bx * kappa))))
    # pure lateral (4.E19)-(4.E30) at zero camber, S_Hy = S_Vy = 0, E_y without PEY3
    Cy = c["PCY1"]
    muy = (c["PDY1"] + c["PDY2"] * dfz) * (1 + c["PPY3"] * dpi + c["PPY4"] * dpi ** 2)
    Dy = muy * Fz
    Ey = c["PEY1"] + c["PEY2"] * dfz
    Ky = (c["PKY1"] * Fz0 * (1 + c["PPY1"] * dpi)
          * math.sin(c["PKY4"] * math.atan(Fz / (c["PKY2"] * Fz0 * (1 + c["PPY2"] * dpi)))))
    By = Ky / (Cy * Dy)
    Fy0 = Dy * math.sin(Cy * math.atan(By * alpha - Ey * (By * alpha - math.atan(By * alpha))))
    # combined (4.E50)-(4.E57)
    Bxa = c["RBX1"] * math.cos(math.atan(c["RBX2"] * kappa))
    Cxa, Exa, SHxa = c["RCX1"], c["REX1"] + c["REX2"] * dfz, sgn * c["RHX1"]
    aS = alpha + SHxa
    Gxa = (math.cos(Cxa * math.atan(Bxa * aS - Exa * (Bxa * aS - math.atan(Bxa * aS))))
           / math.cos(Cxa * math.atan(Bxa * SHxa - Exa * (Bxa * SHxa - math.atan(Bxa * SHxa)))))
    # (4.E58)-(4.E67)
    Byk = c["RBY1"] * math.cos(math.atan(c["RBY2"] * (alpha - sgn * c["RBY3"])))
    Cyk, Eyk, SHyk = c["RCY1"], c["REY1"] + c["REY2"] * dfz, c["RHY1"] + c["RHY2"] * dfz
    kS = kappa + SHyk
    Gyk = (math.cos(Cyk * math.atan(Byk * kS - Eyk * (Byk * kS - math.atan(Byk * kS))))
           / math.cos(Cyk * math.atan(Byk * SHyk - Eyk * (Byk * SHyk - math.atan(Byk * SHyk)))))
    DVyk = muy * Fz * sgn * (c["RVY1"] + c["RVY2"] * dfz) * math.cos(math.atan(c["RVY4"] * alpha))
    SVyk = DVyk * math.sin(c["RVY5"] * math.atan(c["RVY6"] * kappa))
    return Gxa * Fx0, Gyk * Fy0 + SVyk, Fx0, Fy0


def published_moment(c: dict, Fz: float, p: float, alpha: float, kappa: float, mirrored: bool = False) -> float:
    """M_z of MF 6.1's combined slip (4.E71)-(4.E78) at zero camber, term by term, with the paper's decisions: the
    trail (4.E31)-(4.E46) without its shift S_Ht and without cos'(alpha), no residual moment M_zr (the paper's
    aligning moment is the trail's), its trail not mirrored (as free rolling); SSZ1 mirrored."""
    Fz0, pi0, R0 = c["FNOMIN"], c["NOMPRES"], c["UNLOADED_RADIUS"]
    dfz = (Fz - Fz0) / Fz
    dpi = (p - pi0) / pi0
    Fx, Fy, Fx0, Fy0 = published(c, Fz, p, alpha, kappa, mirrored)
    Kx = Fz * (c["PKX1"] + c["PKX2"] * dfz) * math.exp(c["PKX3"] * dfz) * (1 + c["PPX1"] * dpi + c["PPX2"] * dpi ** 2)
    Ky = (c["PKY1"] * Fz0 * (1 + c["PPY1"] * dpi)
          * math.sin(c["PKY4"] * math.atan(Fz / (c["PKY2"] * Fz0 * (1 + c["PPY2"] * dpi)))))
    alpha_t = math.sqrt(alpha ** 2 + (Kx / Ky) ** 2 * kappa ** 2) * (1.0 if alpha >= 0.0 else -1.0)   # (4.E77)
    Bt = c["QBZ1"] + c["QBZ2"] * dfz + c["QBZ3"] * dfz ** 2
    Ct = c["QCZ1"]
    Dt = Fz * (R0 / Fz0) * (c["QDZ1"] + c["QDZ2"] * dfz) * (1 - c["PPZ1"] * dpi)
    Et = (c["QEZ1"] + c["QEZ2"] * dfz + c["QEZ3"] * dfz ** 2) * (1 + c["QEZ4"] * 2 / math.pi * math.atan(Bt * Ct * alpha_t))
    t = Dt * math.cos(Ct * math.atan(Bt * alpha_t - Et * (Bt * alpha_t - math.atan(Bt * alpha_t))))   # (4.E73)
    muy = (c["PDY1"] + c["PDY2"] * dfz) * (1 + c["PPY3"] * dpi + c["PPY4"] * dpi ** 2)
    SVyk = (muy * Fz * (-1.0 if mirrored else 1.0) * (c["RVY1"] + c["RVY2"] * dfz) * math.cos(math.atan(c["RVY4"] * alpha))
            * math.sin(c["RVY5"] * math.atan(c["RVY6"] * kappa)))                     # S_Vyk (4.E66)-(4.E67)
    s = R0 * ((-1.0 if mirrored else 1.0) * c["SSZ1"] + c["SSZ2"] * Fy / Fz0)        # (4.E76), zero camber
    return -t * (Fy - SVyk) + s * Fx             # (4.E71), (4.E72) with F'_y = F_y - S_Vyk (4.E74)


def model_forces(params, p, alpha, kappa, mirrored=False):
    cs = tyre.combined_slip(params, p, kappa, mirrored)
    fy0 = float(tyre.lateral_force(params, alpha, p))
    fx, fy = cs.forces(fy0, alpha)
    return float(fx), float(fy), cs.Fx0, fy0


def model_moment(params, p, alpha, kappa, mirrored=False) -> tuple[float, float, float]:
    """(F_x, F_y, M_z) of the models' one formula (tyre.combined_forces) with the trail (4.2)-(4.8)."""
    cs = tyre.combined_slip(params, p, kappa, mirrored)
    fy0 = tyre.lateral_force(params, np.array([alpha]), p)
    fx, fy, mz = cs.moment_and_forces(fy0, np.array([alpha]), lambda a: tyre.pneumatic_trail(params, a, p))
    return float(fx[0]), float(fy[0]), float(mz[0])


@pytest.fixture(scope="module")
def example():
    return raw_coefficients(EXAMPLE), apply_tyre(paper_axle(), read_tir(str(EXAMPLE))).params


@pytest.mark.parametrize("Fz", [4000.0, 5200.0])
@pytest.mark.parametrize("mirrored", [False, True])
def test_forces_match_the_published_equations(example, Fz, mirrored):
    raw, params = example
    params = params.replace(Fz=Fz)
    worst = 0.0
    for p in (1.5e5, 2e5, 2.6e5):
        for alpha in (-0.2, -0.03, 0.0, 0.004, 0.05, 0.3):
            for kappa in (-0.6, -0.1, -0.02, -1e-3, 0.0, 0.03, 0.15, 0.5):      # > 0 driving
                want = published(raw, Fz, p, alpha, kappa, mirrored)
                got = model_forces(params, p, alpha, kappa, mirrored)
                for w, g in zip(want, got):
                    worst = max(worst, abs(w - g) / max(1.0, abs(w)))
    assert worst < 1e-12


@pytest.mark.parametrize("Fz", [4000.0, 5200.0])
@pytest.mark.parametrize("mirrored", [False, True])
def test_aligning_moment_matches_the_published_equations(example, Fz, mirrored):
    """The combined aligning moment (alpha_t,eq, F'_y = F_y - S_Vyk, s F_x with the file's SSZ1, SSZ2) against the
    term-by-term evaluation, braking and driving, both wheels, two loads, three pressures."""
    raw, params = example
    params = params.replace(Fz=Fz)
    assert params.s_sz1 == raw["SSZ1"] and params.s_sz2 == raw["SSZ2"]
    worst = 0.0
    for p in (1.5e5, 2e5, 2.6e5):
        for alpha in (-0.2, -0.03, -1e-4, 0.004, 0.05, 0.3):
            for kappa in (-0.6, -0.1, -0.02, -1e-3, 0.03, 0.15):
                want = published_moment(raw, Fz, p, alpha, kappa, mirrored)
                got = model_moment(params, p, alpha, kappa, mirrored)[2]
                worst = max(worst, abs(want - got) / max(1.0, abs(want)))
    assert worst < 1e-12


def test_aligning_moment_without_longitudinal_slip_is_the_trail_moment_exactly(example):
    """kappa = 0: alpha_t,eq = alpha and M_z = -t(alpha) F_y0, bit for bit (the paper's aligning moment)."""
    _, params = example
    for alpha in np.linspace(-0.3, 0.3, 13):
        fx, fy, mz = model_moment(params, 2e5, float(alpha), 0.0)
        a = np.array([alpha])
        fy0 = tyre.lateral_force(params, a, 2e5)
        assert fx == 0.0 and fy == fy0[0] and mz == (-tyre.pneumatic_trail(params, a, 2e5) * fy0)[0]
        cs = tyre.combined_slip(params, 2e5, 0.0)
        assert cs.trail_slip(a)[0] == alpha


def test_no_longitudinal_slip_is_pure_slip_exactly(example):
    """kappa = 0: F_y is F_y0 bit for bit (G_yk = 1, S_Vyk = 0) and F_x = 0."""
    _, params = example
    for alpha in np.linspace(-0.3, 0.3, 13):
        fx, fy, _, fy0 = model_forces(params, 2e5, float(alpha), 0.0)
        assert fy == fy0 and fx == 0.0


def test_straight_running_gives_the_pure_longitudinal_force(example):
    """alpha = 0: G_xa = 1 exactly, F_x = F_x0(kappa)."""
    _, params = example
    for kappa in (-0.5, -0.05, -0.01):
        fx, _, fx0, _ = model_forces(params, 2e5, 0.0, kappa)
        assert fx == fx0


def test_without_r_coefficients_the_model_is_pure_slip():
    """A tyre without the R coefficients (all 0, as a file without them is read): F_x = F_x0, F_y = F_y0."""
    names = [n for n in YANG2024.names() if n.startswith("r_")]
    params = YANG2024.replace(**{n: 0.0 for n in names})
    for alpha, kappa in ((0.05, -0.1), (-0.1, -0.3)):
        fx, fy, fx0, fy0 = model_forces(params, 2.5e5, alpha, kappa)
        assert fx == fx0 and fy == fy0


def test_combined_slip_reduces_both_forces(example):
    """The friction ellipse's qualitative content: braking lowers the cornering force and the cornering stiffness,
    side slip lowers the brake force."""
    _, params = example
    fx_a, fy_a, fx0, fy0 = model_forces(params, 2e5, 0.05, -0.1)
    assert abs(fy_a - tyre.combined_slip(params, 2e5, -0.1).weights(0.05)[2]) < abs(fy0)
    assert abs(fx_a) < abs(fx0)
    h = 1e-7
    k_free = (model_forces(params, 2e5, h, 0.0)[1] - model_forces(params, 2e5, -h, 0.0)[1]) / (2 * h)
    k_brake = (model_forces(params, 2e5, h, -0.1)[1] - model_forces(params, 2e5, -h, -0.1)[1]) / (2 * h)
    assert abs(k_brake) < 0.8 * abs(k_free)


def test_brake_force_inverts_the_longitudinal_force():
    for p in (1.5e5, 2.5e5):
        s = tyre.brake_slip_for_force(YANG2024, p, 3000.0)
        assert abs(tyre.longitudinal_formula(YANG2024, p).force(-s) + 3000.0) < 1e-9
        _, peak = tyre.peak_brake_slip(YANG2024, p)
        with pytest.raises(Exception, match="beyond the tyre's grip"):
            tyre.brake_slip_for_force(YANG2024, p, peak * 1.01)


def test_drive_force_inverts_the_longitudinal_force_with_kappa_positive():
    """A negative brake force drives: the slip found is negative (ISO kappa > 0) and F_x0 is the forward force.  The
    drive peak is the Magic Formula's peak D_x (C_x > 1), reached at a slip set by E_x's asymmetry (1 - p_ex4
    sgn kappa); checked on a fine grid too."""
    for p in (1.5e5, 2.5e5):
        lf = tyre.longitudinal_formula(YANG2024, p)
        s = tyre.brake_slip_for_force(YANG2024, p, -2500.0)
        assert s < 0.0 and abs(lf.force(-s) - 2500.0) < 1e-9
        s_peak, f_peak = tyre.peak_brake_slip(YANG2024, p, driving=True)
        grid = np.linspace(1e-4, 1.0, 20001)
        forces = [lf.force(k) for k in grid]
        # the grid's best lies below the peak by O(step^2): 2.5e-9 relative at this step
        assert max(forces) <= -f_peak * (1 + 1e-14) and max(forces) > -f_peak * (1 - 1e-7) and s_peak < 0.0
        assert -f_peak == pytest.approx(lf.D, rel=1e-12)
        with pytest.raises(Exception, match="drive force = .* beyond the tyre's grip"):
            tyre.brake_slip_for_force(YANG2024, p, f_peak * 1.01)


@pytest.mark.parametrize("mirrored", [False, True])
def test_relaxation_length_follows_the_braking_with_rl(mirrored):
    """With ``rl`` the relaxation length is the paper's (4.9), K_ya / C_y, with the braking tyre's cornering
    stiffness: read off the reduced model's slip equation (alpha' = -V alpha / sigma at rest, theta = 0) against
    the slope of the combined F_y at alpha = 0 by central differences over C_y = c_y0 (1 + p_cy1 dp_i); without
    ``rl`` (the section 3 model's sigma0) and free rolling it does not change."""
    from axles.braking import Braking
    from axles.pressures import TyrePressures
    from reduced_model.model import Effects, ShimmyModel
    p = 2.0e5
    braking = Braking.of_slip(0.08, 0.08)
    side = 0 if mirrored else 1                      # the right wheel (index 0) is the mirrored tyre
    speed, alpha = 20.0, 1e-3

    def sigma(effects, b):
        x = np.zeros(8)
        x[6 + side] = alpha
        return -speed * alpha / ShimmyModel(effects=Effects.parse(effects)).rhs(x, speed, TyrePressures.uniform(p),
                                                                                b)[6 + side]
    cs = tyre.combined_slip(YANG2024, p, -0.08, mirrored)
    h = 1e-6
    slope = -(cs.forces(float(tyre.lateral_force(YANG2024, h, p)), h)[1]
              - cs.forces(float(tyre.lateral_force(YANG2024, -h, p)), -h)[1]) / (2 * h)
    dp = tyre.pressure_increment(YANG2024, p)
    want = slope / (YANG2024.c_y0 * (1.0 + YANG2024.p_cy1_rl * dp))
    assert sigma("rl", braking) == pytest.approx(want, rel=1e-8)
    assert sigma("rl", braking) < 0.9 * sigma("rl", Braking())            # braking shortens it
    assert sigma("", braking) == sigma("", Braking()) == YANG2024.sigma0
