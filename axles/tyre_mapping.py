"""The one table between a Magic Formula 6.1/6.2 tyre property file (.tir) and an axle's tyre entries.

Each row names the file's section and key, the axle entry it sets (:mod:`axles.parameters` Table 1, or the camber
entries of :mod:`axles.dimensions`), the paper's symbol, the quantity that says how the file's [UNITS] convert it,
the sign (MF 6.1 writes PKY1 negative in ISO signs, the paper writes F_y = -D sin(...) with a positive K_ya), the
scaling factors of [SCALING_COEFFICIENTS] that multiply it, what is taken when the file has no value, and where the
models use it.  The reader and writer (:mod:`axles.tyre_file`), ``docs/axle-files.md`` (generated) and the tests all
read this table.

The paper's equations against MF 6.1 (Pacejka, Tire and Vehicle Dynamics, 3rd ed., 2012, section 4.3.2, the
pressure terms of Besselink, Schmeitz & Pacejka 2010): the lateral force (2.6)-(2.8), the trail (4.2)-(4.8), the
vertical stiffness (4.10) and the relaxation length (4.9) (sigma = K_ya / C_y, C_y = LATERAL_STIFFNESS (1 + PCFY3
dp_i)) are MF 6.1's at zero camber and without the shifts S_Hy, S_Vy, with one difference: the paper's load increment
is df_z = (F_z - F_z0) / F_z, MF 6.1's (F_z - F_z0) / F_z0; they agree at F_z = F_z0, where the paper keeps the load.
Beyond MF 6.1 the paper adds Hopping's pressure and load-squared terms of E_y, Guo's half contact length (4.1) and the
section 3 model's constants a0, t0, sigma0: a file written by ``shimmy params --write-tir`` carries them in a section
of its own, [SHIMMY_EXTENSIONS], that other MF tools ignore.
"""

from __future__ import annotations

from dataclasses import dataclass

# What the axle takes when the file has no value for a key.
REQUIRED = "required"   # the file is refused
ZERO = "zero"           # MF 6.1's meaning of an absent term: no such variation (0)
AXLE = "axle"           # kept from the axle the tyre is put on (the paper's, or the axle file's)

MISSING_MEANING = {REQUIRED: "the file is refused (exit 2)",
                   ZERO: "0: the term is absent, as in MF 6.1",
                   AXLE: "kept from the axle the tyre is put on"}

BOTH = "both models"
CAMBER = "multibody model with the assumption no_camber_force off"

# The section of the paper's extensions in a written file.
EXTENSIONS = "SHIMMY_EXTENSIONS"


@dataclass(frozen=True)
class TyreKey:
    """One coefficient of a .tir file and the axle entry it is."""

    section: str                  # without brackets
    key: str
    entry: str                    # axle entry name (axles.axle.entries())
    symbol: str                   # the paper's symbol, or MF 6.1's where the paper has none
    quantity: str | None          # "length", "force", "stiffness", "pressure" or None (dimensionless, per rad)
    missing: str                  # REQUIRED, ZERO or AXLE
    enters: str                   # where the models use it
    sign: float = 1.0             # entry = sign * file value * scales
    scales: tuple[str, ...] = ()  # [SCALING_COEFFICIENTS] factors that multiply it (folded in when read)
    also_in: tuple[str, ...] = ()  # other sections some producers put the key in
    note: str = ""                # the decision this row needed, if any


_RL = "both models; the relaxation length (4.9) with --effects rl"
_PT = "both models; the trail (4.2)-(4.8) with --effects pt"
_LONG = "LONGITUDINAL_COEFFICIENTS"
_BRAKE = "both models, under braking (--brake-slip, --brake-force)"
_LONG_NOTE = ("not in the paper's Table 1: the paper's axle takes them from Pacejka's MF 6.1 example tyre (whose "
              "lateral coefficients the paper took); no shifts S_Hx, S_Vx (PHX1, PHX2, PVX1, PVX2 not used, as the paper's F_y "
              "has no S_Hy, S_Vy); zero camber (PDX3 not used); a file without them keeps the axle's")
