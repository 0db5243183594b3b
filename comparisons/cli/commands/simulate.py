"""``shimmy simulate``: time simulation at constant speed or along a speed ramp, with shimmy-mode switches."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from comparisons.api import check_simulation_work, name_and_text, schedule_of
from comparisons.api import simulate as simulate_api
from axles.axle import interface_text
from axles.limits import (
    ANGLE_RANGE_DEG,
    DURATION_RANGE_S,
    MAX_CYCLES,  # noqa: F401 - tests/cli/test_cycles_cli.py reads it from here
    RAMP_TIME_RANGE_S,
    RATE_RANGE_DEG_S,
    SPEED_RANGE_KMH,
    UsageError,
)
from axles.units import kmh
from comparisons.cli.options import (
    add_braking_options,
    add_model_choice,
    add_model_options,
    add_output_options,
    build_axle,
    build_fidelity,
    braking_label,
    build_model,
    chosen_model,
    emit_json,
    inputs_json,
    parse_number,
    pressure_label,
    ranged,
)
from comparisons.cli.progress import progress
from reduced_model.model import STATE_NAMES, STATE_UNITS
from reduced_model.modes import ModeClassifier, ModeHistory
from axles.parameters import ParameterError
from reduced_model.trajectory import SpeedSchedule, Trajectory

HOLD_AFTER_RAMP = 20.0     # s simulated after a ramp when --duration is not given
CONSTANT_DURATION = 20.0   # s at constant speed when --duration is not given


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="time simulation at constant speed or along a speed ramp; reports "
                                        "switches between the yaw and tramp modes")
    add_model_options(p)
    add_model_choice(p)
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--speed", type=ranged("--speed", *SPEED_RANGE_KMH, "km/h"), metavar="KMH",
                     help="constant speed, km/h (within [{:g}, {:g}])".format(*SPEED_RANGE_KMH))
    how.add_argument("--ramp", metavar="FROM:TO:SECONDS",
                     help="speed ramp: FROM to TO km/h linearly in SECONDS s, then held (speeds within "
                          "[{:g}, {:g}] km/h, SECONDS within [{:g}, {:g}])".format(*SPEED_RANGE_KMH,
                                                                                 *RAMP_TIME_RANGE_S))
    p.add_argument("--duration", type=ranged("--duration", *DURATION_RANGE_S, "s"), metavar="SECONDS",
                   help=f"simulated time, s (default {CONSTANT_DURATION:g} at constant speed, ramp time + "
                        f"{HOLD_AFTER_RAMP:g} for a ramp; within [{DURATION_RANGE_S[0]:g}, "
                        f"{DURATION_RANGE_S[1]:g}])")
    p.add_argument("--initial", action="append", metavar="NAME=VALUE",
                   help=f"initial state in degrees and deg/s (angles within [{ANGLE_RANGE_DEG[0]:g}, "
                        f"{ANGLE_RANGE_DEG[1]:g}] deg, rates within [{RATE_RANGE_DEG_S[0]:g}, "
                        f"{RATE_RANGE_DEG_S[1]:g}] deg/s); names: {' '.join(STATE_NAMES)}; repeatable "
                        f"(default theta1=0.573 deg (0.01 rad), the rest 0); under braking added to the braked "
                        f"steady state")
    add_braking_options(p)
    add_output_options(p, plot=True)
    p.add_argument("--rerun", metavar="FILE.rrd", help="write a Rerun recording of the run (3D scene, states, "
                                                        "speed, mode lane, switch events)")
    p.add_argument("--series", metavar="FILE.csv|.parquet",
                   help="write the time series: time, speed, every state in degrees (per second), detected mode")
    p.set_defaults(run=run)


def parse_ramp(text: str) -> tuple[float, float, float]:
    """``--ramp FROM:TO:SECONDS`` to (km/h, km/h, s), each checked against its range."""
    parts = text.split(":")
    if len(parts) != 3:
        raise UsageError(f"--ramp expects FROM:TO:SECONDS, got '{text}'")
    start, end = (parse_number(x, f"--ramp {what}", *SPEED_RANGE_KMH, "km/h") for x, what in
                  zip(parts[:2], ("FROM", "TO")))
    return start, end, parse_number(parts[2], "--ramp SECONDS", *RAMP_TIME_RANGE_S, "s")


def parse_initial(items: list[str] | None) -> dict[str, float] | None:
    """``--initial NAME=VALUE`` to {state: degrees (angles) or degrees per second (rates)}, each checked against
    its range; None without the option (the API's default start)."""
    if not items:
        return None
    values: dict[str, float] = {}
    for item in items:
        try:
            name, text = name_and_text(item, "--initial")
        except ParameterError as exc:
            raise UsageError(interface_text(exc)) from None
        if name not in STATE_NAMES:
            raise UsageError(f"unknown state '{name}' in --initial (names: {' '.join(STATE_NAMES)})")
        rate = STATE_UNITS[STATE_NAMES.index(name)] == "rad/s"
        lo, hi = RATE_RANGE_DEG_S if rate else ANGLE_RANGE_DEG
        values[name] = parse_number(text, f"--initial {name}", lo, hi, "deg/s" if rate else "deg")
    return values


def check_work(args: argparse.Namespace, schedule: SpeedSchedule, duration: float) -> None:
    """Refuse a run whose fastest oscillation would take the integrator minutes to resolve, or an MBS run past
    :data:`~axles.limits.MBS_MAX_DURATION` (exit 2, with why): the API's guard
    (:func:`comparisons.api.check_simulation_work`), naming the option."""
    try:
        check_simulation_work(chosen_model(args), args.tyre_pressures, schedule, duration, what="--duration",
                              braking=args.braking)
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None


def simulate_model(args: argparse.Namespace, ramp: tuple[float, float, float] | None, duration: float,
                   initial: dict[str, float] | None) -> Trajectory:
    """The one place where a trajectory is made, by the API's one call for both models: the reduced model
    (scipy) or the multibody model (Exudyn, with the bodies' poses when recording), either with progress in
    simulated time."""
    def run(tick=None) -> Trajectory:
        try:
            return simulate_api(chosen_model(args), args.tyre_pressures, speed_kmh=args.speed, ramp_kmh=ramp,
                                duration_s=duration, initial_deg=initial, progress=tick,
                                poses=bool(args.rerun), braking=args.braking).trajectory
        except ParameterError as exc:
            raise UsageError(interface_text(exc)) from None

    quiet = args.json or not sys.stderr.isatty()
    with progress(100, "simulating", quiet) as bar:
        def tick(t):
            bar.n = int(100 * t / duration)
            bar.set_postfix_str(f"{t:.4g} of {duration:g} s simulated", refresh=False)
            bar.refresh()
        return run(tick)


def steady_json(trajectory: Trajectory) -> dict:
    """The braked steady state the run starts from and is measured about (angles, deg); {} free rolling."""
    if trajectory.origin is None:
        return {}
    x = trajectory.origin
    return {"steady_state": {f"{n}_deg": math.degrees(x[STATE_NAMES.index(n)]) for n in ("theta1", "theta2", "psi")}}


def result_json(trajectory: Trajectory, history: ModeHistory) -> dict:
    final = history.final
    return {
        "model": trajectory.model,
        "integrator": trajectory.integrator,
        "complete": trajectory.complete,
        "status": trajectory.status.value,
        "message": interface_text(trajectory.message),
        "duration_s": float(trajectory.t[-1]),
        "initial_mode": history.initial.value,
        "mode_switches": [{"time_s": s.time, "speed_kmh": kmh(s.speed), "from": s.before.value,
                           "to": s.after.value} for s in history.switches],
        "final": {"mode": history.final_mode.value, "max_theta1_deg": math.degrees(final.theta1),
                  "max_psi_deg": math.degrees(final.psi),
                  "frequency_hz": None if not np.isfinite(final.frequency_hz) else final.frequency_hz,
                  "speed_kmh": kmh(final.speed)},
        **steady_json(trajectory),
    }


def schedule_json(args: argparse.Namespace, duration: float) -> dict:
    """The run's inputs beyond the axle and pressures: speed schedule, duration asked, start, MBS fidelity."""
    if args.speed is not None:
        schedule = {"speed_kmh": args.speed}
    else:
        start, end, seconds = (float(x) for x in args.ramp.split(":"))
        schedule = {"ramp": {"from_kmh": start, "to_kmh": end, "seconds": seconds}}
    fidelity = build_fidelity(args)
    return {"schedule": schedule, "duration_requested_s": duration, "initial": list(args.initial or []),
            "fidelity": None if fidelity is None else fidelity.label}


def run(args: argparse.Namespace) -> int:
    ramp = None if args.speed is not None else parse_ramp(args.ramp)
    schedule = schedule_of(args.speed, ramp)
    duration = args.duration
    if duration is None:
        duration = CONSTANT_DURATION if ramp is None else schedule.ramp_time + HOLD_AFTER_RAMP
    initial = parse_initial(args.initial)
    check_work(args, schedule, duration)
    if args.series:   # the paths themselves are checked by comparisons.cli before any command runs
        from comparisons.recordings.series import series_format
        try:
            series_format(args.series)
        except ValueError as exc:
            raise UsageError(interface_text(exc)) from None
    trajectory = simulate_model(args, ramp, duration, initial)
    history = ModeClassifier().classify(trajectory)
    if args.rerun:
        from comparisons.recordings.writer import RecordingError, write_recording
        try:
            write_recording(args.rerun, trajectory, history.segments(), history.switches,
                            title=f"{trajectory.model} model, {pressure_label(args)}", model=build_model(args),
                            pressures=args.tyre_pressures)
        except RecordingError as exc:
            raise UsageError(interface_text(exc)) from None
    how = f"{args.speed:g} km/h" if args.speed is not None else f"ramp {args.ramp} (km/h:km/h:s)"
    if args.plot:
        from comparisons.figures.cycle_plots import MODEL_NAMES, plot_trajectory
        plot_trajectory(trajectory, history, args.plot,
                        title=f"{MODEL_NAMES.get(trajectory.model, trajectory.model)}, {pressure_label(args)}, "
                              f"{how}; {trajectory.integrator.split(',')[0]}")
    if args.series:
        from comparisons.recordings.series import series_table, write_series
        write_series(args.series, series_table(trajectory, history.segments(),
                                               {**inputs_json(args), "schedule": how}))
    if args.json:
        emit_json({**inputs_json(args), **schedule_json(args, duration), **result_json(trajectory, history)})
    else:
        out = result_json(trajectory, history)
        print(f"{trajectory.model} model at {pressure_label(args)}{braking_label(args)}, {how}, "
              f"{out['duration_s']:g} s simulated")
        print(f"  {build_axle(args).label()}")
        if "steady_state" in out:
            shown = ", ".join(f"{k.replace('_deg', '')} {v:+.4f}" for k, v in out["steady_state"].items())
            print(f"  started from straight running under braking (--initial adds to it; amplitudes about it), "
                  f"deg: {shown}")
        print(f"  integrator: {trajectory.integrator}")
        print(f"  initial mode: {out['initial_mode']}")
        for s in out["mode_switches"]:
            print(f"  switch {s['from']:>5s} -> {s['to']:5s} at t = {s['time_s']:7.2f} s, {s['speed_kmh']:7.2f} km/h")
        f = out["final"]
        freq = "-" if f["frequency_hz"] is None else f"{f['frequency_hz']:.3f} Hz"
        print(f"  final: {f['mode']}, max|theta1| {f['max_theta1_deg']:.4f} deg, max|psi| {f['max_psi_deg']:.4f} deg,"
              f" {freq} (last {ModeClassifier().window:g} s)")
        if not trajectory.complete:
            print(f"  INCOMPLETE: {interface_text(trajectory.message)}")
        if args.plot:
            print(f"  plot written to {args.plot}")
        if args.rerun:
            print(f"  recording written to {args.rerun}")
        if args.series:
            print(f"  time series written to {args.series}")
    if not trajectory.complete:
        sys.stderr.write(f"shimmy: incomplete: {interface_text(trajectory.message)}\n")
        return 3
    return 0
