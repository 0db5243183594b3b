"""Numbers printed in the reference paper (Yang, Knowles & Mavros, The ANZIAM Journal, 2025), for comparison only.

These are results of the authors' MATLAB/COCO implementation, never inputs: nothing in ``reduced_model`` or
``mbs_shimmy`` reads this file.  Units as printed (km/h, bar, m, N/m, degrees, Hz).
"""

from __future__ import annotations

# Section 3, figures 3 and 4: Hopf speeds of the section 3 model (km/h) by pressure (bar).
HOPF_SPEEDS_KMH = {
    2.5: (46.14, 70.5),
    1.5: (27.63, 97.13, 192.98, 345.89),
    2.7: (),
}

# Section 3, figures 3-4: limit cycles.
NOMINAL_PEAK = {"speed_kmh": 56.34, "theta1_deg": 3.45, "psi_deg": 0.14}
LOW_PRESSURE_MODES = {  # 1.5 bar
    "yaw": {"theta1_deg": 9.85, "psi_deg": 0.41, "frequency_hz": (5.28, 6.66)},
    "tramp": {"theta1_deg": 3.18, "psi_deg": 0.92, "frequency_hz": (10.6, 13.2)},
}

# Figure 5: section 3 model in the (V, p) plane.
FIG5_F1 = {"speed_kmh": 57.79, "pressure_bar": 2.61}
FIG5_TRAMP_VANISHES = {"speed_kmh": 252.0, "pressure_bar": 1.73}

# Section 4 critical values (second parameter in SI units as printed).
SECTION4 = {
    "a0_fold_2.5bar_m": 0.186,               # HB1 and HB2 collide at nominal pressure (figure 6)
    "a0_fold_speed_kmh": 58.0,               # "the speed at which bifurcations intersect remain unchanged"
    "t0_yaw_vanishes_1.5bar_m": 0.053,       # figure 8
    "t0_tramp_vanishes_1.5bar_m": 0.057,
    "t0_hopf_hopf_1.5bar_m": 0.135,
    "t0_dh1_1.5bar_m": 0.146,
    "t0_dh2_1.5bar_m": 0.216,
    "t0_modes_merge_1.5bar_m": 0.28,         # "finally merge into one mode when t > 0.28 m"
    "sigma0_tramp_vanishes_1.5bar_m": 0.73,  # figure 13
    "sigma0_yaw_vanishes_1.5bar_m": 1.2,
    "k5_tramp_vanishes_1.5bar_Npm": 4.39e5,  # figure 14
    "k5_modes_merge_1.5bar_Npm": 2.55e5,
    "k5_F1_2.56bar_Npm": 2.41e5,             # figure 15 (1.024 p_i0)
    "k5_F2_2.56bar_Npm": 3.19e5,
    "k5_second_mode_upper_2.56bar_Npm": 2.78e5,
    "k5_F3_Npm": 6e5,                        # figure 14: "F2 moves to F3"; the pressure is not printed
    "sigma0_small_shimmy_upper_kmh": 325.0,  # figure 13, 1.5 bar: "shimmy from 0 to 325 km/h" as sigma -> 0
}

# Section 5, figure 17: cumulative effects.  None where the paper says the feature does not exist.
SECTION5 = {
    "": {"no_shimmy_bar": 2.61, "tramp_vanishes_bar": 1.73},
    "hcl": {"no_shimmy_bar": 2.58, "tramp_vanishes_bar": 1.75, "cusp_kmh": 220.5, "cusp_bar": 0.078},
    "hcl,pt": {"no_shimmy_bar": 2.56, "tramp_vanishes_bar": 1.88, "hopf_hopf_bar": 0.53},
    "hcl,pt,rl": {"no_shimmy_bar": 2.59, "tramp_vanishes_bar": None},
    "hcl,pt,rl,vs": {"no_shimmy_bar": 2.6, "modes_meet_bar": 0.76},
}

# Figure 9a (t0 = 0.25 m, 1.5 bar): cycle folds and torus points (km/h).
FIG9A = {"S1": 184.75, "T1": 181.65, "T2": 157.39, "S2": 135.56}

# Figures 10 and 11 (t0 = 0.25 m, 1.5 bar): the phase portrait is at 180 km/h; the ramps' jump speeds are not
# printed, only that they happen at S1 (speed increasing) and T2 (speed decreasing).
FIG11_SPEED_KMH = 180.0

# Figure 15a (2.5 bar, k5 = 2.2e5 N/m): peak tramp angle of the low-speed mode (deg).
FIG15A = {"k5_0_Npm": 2.2e5, "psi_low_mode_deg": 0.41}

# Printed values that an honest computation of the printed equations does not reproduce beyond the printed
# digits, with the explanation shown in the README's "Differences from the paper" table and in verify's report.
KNOWN_DIFFERENCES = {
    "hopf:1.5:HB1": "computed 26.630 km/h; cause unknown: the other five section 3 Hopf speeds agree to every "
                    "printed digit, yet the printed 27.63 km/h is consistent with the printed lowest yaw-mode "
                    "frequency 5.28 Hz (the computed cycle has it near 27.5 km/h)",
    "cycles:2.5:peak_speed": "computed: max|theta1| peaks at 56.64 km/h and max|psi| at 57.01 km/h (paper: both "
                             "at 56.34); the peak is flat, at 56.34 km/h max|theta1| is 0.001 deg below it",
    "cycles:1.5:yaw_frequency_low": "computed 5.263 Hz (the frequency at HB1 = 26.63 km/h); the printed 5.28 Hz "
                                    "is the cycle's frequency near 27.5 km/h, consistent with the printed HB1",
    "cycles:fig9a:T2": "computed 157.3849 km/h, printed 157.39: 0.005 km/h apart, at the rounding edge",
    "cycles:fig10b:jump": "ramp 200 -> 120 km/h in 80 s: tramp -> yaw at 138.5 km/h, not at T2 = 157.38 km/h: "
                          "delayed loss of stability on the slowly crossed torus point (the jump at constant "
                          "speed below T2 is shown separately)",
}
