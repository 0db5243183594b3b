"""Dimensions of the multibody axle that the paper does not give, each with its unit and the reason for its value.

Table 1 fixes the inertias I1 (wheel about its kingpin), I2 (wheel spin), I3 (axle roll), the track L, the
kingpin offset l, the caster angle gamma and the rolling radius R.  The multibody model also needs masses, the
wheel's diametral inertia and the linkage arms.  They are chosen here so that the Table 1 inertias hold exactly
at straight running (the axle's own roll inertia and the knuckle's inertia about the kingpin are what is left);
the linkage stiffnesses are scaled so that their stiffness about the kingpins is exactly k1 and k2.  With the
reduced model's assumptions none of these numbers enters the equations (``tests/test_mbs_equivalence.py`` checks
that); with the full geometry they set the inertial coupling and the linkage nonlinearity.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from bifurcation.messages import Message, Quantity
from axles.parameters import ParameterError, ShimmyParameters, check_ranges


def _d(value: float, unit: str, reason: str, *, range: tuple[float, float], plausible: tuple[float, float],
       neutral: float | None = None, source: str | None = None) -> Any:
    """A chosen dimension (SI).  ``range``: where the model stays physically meaningful (inclusive);
    ``plausible``: where a real truck beam axle's value lies (for uncertainty studies); ``neutral``: the value at
    which the element has no effect, if there is one; ``source``: where the value comes from, if it is not an
    estimate chosen for the multibody model (the axle registry then says "chosen")."""
    meta = {"unit": unit, "reason": reason, "range": range, "plausible": plausible, "neutral": neutral}
    if source is not None:
        meta["source"] = source
    return field(default=value, metadata=meta)


_PACEJKA_205 = ("Pacejka, Tire and Vehicle Dynamics, 3rd ed., 2012, the 205/60R15 91V example tyre (MF-Tyre 6.1 "
                "parameter table of the appendix), the tyre of the paper's Table 1; read from a transcription of that"
                " table whose entries the paper uses (PDY2, PKY2, PKY4, PPY1-4, QBZ1-2, QEZ1-2, QEZ4) equal Table 1;"
                " the eight camber coefficients also equal those of four other public transcriptions of the same "
                "MF 6.1 example tyre file (sample.tir, FNOMIN 4000 N, R0 0.3135 m), checked 2026-12-02; not checked "
                "against the book itself")


@dataclass(frozen=True)
class AxleDimensions:
    """Masses, inertias and arm lengths of the multibody axle not given by the paper (SI)."""

    wheel_mass: float = _d(40.0, "kg", "truck wheel with tyre; gives I2 = 4.85 kg m^2 with a radius of "
                                       "gyration 0.35 m at R = 0.4 m",
                   range=(1.0, 500.0), plausible=(30.0, 60.0))
    wheel_diametral_inertia: float = _d(2.6, "kg m^2", "wheel about a diameter; about half of I2 plus the "
                                                      "tyre width, as for a ring-like rim and tyre",
                   range=(0.1, 50.0), plausible=(2.45, 3.2))   # a rigid wheel needs at least I2 / 2
    knuckle_mass: float = _d(20.0, "kg", "knuckle, hub and brake; its centre of mass is put on the kingpin axis",
                   range=(1.0, 200.0), plausible=(12.0, 35.0))
    knuckle_transverse_inertia: float = _d(0.3, "kg m^2", "knuckle about axes across the kingpin",
                   range=(0.01, 10.0), plausible=(0.15, 0.6))
    axle_mass: float = _d(120.0, "kg", "beam axle; centre of mass at wheel-centre height (on the line through the "
                                       "wheel centres), so about a raised roll axis it adds m h^2 of roll inertia "
                                       "and couples the roll with the lateral travel",
                   range=(10.0, 1000.0), plausible=(80.0, 200.0))
    tie_rod_arm: float = _d(0.2, "m", "steering arm length to the tie-rod joint, perpendicular to the kingpin, "
                                      "pointing rearward",
                   range=(0.05, 1.0), plausible=(0.15, 0.3))
    drag_link_arm: float = _d(0.2, "m", "left steering arm to the drag link, pointing inboard",
                   range=(0.05, 1.0), plausible=(0.15, 0.3))
    drag_link_length: float = _d(0.8, "m", "drag link from the arm forward to the steering gear on the frame",
                   range=(0.1, 3.0), plausible=(0.5, 1.2))
    # --- the geometry of issue 9: each entry has a neutral value at which its element has no effect -----------
    kingpin_inclination: float = _d(math.radians(7.0), "rad",
                                    "kingpin inclination (7 deg), the kingpin's inward tilt at the top seen from the "
                                    "front; truck beam axles use 5-9 deg (Reimpell, Stoll & Betzler, The Automotive "
                                    "Chassis, 2001, sec. 3.6); with the hub offset l it gives the scrub radius "
                                    "l - R tan(inclination) (21 mm with Table 1)",
                   range=(0.0, math.radians(20.0)), plausible=(math.radians(5.0), math.radians(9.0)), neutral=0.0)
    steering_arm_angle: float = _d(math.atan(0.734 / 4.5), "rad",
                                   "inward angle of the tie-rod arms from the vehicle's x-axis (9.26 deg): their lines "
                                   "meet at the rear axle of a 4.5 m wheelbase (Ackermann's condition, "
                                   "atan((L/2 - l) / 4.5 m)); 0 = parallel arms",
                   range=(math.radians(-30.0), math.radians(30.0)), plausible=(math.radians(7.0), math.radians(11.5)),
                   neutral=0.0)
    roll_axis_above_wheel_centre: float = _d(0.1, "m", "height of the axle's roll axis above the wheel centres: "
                                                       "a leaf-sprung beam axle rolls about the spring seats, "
                                                       "0.05-0.2 m above the axle (roll centre 0.5 m above the road "
                                                       "with R = 0.4 m)",
                   range=(-0.3, 1.0), plausible=(0.05, 0.25), neutral=0.0)
    axle_mount_lateral_compliance: float = _d(1.0e-6, "m/N", "lateral compliance of both leaf springs at the axle "
                                                            "seats together: 1 / (1.0 MN/m), an order-of-magnitude "
                                                            "value (0.3-1.5 kN/mm per spring); 0 = rigid mounts",
                   range=(0.0, 1e-4), plausible=(0.33e-6, 2.5e-6), neutral=0.0)
    axle_mount_lateral_damping: float = _d(1.6e3, "N s/m", "lateral damping of the axle mounts: 5 % of critical "
                                                           "on the axle's 240 kg (inter-leaf friction, bushes); no "
                                                           "effect with rigid mounts",
                   range=(0.0, 1e6), plausible=(0.5e3, 5e3))
    steering_gear_compliance: float = _d(1.25e-5, "rad/(N m)", "torsional compliance of the steering gear's output "
                                                               "(Pitman) shaft to the frame, 1 / (80 kN m/rad): column "
                                                               "and hands-on steering wheel, about 200 N m/rad at the "
                                                               "wheel, through a 20:1 gear (x 400); 0 = rigid gear",
                   range=(0.0, 1e-3), plausible=(5.0e-6, 3.3e-5), neutral=0.0)
    steering_gear_damping: float = _d(800.0, "N m s/rad", "damping of the Pitman shaft to the frame: about 2 N m s/rad "
                                                          "of hands and column at the steering wheel x 400; no effect "
                                                          "with a rigid gear",
                   range=(0.0, 1e6), plausible=(200.0, 3000.0))
    steering_gear_inertia: float = _d(30.0, "kg m^2", "inertia about the Pitman shaft: steering wheel and column "
                                                      "(about 0.075 kg m^2) through the 20:1 gear (x 400); no effect "
                                                      "with a rigid gear",
                   range=(0.01, 1000.0), plausible=(10.0, 60.0))
    pitman_arm: float = _d(0.2, "m", "Pitman arm from the steering-gear shaft down to the drag-link ball; no effect "
                                     "with a rigid gear",
                   range=(0.05, 1.0), plausible=(0.15, 0.3))
    drag_link_inclination: float = _d(math.radians(5.0), "rad",
                                      "rise of the drag link towards the steering gear seen from the side (5 deg): the "
                                      "gear sits on the frame above the steering arm; with the axle's roll it steers "
                                      "the left wheel (roll steer)",
                   range=(math.radians(-30.0), math.radians(30.0)), plausible=(0.0, math.radians(12.0)),
                   neutral=0.0)

    # --- the freedoms of issue 18 ---------------------------------------------------------------------------
    axle_roll_steer: float = _d(0.1, "rad/rad",
                                "yaw of the axle about z per unit of its roll about x (roll steer), both right-handed "
                                "in the vehicle frame: the spring eyes and shackles of the leaf springs make the "
                                "axle roll about an axis sloped in side view by atan(coefficient); positive = the "
                                "axle turns its nose left as its left side rises (roll understeer of a front axle "
                                "in a right turn, where the frame rolls left over the axle); 0 = roll about x",
                                source="leaf-sprung solid axles 0-0.2 rad/rad, the slope of the axle's roll axis in "
                                       "side view: the range as remembered from Gillespie, Fundamentals of Vehicle "
                                       "Dynamics, SAE 1992 (roll steer of solid axles), not checked against the book; "
                                       "0.1 is the middle, an estimate",
                   range=(-0.5, 0.5), plausible=(0.0, 0.2), neutral=0.0)

    axle_mount_vertical_compliance: float = _d(2.0e-6, "m/N",
                                               "vertical compliance of both leaf springs at the axle seats together: "
                                               "1 / (0.5 MN/m), 250 kN/m per spring, an order-of-magnitude value for "
                                               "a truck front axle (axle hop near 12 Hz with the tyres); 0 = rigid",
                   range=(0.0, 1e-4), plausible=(1.25e-6, 3.3e-6), neutral=0.0)
    axle_mount_vertical_damping: float = _d(6.0e3, "N s/m", "vertical damping at the seats (shock absorbers, "
                                                            "inter-leaf friction): about 17 % of critical for the "
                                                            "axle's 240 kg on springs and tyres; no effect with "
                                                            "rigid mounts",
                   range=(0.0, 1e6), plausible=(3.0e3, 12.0e3))
    tie_rod_mass: float = _d(10.0, "kg", "tie rod with its ball joints: a steel tube of about 1.4 m, an "
                                         "order-of-magnitude value for a truck front axle; 0 = massless",
                   range=(0.0, 100.0), plausible=(6.0, 15.0), neutral=0.0)
    drag_link_mass: float = _d(6.0, "kg", "drag link with its ball joints (0.8 m), an order-of-magnitude value; "
                                          "0 = massless",
                   range=(0.0, 100.0), plausible=(3.0, 10.0), neutral=0.0)
    # --- the Magic Formula's camber terms (assumption no_camber_force off; mbs_shimmy/camber.py) -------------
    # plausible: +-50 % of the example tyre's value (no measured truck-tyre set here); neutral 0: no camber term
    camber_p_ky3: float = _d(0.3695, "1/rad", "MF 6.1 PKY3: fall of the cornering stiffness with |camber| (the "
                                              "paper's p_ky3 is MF 6.1's PKY4)",
                   source=_PACEJKA_205, range=(0.0, 0.95), plausible=(0.18, 0.55), neutral=0.0)
    camber_p_ky6: float = _d(-0.8987, "1/rad", "MF 6.1 PKY6: camber stiffness K_ygamma / F_z at the nominal load (ISO"
                                               " signs: a wheel leaning right pushes right)",
                   source=_PACEJKA_205, range=(-5.0, 5.0), plausible=(-1.35, -0.45), neutral=0.0)
    camber_p_ky7: float = _d(-0.23303, "1/rad", "MF 6.1 PKY7: load dependence of the camber stiffness",
                   source=_PACEJKA_205, range=(-5.0, 5.0), plausible=(-0.35, -0.12), neutral=0.0)
    camber_p_vy3: float = _d(-0.162, "1/rad", "MF 6.1 PVY3: camber part of the vertical shift S_Vy / F_z",
                   source=_PACEJKA_205, range=(-5.0, 5.0), plausible=(-0.24, -0.08), neutral=0.0)
    camber_p_vy4: float = _d(-0.4864, "1/rad", "MF 6.1 PVY4: load dependence of that shift",
                   source=_PACEJKA_205, range=(-5.0, 5.0), plausible=(-0.73, -0.24), neutral=0.0)
    camber_q_dz8: float = _d(-0.1428, "1/rad", "MF 6.1 QDZ8: camber moment, the residual torque's peak / (F_z R) per "
                                               "rad of camber",
                   source=_PACEJKA_205, range=(-2.0, 2.0), plausible=(-0.21, -0.07), neutral=0.0)
    camber_q_dz9: float = _d(0.00915, "1/rad", "MF 6.1 QDZ9: load dependence of the camber moment",
                   source=_PACEJKA_205, range=(-2.0, 2.0), plausible=(0.0046, 0.0137), neutral=0.0)
    camber_q_bz9: float = _d(34.5, "1/rad", "MF 6.1 QBZ9: slope of the residual torque's fade with slip, "
                                            "cos(arctan(QBZ9 alpha_r))",
                   source=_PACEJKA_205, range=(0.0, 200.0), plausible=(17.0, 52.0), neutral=None)

    def __post_init__(self) -> None:
        check_ranges(self, "dimension")

    def replace(self, **overrides: float) -> "AxleDimensions":
        names = {f_.name for f_ in dataclasses.fields(self)}
        for name in overrides:
            if name not in names:
                raise ParameterError(f"unknown dimension '{name}' (known: {', '.join(sorted(names))})")
        return dataclasses.replace(self, **{k: float(v) for k, v in overrides.items()})

    def table(self) -> list[dict[str, Any]]:
        return [{"name": f_.name, "value": getattr(self, f_.name), "unit": f_.metadata["unit"],
                 "reason": f_.metadata["reason"], "range": f_.metadata["range"],
                 "plausible": f_.metadata["plausible"], "neutral": f_.metadata["neutral"]}
                for f_ in dataclasses.fields(self)]

    # --- derived inertias that make Table 1 hold at straight running ------------------------------------
    def knuckle_kingpin_inertia(self, params: ShimmyParameters) -> float:
        """Knuckle about its kingpin: I1 less the wheel's diametral inertia and its offset l (kg m^2)."""
        value = params.I1 - self.wheel_diametral_inertia - self.wheel_mass * params.l ** 2
        if not value > 0.0:
            raise ParameterError(Message.of(Quantity("I1", params.I1, 6, "kg m^2"), " is smaller than the wheel's "
                                            f"own inertia about the kingpin ({params.I1 - value:g} kg m^2): choose a "
                                            "lighter wheel"))
        return value

    def check(self, params: ShimmyParameters) -> None:
        """Raise :class:`ParameterError` if these dimensions cannot reproduce Table 1's I1 and I2."""
        self.knuckle_kingpin_inertia(params)
        if params.I2 > 2.0 * self.wheel_diametral_inertia + 1e-12:
            raise ParameterError(Message.of(Quantity("I2", params.I2, 6, "kg m^2"), " exceeds twice the diametral "
                                            f"inertia {self.wheel_diametral_inertia:g} kg m^2: no rigid wheel has that"))


DEFAULT_DIMENSIONS = AxleDimensions()
