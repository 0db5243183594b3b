"""``shimmy simulate``: time simulation at constant speed or along a speed ramp, with shimmy-mode switches."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from reduced_model.model import STATE_NAMES
from reduced_model.modes import ModeClassifier, ModeHistory
from reduced_model.simulation import initial_state, simulate
from reduced_model.trajectory import SpeedSchedule, Trajectory

from ..options import (
    KMH,
    UsageError,
    add_model_choice,
    add_model_options,
    add_output_options,
    build_axle,
    build_fidelity,
    build_model,
    check_output_path,
    emit_json,
    inputs_json,
    operating_pressure,
    pressure_label,
    positive_float,
    progress,
)

HOLD_AFTER_RAMP = 20.0     # s simulated after a ramp when --duration is not given
CONSTANT_DURATION = 20.0   # s at constant speed when --duration is not given


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="time simulation at constant speed or along a speed ramp; reports "
                                        "switches between the yaw and tramp modes")
    add_model_options(p)
    add_model_choice(p)
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--speed", type=positive_float("--speed"), metavar="KMH", help="constant speed, km/h")
    how.add_argument("--ramp", metavar="FROM:TO:SECONDS",
                     help="speed ramp: FROM to TO km/h linearly in SECONDS s, then held")
    p.add_argument("--duration", type=positive_float("--duration"), metavar="SECONDS",
                   help=f"simulated time, s (default {CONSTANT_DURATION:g} at constant speed, ramp time + "
                        f"{HOLD_AFTER_RAMP:g} for a ramp)")
    p.add_argument("--initial", action="append", metavar="NAME=VALUE",
                   help=f"initial state, SI (rad, rad/s); names: {' '.join(STATE_NAMES)}; repeatable "
                        f"(default theta1=0.01, the rest 0)")
    add_output_options(p, plot=True)
    p.add_argument("--rerun", metavar="FILE.rrd", help="write a Rerun recording of the run (3D scene, states, "
                                                        "speed, mode lane, switch events)")
    p.add_argument("--series", metavar="FILE.csv|.parquet",
                   help="write the time series: time, speed, every state in degrees (per second), detected mode")
    p.set_defaults(run=run)


def parse_ramp(text: str) -> SpeedSchedule:
    parts = text.split(":")
    if len(parts) != 3:
        raise UsageError(f"--ramp expects FROM:TO:SECONDS, got '{text}'")
    try:
        start, end, seconds = (float(x) for x in parts)
    except ValueError:
        raise UsageError(f"--ramp expects three numbers FROM:TO:SECONDS, got '{text}'") from None
    if not all(math.isfinite(v) and v > 0.0 for v in (start, end, seconds)):
        raise UsageError(f"--ramp speeds and duration must be positive, got '{text}'")
    return SpeedSchedule.ramp(start * KMH, end * KMH, seconds)


def parse_initial(items: list[str] | None) -> np.ndarray:
    if not items:
        return initial_state()
    values: dict[str, float] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise UsageError(f"--initial expects NAME=VALUE, got '{item}'")
        if name not in STATE_NAMES:
            raise UsageError(f"unknown state '{name}' in --initial (names: {' '.join(STATE_NAMES)})")
        try:
            value = float(text)
        except ValueError:
            raise UsageError(f"--initial {name}: '{text}' is not a number") from None
        if not math.isfinite(value):
            raise UsageError(f"--initial {name} must be finite, got {text}")
        values[name] = value
    return initial_state(values)


def simulate_model(args: argparse.Namespace, schedule: SpeedSchedule, x0: np.ndarray) -> Trajectory:
    """The one place where a trajectory is made: the reduced model (scipy) or the multibody model (Exudyn)."""
    model = build_model(args)
    fidelity = build_fidelity(args)
    if fidelity is not None:
        from mbs_shimmy import simulate as simulate_mbs
        return simulate_mbs(model.params, model.effects, fidelity, operating_pressure(args), schedule, x0,
                            args.duration, dims=build_axle(args).dims, poses=bool(args.rerun))
    quiet = args.json or not sys.stderr.isatty()
    with progress(100, "simulating", quiet) as bar:
        def tick(t):
            bar.n = int(100 * t / args.duration)
            bar.refresh()
        return simulate(model, operating_pressure(args), schedule, args.duration, x0, progress=tick)


def result_json(trajectory: Trajectory, history: ModeHistory) -> dict:
    final = history.final
    return {
        "model": trajectory.model,
        "integrator": trajectory.integrator,
        "complete": trajectory.complete,
        "status": trajectory.status.value,
        "message": trajectory.message,
        "duration_s": float(trajectory.t[-1]),
        "initial_mode": history.initial.value,
        "mode_switches": [{"time_s": s.time, "speed_kmh": s.speed * 3.6, "from": s.before.value,
                           "to": s.after.value} for s in history.switches],
        "final": {"mode": history.final_mode.value, "max_theta1_deg": math.degrees(final.theta1),
                  "max_psi_deg": math.degrees(final.psi),
                  "frequency_hz": None if not np.isfinite(final.frequency_hz) else final.frequency_hz,
                  "speed_kmh": final.speed * 3.6},
    }


def schedule_json(args: argparse.Namespace) -> dict:
    """The run's inputs beyond the axle and pressures: speed schedule, duration asked, start, MBS fidelity."""
    if args.speed is not None:
        schedule = {"speed_kmh": args.speed}
    else:
        start, end, seconds = (float(x) for x in args.ramp.split(":"))
        schedule = {"ramp": {"from_kmh": start, "to_kmh": end, "seconds": seconds}}
    fidelity = build_fidelity(args)
    return {"schedule": schedule, "duration_requested_s": args.duration, "initial": list(args.initial or []),
            "fidelity": None if fidelity is None else fidelity.label}