_PURE_NOTE = ("the combined-slip R coefficients: a file without them gives 0, the pure-slip model (G_xa = G_yk = 1, "
              "S_Vyk = 0); the camber terms RBX3, RBY4, RVY3 are not used (zero camber)")
_MIRROR_NOTE = ("the file's tyre is the left wheel's (TYRESIDE is not read); the right wheel's is the mirror image, "
                "with RHX1, RBY3, RVY1 and RVY2 of opposite sign")

_SSZ_NOTE = ("the combined-slip aligning moment's lever s F_x, s = R (SSZ1 + SSZ2 F_y / F_z0) (MF 6.1 (4.E76); R0 = R); "
             "SSZ3, SSZ4 are camber terms, not used; the right wheel's SSZ1 is of opposite sign (mirror image)")

TYRE_KEYS: tuple[TyreKey, ...] = (
    TyreKey("DIMENSION", "UNLOADED_RADIUS", "R", "R", "length", REQUIRED, BOTH,
            note="the paper has one radius, for the wheel (eqs. 2.1-2.3) and the trail's scale (4.5); MF 6.1 scales "
                 "the trail by the unloaded radius R0: R = R0 (the loaded radius is a few per cent less)"),
    TyreKey("OPERATING_CONDITIONS", "NOMPRES", "pi0", "p_i0", "pressure", REQUIRED, BOTH,
            note="INFLPRES is not used: the pressure is the command's --pressure"),
    TyreKey("VERTICAL", "FNOMIN", "Fz0", "F_z0", "force", REQUIRED, BOTH, scales=("LFZO",),
            note="F_z, the wheel load, stays the axle's; the paper's df_z = (F_z - F_z0)/F_z equals MF 6.1's "
                 "(F_z - F_z0)/F_z0 only at F_z = F_z0"),
    TyreKey("VERTICAL", "VERTICAL_STIFFNESS", "k5_0", "k5_0", "stiffness", REQUIRED, BOTH),
    TyreKey("VERTICAL", "PFZ1", "p_fz1", "p_fz1", None, ZERO, "both models; k5 (4.10) with --effects vs",
            also_in=("LOADED_RADIUS_COEFFICIENTS",)),
    TyreKey("STRUCTURAL", "LATERAL_STIFFNESS", "c_y0", "c_y0", "stiffness", AXLE, _RL,
            note="MF 6.1's C_y of sigma = K_ya / C_y; k4, the tyre's lateral stiffness in the tramp equation "
                 "(Li et al.), stays the axle's"),
    TyreKey("STRUCTURAL", "PCFY3", "p_cy1_rl", "p_cy1 (eq. 4.9)", None, AXLE, _RL,
            note="the paper's second p_cy1 is MF 6.1's PCFY3 (C_y = C_y0 (1 + PCFY3 dp_i)); kept from the axle "
                 "with C_y0 when the file has none, so the relaxation law stays one pair"),
    TyreKey("LATERAL_COEFFICIENTS", "PCY1", "p_cy1", "p_cy1", None, REQUIRED, BOTH, scales=("LCY",)),
    TyreKey("LATERAL_COEFFICIENTS", "PDY1", "p_dy1", "p_dy1", None, REQUIRED, BOTH, scales=("LMUY",)),
    TyreKey("LATERAL_COEFFICIENTS", "PDY2", "p_dy2", "p_dy2", None, ZERO, BOTH, scales=("LMUY",)),
    TyreKey("LATERAL_COEFFICIENTS", "PEY1", "p_ey1", "p_ey1", None, REQUIRED, BOTH, scales=("LEY",),
            note="MF 6.1's E_y = (PEY1 + PEY2 df_z)(1 - PEY3 sgn alpha) at zero camber: the paper's E_y has no "
                 "asymmetry PEY3 (listed as not used when the file has it)"),
    TyreKey("LATERAL_COEFFICIENTS", "PEY2", "p_ey2", "p_ey2", None, ZERO, BOTH, scales=("LEY",)),
    TyreKey("LATERAL_COEFFICIENTS", "PKY1", "p_ky1", "p_ky1", None, REQUIRED, BOTH, sign=-1.0, scales=("LKY",),
            note="sign reversed: MF 6.1's PKY1 is negative (ISO signs), the paper's F_y = -D sin(...) takes "
                 "K_ya > 0"),
    TyreKey("LATERAL_COEFFICIENTS", "PKY2", "p_ky2", "p_ky2", None, REQUIRED, BOTH),
    TyreKey("LATERAL_COEFFICIENTS", "PKY4", "p_ky3", "p_ky3", None, REQUIRED, BOTH,
            note="the paper's p_ky3 is MF 6.1's PKY4 (MF 6.1's PKY3 is the camber term camber_p_ky3)"),
    TyreKey("LATERAL_COEFFICIENTS", "PPY1", "p_py1", "p_py1", None, ZERO, BOTH),
    TyreKey("LATERAL_COEFFICIENTS", "PPY2", "p_py2", "p_py2", None, ZERO, BOTH),
    TyreKey("LATERAL_COEFFICIENTS", "PPY3", "p_py3", "p_py3", None, ZERO, BOTH),
    TyreKey("LATERAL_COEFFICIENTS", "PPY4", "p_py4", "p_py4", None, ZERO, BOTH),
    TyreKey("LATERAL_COEFFICIENTS", "PKY3", "camber_p_ky3", "PKY3", None, ZERO, CAMBER),
    TyreKey("LATERAL_COEFFICIENTS", "PKY6", "camber_p_ky6", "PKY6", None, ZERO, CAMBER, scales=("LKYC",)),
    TyreKey("LATERAL_COEFFICIENTS", "PKY7", "camber_p_ky7", "PKY7", None, ZERO, CAMBER, scales=("LKYC",)),
    TyreKey("LATERAL_COEFFICIENTS", "PVY3", "camber_p_vy3", "PVY3", None, ZERO, CAMBER),
    TyreKey("LATERAL_COEFFICIENTS", "PVY4", "camber_p_vy4", "PVY4", None, ZERO, CAMBER),
    TyreKey("ALIGNING_COEFFICIENTS", "QCZ1", "q_cz1", "q_cz1", None, REQUIRED, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QDZ1", "q_dz1", "q_dz1", None, REQUIRED, _PT, scales=("LTR",)),
    TyreKey("ALIGNING_COEFFICIENTS", "QDZ2", "q_dz2", "q_dz2", None, ZERO, _PT, scales=("LTR",)),
    TyreKey("ALIGNING_COEFFICIENTS", "PPZ1", "p_pz1", "p_pz1", None, ZERO, _PT,
            note="the same form as MF 6.1, D_t (1 - PPZ1 dp_i); the paper's Table 1 has +0.4408 where the MF 6.1 "
                 "example file has -0.4408"),
    TyreKey("ALIGNING_COEFFICIENTS", "QBZ1", "q_bz1", "q_bz1", None, REQUIRED, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QBZ2", "q_bz2", "q_bz2", None, ZERO, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QBZ3", "q_bz3", "q_bz3", None, ZERO, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QEZ1", "q_ez1", "q_ez1", None, REQUIRED, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QEZ2", "q_ez2", "q_ez2", None, ZERO, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QEZ3", "q_ez3", "q_ez3", None, ZERO, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QEZ4", "q_ez4", "q_ez4", None, ZERO, _PT),
    TyreKey("ALIGNING_COEFFICIENTS", "QDZ8", "camber_q_dz8", "QDZ8", None, ZERO, CAMBER),
    TyreKey("ALIGNING_COEFFICIENTS", "QDZ9", "camber_q_dz9", "QDZ9", None, ZERO, CAMBER),
    TyreKey("ALIGNING_COEFFICIENTS", "QBZ9", "camber_q_bz9", "QBZ9", None, ZERO, CAMBER),
    # --- longitudinal force and combined slip (MF 6.1 (4.E9)-(4.E18), (4.E50)-(4.E67)): only under braking ---------
    TyreKey(_LONG, "PCX1", "p_cx1", "PCX1", None, AXLE, _BRAKE, scales=("LCX",), note=_LONG_NOTE),
    TyreKey(_LONG, "PDX1", "p_dx1", "PDX1", None, AXLE, _BRAKE, scales=("LMUX",)),
    TyreKey(_LONG, "PDX2", "p_dx2", "PDX2", None, AXLE, _BRAKE, scales=("LMUX",)),
    TyreKey(_LONG, "PEX1", "p_ex1", "PEX1", None, AXLE, _BRAKE, scales=("LEX",)),
    TyreKey(_LONG, "PEX2", "p_ex2", "PEX2", None, AXLE, _BRAKE, scales=("LEX",)),
    TyreKey(_LONG, "PEX3", "p_ex3", "PEX3", None, AXLE, _BRAKE, scales=("LEX",)),
    TyreKey(_LONG, "PEX4", "p_ex4", "PEX4", None, AXLE, _BRAKE),
    TyreKey(_LONG, "PKX1", "p_kx1", "PKX1", None, AXLE, _BRAKE, scales=("LKX",)),
    TyreKey(_LONG, "PKX2", "p_kx2", "PKX2", None, AXLE, _BRAKE, scales=("LKX",)),
    TyreKey(_LONG, "PKX3", "p_kx3", "PKX3", None, AXLE, _BRAKE),
    TyreKey(_LONG, "PPX1", "p_px1", "PPX1", None, AXLE, _BRAKE),
    TyreKey(_LONG, "PPX2", "p_px2", "PPX2", None, AXLE, _BRAKE),
    TyreKey(_LONG, "PPX3", "p_px3", "PPX3", None, AXLE, _BRAKE),
    TyreKey(_LONG, "PPX4", "p_px4", "PPX4", None, AXLE, _BRAKE),
    TyreKey(_LONG, "RBX1", "r_bx1", "RBX1", None, ZERO, _BRAKE, scales=("LXAL",), note=_PURE_NOTE),
    TyreKey(_LONG, "RBX2", "r_bx2", "RBX2", None, ZERO, _BRAKE),
    TyreKey(_LONG, "RCX1", "r_cx1", "RCX1", None, ZERO, _BRAKE),
    TyreKey(_LONG, "REX1", "r_ex1", "REX1", None, ZERO, _BRAKE),
    TyreKey(_LONG, "REX2", "r_ex2", "REX2", None, ZERO, _BRAKE),
    TyreKey(_LONG, "RHX1", "r_hx1", "RHX1", None, ZERO, _BRAKE, note=_MIRROR_NOTE),
    TyreKey("LATERAL_COEFFICIENTS", "RBY1", "r_by1", "RBY1", None, ZERO, _BRAKE, scales=("LYKA",)),
    TyreKey("LATERAL_COEFFICIENTS", "RBY2", "r_by2", "RBY2", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RBY3", "r_by3", "RBY3", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RCY1", "r_cy1", "RCY1", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "REY1", "r_ey1", "REY1", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "REY2", "r_ey2", "REY2", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RHY1", "r_hy1", "RHY1", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RHY2", "r_hy2", "RHY2", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RVY1", "r_vy1", "RVY1", None, ZERO, _BRAKE, scales=("LVYKA",)),
    TyreKey("LATERAL_COEFFICIENTS", "RVY2", "r_vy2", "RVY2", None, ZERO, _BRAKE, scales=("LVYKA",)),
    TyreKey("LATERAL_COEFFICIENTS", "RVY4", "r_vy4", "RVY4", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RVY5", "r_vy5", "RVY5", None, ZERO, _BRAKE),
    TyreKey("LATERAL_COEFFICIENTS", "RVY6", "r_vy6", "RVY6", None, ZERO, _BRAKE),
    TyreKey("ALIGNING_COEFFICIENTS", "SSZ1", "s_sz1", "SSZ1", None, ZERO, _BRAKE, scales=("LS",), note=_SSZ_NOTE),
    TyreKey("ALIGNING_COEFFICIENTS", "SSZ2", "s_sz2", "SSZ2", None, ZERO, _BRAKE, scales=("LS",)),
    # --- the paper's extensions beyond MF 6.1 ---------------------------------------------------------------
    TyreKey(EXTENSIONS, "PEY_DFZ2", "p_ey3", "p_ey3", None, ZERO, BOTH,
            note="Hopping's E_y terms: the paper's p_ey3 multiplies df_z^2, not MF 6.1's PEY3; without them E_y "
                 "is MF 6.1's, independent of pressure"),
    TyreKey(EXTENSIONS, "PEPY1", "p_epy1", "p_epy1", None, ZERO, BOTH),
    TyreKey(EXTENSIONS, "PEPY2", "p_epy2", "p_epy2", None, ZERO, BOTH),
    TyreKey(EXTENSIONS, "PEPEY1", "p_epey1", "p_epey1", None, ZERO, BOTH),
    TyreKey(EXTENSIONS, "A0", "a0", "a0", "length", AXLE, "both models; with --effects hcl through Guo's law (4.1)",
            note="MF 6.1 has no half contact length (MF-Swift's contact patch is not read)"),
    TyreKey(EXTENSIONS, "T0", "t0", "t0", "length", AXLE, "both models, section 3 model (without --effects pt)",
            note="a constant of the section 3 model: the paper keeps Li et al.'s truck value with Pacejka's tyre; "
                 "'shimmy params --tyre' prints the file's trail D_t at the nominal pressure beside it"),
    TyreKey(EXTENSIONS, "SIGMA0", "sigma0", "sigma0", "length", AXLE,
            "both models, section 3 model (without --effects rl)",
            note="as t0; the file's K_ya / C_y at the nominal pressure is printed beside it"),
)

# Scaling factors that act on a term the models use in a way that is not a plain product of the coefficients above
# (or on the speed, which neither model has): a file with another value is refused rather than read wrongly.
SCALES_MUST_BE = {"LVY": 1.0, "LKZC": 1.0, "LSGAL": 1.0, "LMUV": 0.0}

TIR_UNIT_KEYS = ("LENGTH", "FORCE", "ANGLE", "MASS", "TIME", "PRESSURE")
REQUIRED_UNITS = ("LENGTH", "FORCE", "ANGLE")
FITTYPS = {61: "MF 6.1", 62: "MF 6.2"}

# Sections a file must have: those with a required key, and the two that say how to read the rest.
REQUIRED_SECTIONS = ("UNITS", "MODEL") + tuple(dict.fromkeys(k.section for k in TYRE_KEYS if k.missing == REQUIRED))
# Sections the issue names that are read when present; their keys fall back as the table says.
READ_SECTIONS = REQUIRED_SECTIONS + ("STRUCTURAL", "LONGITUDINAL_COEFFICIENTS", "SCALING_COEFFICIENTS", EXTENSIONS)


def by_entry() -> dict[str, TyreKey]:
    return {k.entry: k for k in TYRE_KEYS}


def scale_keys() -> tuple[str, ...]:
    """Every scaling factor the reader folds in or checks."""
    folded = tuple(dict.fromkeys(s for k in TYRE_KEYS for s in k.scales))
    return folded + tuple(SCALES_MUST_BE)
