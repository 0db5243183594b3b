"""Parameter sets of the shimmy model, one frozen typed object with a unit and a source per entry.

The only set so far is :data:`YANG2024`, Table 1 of Yang, Knowles & Mavros, "Bifurcation analysis of the
effect of tyre inflation pressure on wheel shimmy with multiple tyre properties considered" (The ANZIAM
Journal, 2025).  Every entry is stored in SI units (the paper prints kN, kN m/rad and bar).  Garbled symbols of
the OCR'd Table 1 are read as ``docs/paper-notes.md`` explains; the paper uses the name ``p_cy1`` twice, for the
lateral shape factor C_y (1.29) and for the pressure coefficient of the relaxation length (0.5, eq. 4.9); the
second is called ``p_cy1_rl`` here.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from bifurcation.problem import ProblemError
from bifurcation.messages import Message, Quantity

_T1 = "Yang et al., Table 1"
_T1_LI = "Yang et al., Table 1 (from Li et al. [16])"
_T1_PAC = "Yang et al., Table 1 (from Pacejka [19])"
_T1_HOP = "Yang et al., Table 1 (from Hopping [12])"
_TEXT = "Yang et al., section 2 text"
_PAC61 = "Pacejka (2012), MF 6.1 example tyre 205/60R15 (not in Table 1)"


def _p(value: float, unit: str, source: str, description: str, printed: str = "", *,
       range: tuple[float, float]) -> Any:
    """A Table 1 entry; ``range`` (SI, inclusive) is where the model stays physically meaningful."""
    return field(default=value, metadata={"unit": unit, "source": source, "description": description,
                                          "printed": printed, "range": range})


class ParameterError(ProblemError):
    """A parameter name or value that makes the model meaningless (a :class:`ProblemError` of the toolkit, so
    that its algorithms treat it as any problem's refusal)."""


def check_ranges(entries: Any, what: str) -> None:
    """Every field of a frozen parameter dataclass finite and inside its ``range`` metadata (SI, inclusive)."""
    for f_ in dataclasses.fields(entries):
        value = getattr(entries, f_.name)
        if not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ParameterError(f"{what} {f_.name} must be a finite number, got {value!r}")
        lo, hi = f_.metadata["range"]
        if not lo <= value <= hi:
            raise ParameterError(Message.of(f"{what} ", Quantity(f_.name, value, 6, f_.metadata["unit"]),
                                            f" is outside its physical range [{lo:g}, {hi:g}] {f_.metadata['unit']}"))


@dataclass(frozen=True)
class ShimmyParameters:
    """Parameters of the truck front-axle shimmy model, SI units (see each field's metadata)."""

    # --- steering and suspension (Li et al. [16]) -----------------------------------------------------
    I1: float = _p(6.0, "kg m^2", _T1_LI, "inertia of one front wheel about its kingpin", range=(0.1, 1000.0))
    I2: float = _p(4.85, "kg m^2", _T1_LI, "inertia of one front wheel about its spin (y) axis", range=(0.1, 1000.0))
    I3: float = _p(160.0, "kg m^2", _T1_LI, "inertia of the front axle about the x-axis (tramp)", range=(1.0, 1e5))
    k1: float = _p(35.5e3, "N m/rad", _T1_LI, "tie-rod angular stiffness about the kingpins", range=(0.0, 1e8))
    k2: float = _p(17.0e3, "N m/rad", _T1_LI, "drag-link angular stiffness about the left kingpin", range=(0.0, 1e8))
    k3: float = _p(32.0e3, "N m/rad", _T1_LI, "suspension roll stiffness about the x-axis", range=(0.0, 1e8))
    k4: float = _p(80.0e3, "N/m", _T1_LI, "tyre lateral stiffness", range=(100.0, 1e8))
    k5_0: float = _p(400.0e3, "N/m", _T1_LI, "tyre vertical stiffness at nominal pressure", "k_{5_0}",
                     range=(1000.0, 1e8))
    c1: float = _p(10.0, "N m s/rad", _T1_LI, "tie-rod angular damping about the kingpins", range=(0.0, 1e6))
    c2: float = _p(100.0, "N m s/rad", _T1_LI, "drag-link angular damping about the left kingpin", range=(0.0, 1e6))
    c3: float = _p(1050.0, "N m s/rad", _T1_LI, "suspension roll damping about the x-axis", range=(0.0, 1e6))
    c4: float = _p(44.0, "N m s/rad", _T1_LI, "equivalent wheel damping about the kingpin", range=(0.0, 1e6))
    R: float = _p(0.4, "m", _T1_LI, "rolling radius", range=(0.1, 1.5))
    L: float = _p(1.608, "m", _T1_LI, "wheel-centre distance", range=(0.5, 3.0))
    f: float = _p(0.015, "-", _T1_LI, "rolling-resistance coefficient", range=(0.0, 0.1))
    l: float = _p(0.07, "m", _T1_LI, "wheel offset (kingpin to wheel centre plane)", range=(0.0, 0.5))
    gamma: float = _p(0.04, "rad", _T1_LI, "caster angle", "γ", range=(-math.radians(20.0), math.radians(20.0)))
    a0: float = _p(0.2, "m", _T1_LI, "half contact length at nominal pressure", range=(0.005, 1.0))
    sigma0: float = _p(0.65, "m", _T1_LI, "relaxation length (section 3 model)", "σ_0", range=(0.001, 5.0))
    t0: float = _p(0.07, "m", _T1_LI, "pneumatic trail (section 3 model)", range=(0.001, 0.5))
    # --- nominal operating point -------------------------------------------------------------------------
    Fz0: float = _p(6000.0, "N", _TEXT, "nominal vertical wheel load", "F_z0", range=(100.0, 1e5))
    Fz: float = _p(6000.0, "N", _TEXT, "actual vertical wheel load (the paper keeps Fz = Fz0)", "F_z",
                   range=(100.0, 1e5))
    pi0: float = _p(2.5e5, "Pa", _TEXT, "nominal inflation pressure (2.5 bar)", "p_i0", range=(1e4, 2e6))
    # --- Magic-Formula lateral force, eqs. (2.6)-(2.9) -------------------------------------------------
    p_cy1: float = _p(1.29, "-", _T1_PAC, "shape factor C_y", "p_{cv1}", range=(0.1, 3.0))
    p_dy1: float = _p(0.875, "-", _T1_PAC, "peak friction mu_y at nominal load and pressure", range=(0.1, 3.0))
    p_dy2: float = _p(-0.06452, "-", _T1_PAC, "variation of mu_y with load", "p_{+2}", range=(-2.0, 2.0))
    p_py3: float = _p(-0.16666, "-", _T1_PAC, "variation of mu_y with pressure", "p_my2", range=(-2.0, 2.0))
    p_py4: float = _p(0.2811, "-", _T1_PAC, "variation of mu_y with pressure squared", range=(-2.0, 2.0))
    p_ky1: float = _p(12.0628, "-", _T1_PAC, "cornering stiffness K_ya / Fz0 scale", range=(0.1, 100.0))
    p_ky2: float = _p(1.715, "-", _T1_PAC, "load at which K_ya peaks, / Fz0", range=(0.1, 10.0))
    p_ky3: float = _p(2.0005, "-", _T1_PAC, "curvature of K_ya against load", range=(-10.0, 10.0))
    p_py1: float = _p(-0.6255, "-", _T1_PAC, "variation of K_ya peak with pressure", "p_nv1", range=(-5.0, 5.0))
    p_py2: float = _p(-0.06523, "-", _T1_PAC, "variation of K_ya peak load with pressure", "p_pv2", range=(-5.0, 5.0))
    p_ey1: float = _p(-0.801, "-", _T1_HOP, "curvature factor E_y at nominal load and pressure", range=(-10.0, 1.0))
    p_ey2: float = _p(0.54602, "-", _T1_HOP, "variation of E_y with load", range=(-10.0, 10.0))
    p_ey3: float = _p(-0.91981, "-", _T1_HOP, "variation of E_y with load squared", range=(-10.0, 10.0))
    p_epy1: float = _p(0.58897, "-", _T1_HOP, "variation of E_y with pressure", range=(-10.0, 10.0))
    p_epy2: float = _p(0.08363, "-", _T1_HOP, "variation of E_y with pressure squared", range=(-10.0, 10.0))
    p_epey1: float = _p(0.40612, "-", _T1_HOP, "combined load-pressure variation of E_y", range=(-10.0, 10.0))
    # --- pneumatic trail, eqs. (4.2)-(4.8) -----------------------------------------------------------
    q_cz1: float = _p(1.0, "-", _T1_PAC, "shape factor C_t", range=(0.1, 3.0))
    q_dz1: float = _p(0.175, "-", _T1_PAC, "peak trail D_t / R at nominal load and pressure", range=(0.001, 1.0))
    q_dz2: float = _p(-0.00565, "-", _T1_PAC, "variation of D_t with load", range=(-1.0, 1.0))
    p_pz1: float = _p(0.4408, "-", _T1_PAC, "variation of D_t with pressure", range=(-5.0, 5.0))
    q_bz1: float = _p(12.035, "-", _T1_PAC, "stiffness factor B_t at nominal load", range=(0.1, 100.0))
    q_bz2: float = _p(-1.33, "-", _T1_PAC, "variation of B_t with load", range=(-50.0, 50.0))
    q_bz3: float = _p(0.0, "-", _T1_PAC, "variation of B_t with load squared", range=(-50.0, 50.0))
    q_ez1: float = _p(-1.7924, "-", _T1_PAC, "curvature factor E_t at nominal load", range=(-20.0, 1.0))
    q_ez2: float = _p(0.8975, "-", _T1_PAC, "variation of E_t with load", range=(-20.0, 20.0))
    q_ez3: float = _p(0.0, "-", _T1_PAC, "variation of E_t with load squared", range=(-20.0, 20.0))
    q_ez4: float = _p(0.2895, "-", _T1_PAC, "asymmetry of E_t in slip angle", range=(-1.0, 1.0))
    # --- relaxation length and vertical stiffness, eqs. (4.9)-(4.10) ---------------------------------
    c_y0: float = _p(96.92e3, "N/m", _T1, "tyre lateral stiffness at nominal load and pressure", "C_{y0}",
                     range=(1000.0, 1e7))
    p_cy1_rl: float = _p(0.5, "-", _T1_PAC, "variation of relaxation length with pressure (eq. 4.9)",
                         "p_cy1 (second row)", range=(-5.0, 5.0))
    p_fz1: float = _p(0.7, "-", _T1_PAC, "variation of vertical stiffness with pressure (eq. 4.10)",
                      range=(-5.0, 5.0))

    # --- longitudinal force and combined slip (MF 6.1), only under braking --------------------------------
    # Not in Table 1: the paper's tyre has no longitudinal or combined-slip coefficients.  Its lateral ones come
    # from Pacejka's MF 6.1 example tyre (205/60R15); these are that tyre's, from the same example set
    # (tests/data/mf61-205-60R15-example.tir).  Pure longitudinal force: Pacejka (2012) eqs. (4.E9)-(4.E18);
    # combined slip: (4.E50)-(4.E67).  All r_ coefficients 0 is the pure-slip model (G_xa = G_yk = 1, S_Vyk = 0).
    p_cx1: float = _p(1.579, "-", _PAC61, "shape factor C_x", range=(0.1, 3.0))
    p_dx1: float = _p(1.0422, "-", _PAC61, "peak friction mu_x at nominal load", range=(0.1, 3.0))
    p_dx2: float = _p(-0.08285, "-", _PAC61, "variation of mu_x with load", range=(-2.0, 2.0))
    p_ex1: float = _p(0.11113, "-", _PAC61, "curvature factor E_x at nominal load", range=(-10.0, 1.0))
    p_ex2: float = _p(0.3143, "-", _PAC61, "variation of E_x with load", range=(-10.0, 10.0))
    p_ex3: float = _p(0.0, "-", _PAC61, "variation of E_x with load squared", range=(-10.0, 10.0))
    p_ex4: float = _p(0.001719, "-", _PAC61, "E_x's asymmetry between driving and braking", range=(-1.0, 1.0))
    p_kx1: float = _p(21.687, "-", _PAC61, "longitudinal slip stiffness K_xk / Fz at nominal load",
                      range=(0.1, 200.0))
    p_kx2: float = _p(13.728, "-", _PAC61, "variation of K_xk with load", range=(-200.0, 200.0))
    p_kx3: float = _p(-0.4098, "-", _PAC61, "exponential variation of K_xk with load", range=(-10.0, 10.0))
    p_px1: float = _p(-0.3485, "-", _PAC61, "variation of K_xk with pressure", range=(-5.0, 5.0))
    p_px2: float = _p(0.37824, "-", _PAC61, "variation of K_xk with pressure squared", range=(-5.0, 5.0))
    p_px3: float = _p(-0.09603, "-", _PAC61, "variation of mu_x with pressure", range=(-5.0, 5.0))
    p_px4: float = _p(0.06518, "-", _PAC61, "variation of mu_x with pressure squared", range=(-5.0, 5.0))
    r_bx1: float = _p(13.046, "-", _PAC61, "slope factor of G_xa (F_x's reduction by slip angle)",
                      range=(0.0, 100.0))
    r_bx2: float = _p(9.718, "-", _PAC61, "variation of G_xa's slope with longitudinal slip", range=(-100.0, 100.0))
    r_cx1: float = _p(0.9995, "-", _PAC61, "shape factor of G_xa", range=(0.0, 3.0))
    r_ex1: float = _p(-0.4403, "-", _PAC61, "curvature factor of G_xa", range=(-10.0, 1.0))
    r_ex2: float = _p(-0.4663, "-", _PAC61, "variation of G_xa's curvature with load", range=(-10.0, 10.0))
    r_hx1: float = _p(-9.968e-5, "-", _PAC61, "slip-angle shift of G_xa", range=(-0.1, 0.1))
    r_by1: float = _p(10.622, "-", _PAC61, "slope factor of G_yk (F_y's reduction by longitudinal slip)",
                      range=(0.0, 100.0))
    r_by2: float = _p(7.82, "-", _PAC61, "variation of G_yk's slope with slip angle", range=(-100.0, 100.0))
    r_by3: float = _p(0.002037, "-", _PAC61, "slip-angle shift of G_yk's slope", range=(-0.5, 0.5))
    r_cy1: float = _p(1.0587, "-", _PAC61, "shape factor of G_yk", range=(0.0, 3.0))
    r_ey1: float = _p(0.3148, "-", _PAC61, "curvature factor of G_yk", range=(-10.0, 1.0))
    r_ey2: float = _p(0.004867, "-", _PAC61, "variation of G_yk's curvature with load", range=(-10.0, 10.0))
    r_hy1: float = _p(0.009472, "-", _PAC61, "longitudinal-slip shift of G_yk", range=(-0.1, 0.1))
    r_hy2: float = _p(0.009754, "-", _PAC61, "variation of G_yk's shift with load", range=(-1.0, 1.0))
    r_vy1: float = _p(0.05187, "-", _PAC61, "slip-induced side force S_Vyk / (mu_y Fz)", range=(-1.0, 1.0))
    r_vy2: float = _p(4.853e-4, "-", _PAC61, "variation of S_Vyk with load", range=(-1.0, 1.0))
    r_vy4: float = _p(94.63, "-", _PAC61, "variation of S_Vyk with slip angle", range=(-1000.0, 1000.0))
    r_vy5: float = _p(1.8914, "-", _PAC61, "shape of S_Vyk against longitudinal slip", range=(-10.0, 10.0))
    r_vy6: float = _p(23.8, "-", _PAC61, "slope of S_Vyk against longitudinal slip", range=(-1000.0, 1000.0))
    s_sz1: float = _p(0.00918, "-", _PAC61, "lateral offset s / R of F_x's line of action in M_z (combined slip)",
                      range=(-1.0, 1.0))
    s_sz2: float = _p(0.03869, "-", _PAC61, "variation of s / R with F_y / F_z0", range=(-10.0, 10.0))

    def __post_init__(self) -> None:
        check_ranges(self, "parameter")

    # --- access by name ------------------------------------------------------------------------------
    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f_.name for f_ in dataclasses.fields(cls))

    @classmethod
    def _field(cls, name: str) -> dataclasses.Field:
        for f_ in dataclasses.fields(cls):
            if f_.name == name:
                return f_
        raise ParameterError(f"unknown parameter '{name}' (known: {', '.join(cls.names())})")

    @classmethod
    def unit(cls, name: str) -> str:
        return cls._field(name).metadata["unit"]

    @classmethod
    def source(cls, name: str) -> str:
        return cls._field(name).metadata["source"]

    @classmethod
    def physical_range(cls, name: str) -> tuple[float, float]:
        """Inclusive physical range of an entry (SI)."""
        return cls._field(name).metadata["range"]

    @classmethod
    def description(cls, name: str) -> str:
        return cls._field(name).metadata["description"]

    def replace(self, **overrides: float) -> "ShimmyParameters":
        """A copy with the named entries replaced (SI units); unknown names raise :class:`ParameterError`."""
        for name in overrides:
            self._field(name)
        return dataclasses.replace(self, **{k: float(v) for k, v in overrides.items()})

    def table(self) -> list[dict[str, Any]]:
        """One row per entry: name, value (SI), unit, description, source, symbol as printed if garbled."""
        rows = []
        for f_ in dataclasses.fields(self):
            rows.append({"name": f_.name, "value": getattr(self, f_.name), "unit": f_.metadata["unit"],
                         "description": f_.metadata["description"], "source": f_.metadata["source"],
                         "printed_as": f_.metadata["printed"], "range": f_.metadata["range"]})
        return rows


YANG2024 = ShimmyParameters()
"""Table 1 of Yang, Knowles & Mavros (the reference paper), SI units."""