def run(args: argparse.Namespace) -> int:
    if args.speed is not None:
        schedule = SpeedSchedule.constant(args.speed * KMH)
        default = CONSTANT_DURATION
    else:
        schedule = parse_ramp(args.ramp)
        default = schedule.ramp_time + HOLD_AFTER_RAMP
    if args.duration is None:
        args.duration = default
    x0 = parse_initial(args.initial)
    for path in (args.rerun, args.plot, args.series):
        if path:
            check_output_path(path)
    if args.series:
        from ..series import series_format
        try:
            series_format(args.series)
        except ValueError as exc:
            raise UsageError(str(exc)) from None
    trajectory = simulate_model(args, schedule, x0)
    history = ModeClassifier().classify(trajectory)
    if args.rerun:
        from ..recording import RecordingError, write_recording
        try:
            write_recording(args.rerun, trajectory, history.segments(), history.switches,
                            title=f"{trajectory.model} model, {pressure_label(args)}", model=build_model(args),
                            pressure=operating_pressure(args))
        except RecordingError as exc:
            raise UsageError(str(exc)) from None
    how = f"{args.speed:g} km/h" if args.speed is not None else f"ramp {args.ramp} (km/h:km/h:s)"
    if args.plot:
        from ..cycle_plots import MODEL_NAMES, plot_trajectory
        plot_trajectory(trajectory, history, args.plot,
                        title=f"{MODEL_NAMES.get(trajectory.model, trajectory.model)}, {pressure_label(args)}, "
                              f"{how}; {trajectory.integrator.split(',')[0]}")
    if args.series:
        from ..series import series_table, write_series
        write_series(args.series, series_table(trajectory, history.segments(),
                                               {**inputs_json(args), "schedule": how}))
    if args.json:
        emit_json({**inputs_json(args), **schedule_json(args), **result_json(trajectory, history)})
    else:
        out = result_json(trajectory, history)
        print(f"{trajectory.model} model at {pressure_label(args)}, {how}, {out['duration_s']:g} s simulated")
        print(f"  {build_axle(args).label()}")
        print(f"  integrator: {trajectory.integrator}")
        print(f"  initial mode: {out['initial_mode']}")
        for s in out["mode_switches"]:
            print(f"  switch {s['from']:>5s} -> {s['to']:5s} at t = {s['time_s']:7.2f} s, {s['speed_kmh']:7.2f} km/h")
        f = out["final"]
        freq = "-" if f["frequency_hz"] is None else f"{f['frequency_hz']:.3f} Hz"
        print(f"  final: {f['mode']}, max|theta1| {f['max_theta1_deg']:.4f} deg, max|psi| {f['max_psi_deg']:.4f} deg,"
              f" {freq} (last {ModeClassifier().window:g} s)")
        if not trajectory.complete:
            print(f"  INCOMPLETE: {trajectory.message}")
        if args.plot:
            print(f"  plot written to {args.plot}")
        if args.rerun:
            print(f"  recording written to {args.rerun}")
        if args.series:
            print(f"  time series written to {args.series}")
    if not trajectory.complete:
        sys.stderr.write(f"shimmy: incomplete: {trajectory.message}\n")
        return 3
    return 0
