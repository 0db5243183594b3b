"""``shimmy sweep``: Hopf points, assumption shifts and cycle amplitudes over a grid or a sample of inputs, on Dask."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import time

from axles.axle import interface_text
from comparisons.cli.options import (
    add_braking_options,
    add_model_options,
    add_output_options,
    add_speed_window,
    build_axle,
    emit_json,
    inputs_json,
    braking_label,
    pressure_label,
)
from comparisons.cli.progress import progress


def _count(what: str, minimum: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} must be an integer, got '{text}'") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{what} must be at least {minimum}, got {value}")
        return value
    return parse


def add_parser(sub) -> None:
    p = sub.add_parser("sweep", help="vary axle entries and pressures over a grid or a quasi-random sample, on Dask; "
                                     "results to Parquet, sensitivities, stability map, tornado chart")
    p.add_argument("--vary", action="append", metavar="NAME=SPEC", required=True,
                   help="an axle entry (units of 'shimmy params') or pressure/pressure_left/pressure_right (bar): "
                        "LO:HI:N (grid; several: full factorial), uniform:LO:HI or normal:MEAN:SD (with --samples); "
                        "repeatable")
    p.add_argument("--samples", type=_count("--samples", 1), default=None, metavar="N",
                   help="number of quasi-random samples (Saltelli design: base samples, N (D + 2) rows)")
    p.add_argument("--seed", type=_count("--seed", 0), default=0, metavar="S", help="seed of the sample (default 0)")
    p.add_argument("--design", choices=("sobol", "saltelli"), default=None,
                   help="sobol: scrambled Sobol' sequence (default); saltelli: A/AB/B matrices for Sobol' indices")
    p.add_argument("--compute", default="hopf", metavar="LIST",
                   help="comma list of hopf (reduced model, and MBS with --mbs), margins (least damping ratio of "
                        "straight running over the speed window, reduced model and the --mbs fidelities), "
                        "assumptions (each assumption's Hopf-speed shift, MBS), cycles (peak limit-cycle amplitude "
                        "of each mode); default hopf")
    p.add_argument("--mbs", default="", metavar="FIDELITIES",
                   help="also the MBS at these fidelities, comma list of reduced, full: its Hopf points (with "
                        "hopf), its own cycle branches with each Hopf point's l1 (with cycles; tens of seconds "
                        "per sample)")
    p.add_argument("--lyapunov", action="store_true", help="also each Hopf point's first Lyapunov coefficient "
                                                           "(reduced model; about doubles the Hopf cost)")
    add_model_options(p, pressure_required=False)
    add_braking_options(p)
    add_speed_window(p)
    p.add_argument("--out", default="sweep.parquet", metavar="FILE.parquet",
                   help="results, one row per sample (default sweep.parquet; schema in docs/sweeps.md)")
    p.add_argument("--resume", action="store_true", help="continue an interrupted sweep into the same --out "
                                                         "without recomputing its finished batches")
    p.add_argument("--scheduler", metavar="ADDRESS", default=None,
                   help="an existing Dask scheduler (tcp://host:8786); default: a local cluster on this machine's "
                        "cores")
    p.add_argument("--workers", type=_count("--workers", 1), default=None, metavar="N",
                   help="local cluster: worker processes (default: one per core)")
    p.add_argument("--batch-size", type=_count("--batch-size", 1), default=None, metavar="N",
                   help="samples per Dask task (default: about one second of work each)")
    p.add_argument("--output", default=None, metavar="COLUMN",
                   help="output for the sensitivities and the tornado chart (default onset_kmh, the lowest Hopf "
                        "speed; any numeric column, or a list column with an index: hopf_kmh[0])")
    add_output_options(p, plot=True)
    # --out is a file here: it takes part in the check that no two outputs name the same file (cli.main)
    p.set_defaults(run=run, file_outputs=(("out", "--out"),))


def _compute(args: argparse.Namespace) -> tuple[tuple[str, ...], tuple[str, ...]]:
    from axles.limits import UsageError
    from comparisons.sweeps.sample import COMPUTE
    compute = tuple(dict.fromkeys(s.strip() for s in args.compute.split(",") if s.strip()))
    bad = [c for c in compute if c not in COMPUTE]
    if bad or not compute:
        raise UsageError(f"--compute: unknown output '{bad[0] if bad else args.compute}' "
                         f"(known: {', '.join(COMPUTE)})")
    mbs = tuple(dict.fromkeys(s.strip() for s in args.mbs.split(",") if s.strip()))
    for f in mbs:
        if f not in ("reduced", "full"):
            raise UsageError(f"--mbs: unknown fidelity '{f}' (known: reduced, full)")
    if mbs and not {"hopf", "cycles"} & set(compute):
        raise UsageError("--mbs adds MBS Hopf points (hopf) or the MBS's own cycle branches (cycles): it needs "
                         "--compute hopf or cycles")
    return compute, mbs


def build_task(args: argparse.Namespace, names: tuple[str, ...]):
    from axles.limits import UsageError
    from comparisons.sweeps.sample import SweepTask
    from reduced_model.model import Effects
    from axles.parameters import ParameterError
    compute, mbs = _compute(args)
    try:
        effects = Effects.parse(args.effects).names
    except ParameterError as exc:
        raise UsageError(interface_text(exc)) from None
    if args.braking.active and "assumptions" in compute:
        raise UsageError("--compute assumptions is a free-rolling study (its braking rows: shimmy assumptions "
                         "--brake-slip); leave out --brake-slip/--brake-force or 'assumptions'")
    return SweepTask(axle=build_axle(args), effects=effects, pressure_right_bar=args.tyre_pressures.right_bar,
                     pressure_left_bar=args.tyre_pressures.left_bar, names=names, compute=compute, mbs=mbs,
                     vmax_kmh=args.vmax, lyapunov=args.lyapunov, braking=args.braking)


class _Progress:
    """tqdm on a terminal; plain lines on stderr otherwise (every 10 %); nothing under --json."""

    def __init__(self, total: int, quiet: bool):
        self.quiet, self.total = quiet, total
        self.tty = sys.stderr.isatty()
        self.bar = progress(total, "sweep", quiet) if self.tty else None
        self.start, self.shown = time.perf_counter(), -1

    def __call__(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if self.bar is not None:
            self.bar.total, self.bar.n = total, done
            self.bar.refresh()
            return
        tenth = (10 * done) // max(total, 1)
        if tenth > self.shown:
            self.shown = tenth
            elapsed = time.perf_counter() - self.start
            left = f", about {elapsed * (total - done) / done:.0f} s left" if 0 < done < total else ""
            sys.stderr.write(f"sweep: {done}/{total} samples, {elapsed:.0f} s{left}\n")

    def note(self, text: str) -> None:
        """What the run found and did about it (a damaged part, a stale lock): shown even under --json."""
        line = f"sweep: {text}"
        if self.bar is not None:
            self.bar.write(line, file=sys.stderr)
        else:
            sys.stderr.write(line + "\n")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _quiet_shutdown() -> None:
    """After Ctrl-C, Dask's loop thread and atexit hooks may still report the cancelled start-up: the user asked
    for the stop and has been told what was kept, so those reports are dropped."""
    import logging
    import threading
    for name in ("distributed", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)
    sys.unraisablehook = lambda unraisable: None
    threading.excepthook = lambda hook_args: None


def kept_line(what: str, out: str, argv: list[str], when: str = "") -> str:
    """One line for a sweep that stopped: ``what`` happened, which batches are kept and the exact command that
    continues (the same for Ctrl-C in the cluster's start-up as later, and for a lost scheduler or a full disk)."""
    from comparisons.sweeps.parts import MANIFEST, kept_batches, parts_folder
    parts = parts_folder(out)
    if not os.path.exists(os.path.join(parts, MANIFEST)):
        return f"{what}; nothing was kept; the same command starts again"
    resume = argv if "--resume" in argv else [*argv, "--resume"]
    return (f"{what}; {kept_batches(parts)} finished batches kept in {parts}; {when}this continues: "
            f"{shlex.join(['shimmy', *resume])}")


def run(args: argparse.Namespace) -> int:
    from comparisons.cli.main import EXIT_INCOMPLETE, EXIT_INTERRUPTED, received_signal
    from comparisons.files import OutputFault
    from comparisons.sweeps.analysis import OutputChoice, sensitivity, write_plot
    from comparisons.sweeps.cluster import SweepStopped, scheduler_address
    from comparisons.sweeps.design import make_design, parse_vary
    from comparisons.sweeps.run import run_sweep
    scheduler_address(args.scheduler)     # a bad address is refused before anything else is done
    variations = [parse_vary(v) for v in args.vary]
    design = make_design(variations, args.samples, args.seed, args.design)
    task = build_task(args, design.names)
    output = OutputChoice.parse(args.output, task)
    bar = _Progress(len(design), args.json)
    try:
        result = run_sweep(task, design, args.out, scheduler=args.scheduler, workers=args.workers,
                           size=args.batch_size, resume=args.resume, progress=bar, notice=bar.note)
    except SweepStopped as exc:
        bar.close()
        _quiet_shutdown()
        sys.stderr.write(kept_line(f"shimmy: failed: {exc.message}", args.out, args.argv) + "\n")
        return EXIT_INCOMPLETE
    except OutputFault as exc:
        bar.close()
        _quiet_shutdown()
        raise OutputFault(kept_line(exc.message, args.out, args.argv, "once there is space, ")) from None
    except BaseException as exc:
        # Ctrl-C, also where it came out as another error (raised inside Dask's start-up or an import)
        if not isinstance(exc, KeyboardInterrupt) and received_signal() != EXIT_INTERRUPTED:
            raise
        bar.close()
        _quiet_shutdown()
        sys.stderr.write(kept_line("shimmy: interrupted", args.out, args.argv) + "\n")
        return EXIT_INTERRUPTED
    finally:
        bar.close()
    sens = sensitivity(result.table, design, output)
    if args.plot:
        write_plot(args.plot, result.table, design, task, output, sens)
    if args.json:
        emit_json({**inputs_json(args), "design": design.to_json(), "run": result.to_json(),
                   "sensitivity": sens.to_json()})
        return 0
    run_ = result.to_json()
    print(f"Sweep of {len(design)} samples ({design.kind}) over {', '.join(design.names)} at {pressure_label(args)}"
          f"{braking_label(args)}, 0-{args.vmax:g} km/h")
    print(f"  {build_axle(args).label()}")
    print(f"  {run_['computed_batches']} of {run_['batches']} batches of {run_['batch_size']} computed on "
          f"{run_['workers']} workers ({run_['scheduler']}) in {run_['elapsed_s']:.1f} s; "
          f"{result.failed} failed samples; written to {args.out}")
    if result.damaged:
        print(f"  {len(result.damaged)} damaged batches computed again: {', '.join(d.name for d in result.damaged)}")
    if result.killed_batches:
        print(f"  {len(result.killed_batches)} batches killed every worker that ran them (failed rows): "
              f"{', '.join(map(str, result.killed_batches))}")
    for line in sens.lines():
        print(f"  {line}")
    if args.plot:
        print(f"  plot: {args.plot}")
    return 0
