"""Inputs that are not axle entries: their physical ranges (interface units; read by the options, the sweeps and
the docs) and the error for a value outside them.
"""

from __future__ import annotations


class UsageError(Exception):
    """Bad input from the command line: reported as one line, exit code 2."""


# Physical ranges of the inputs that are not axle entries (interface units; docs/cli.md's table is generated from them).
# comparisons.cli.main imports this module outside the guard for an interrupt during the model packages' import,
# so the lowest speed repeats reduced_model.family.MIN_SPEED instead of importing it; tests/axles/test_limits.py
# holds the two together.
SPEED_RANGE_KMH = (0.5, 1000.0)       # below 0.5 km/h the slip equations degenerate (reduced_model.family.MIN_SPEED)
PRESSURE_RANGE_BAR = (0.05, 20.0)
DURATION_RANGE_S = (0.01, 1000.0)     # simulated time; 1000 s at 1 kHz samples is 8 MB of states
RAMP_TIME_RANGE_S = (0.01, 1000.0)
ANGLE_RANGE_DEG = (-45.0, 45.0)       # initial angles: a small-angle model, 45 deg is already far beyond it
RATE_RANGE_DEG_S = (-1.0e4, 1.0e4)    # initial angular rates

# Work a simulation may take on (the command's simulate and the API's simulate; docs/cli.md's table reads them).
MAX_CYCLES = 5.0e4         # periods of the fastest mode an integrator must resolve; about 80 s of LSODA here
MBS_MAX_DURATION = 100.0   # s: the MBS steps at 1 ms through a Python tyre element, about 2 s per simulated s
BRAKE_SLIP_RANGE = (-1.0, 1.0)        # steady brake slip per wheel (-): 0 free rolling, 1 a locked wheel, < 0 driving
BRAKE_FORCE_RANGE_N = (-1.0e5, 1.0e5)  # steady brake force per wheel, N rearward, < 0 driving (the tyre's grip is
#                                      checked with the tyre)
