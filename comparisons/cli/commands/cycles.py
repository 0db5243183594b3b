"""``shimmy cycles``: limit-cycle branches born at the Hopf points in a speed window, with their bifurcations."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from axles.axle import interface_text, interface_unit
from axles.limits import UsageError
from axles.units import KMH, kmh, to_interface
from comparisons.cli.options import (
    SECOND_PARAMETERS,
    add_model_choice,
    add_braking_options,
    add_model_options,
    braking_label,
    add_output_options,
    add_speed_window,
    build_axle,
    build_family,
    build_model,
    check_window,
    emit_json,
    inputs_json,
    positive_float,
    pressure_label,
)
from comparisons.cli.progress import progress, ticker
from bifurcation.cycle_curves.curve import cycle_bifurcation_curve
from bifurcation.cycle_curves.result import CycleCurve
from bifurcation.cycles.branches import cycle_diagram
from bifurcation.cycles.problem import CycleDiagram, CyclePoint, CycleSettings
from bifurcation.special_points import ConvergenceError, PointKind
from reduced_model.family import MIN_SPEED, SpeedFamily
from comparisons.api import family_of
from comparisons.cli.commands.cycle_json import (
    add_exudyn_residuals,
    at_json,
    curves_json,
    degrees,
    diagram_json,
    kick_row,
    largest,
    peaks,
)
from comparisons.studies.onset import read_onset

TWO_PARAMS = SECOND_PARAMETERS
DEFAULT_SETTINGS = CycleSettings()
DEFAULT_WINDOW_KMH = (0.0, 400.0)   # continuation window when --vmin = --vmax asks for one speed


def speed_list(text: str) -> tuple[float, ...]:
    """'60,80.5' -> (60.0, 80.5) km/h, each finite and at least 0.5 km/h."""
    out = []
    for item in text.split(","):
        try:
            v = float(item)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--at expects speeds in km/h separated by commas, got '{text}'") \
                from None
        if not math.isfinite(v) or v < kmh(MIN_SPEED) - 1e-12:
            raise argparse.ArgumentTypeError(f"--at {item}: speeds must be at least {kmh(MIN_SPEED):g} km/h")
        out.append(v)
    return tuple(out)


def cycle_ticker(bar):
    """An ``accept_hook`` that shows the continuation inside a branch: cycles so far, the speed reached and the
    collocation mesh (a branch of the MBS takes a minute; the bar alone counts branches)."""
    count = [0]

    def tick(cycle) -> None:
        count[0] += 1
        intervals = len(cycle.orbit.mesh) - 1 if cycle.orbit is not None else 0
        bar.set_postfix_str(f"{count[0]} cycles, at {kmh(cycle.p):.1f} km/h, {intervals} mesh intervals")
    return tick


def curve_ticker(bar, label: str, name: str):
    """An ``accept_hook`` that shows a two-parameter curve's continuation: its label, points so far and where it
    is (an MBS curve takes minutes; the bar alone counts curves)."""
    count = [0]
    unit, factor = interface_unit(name)

    def tick(cycle) -> None:
        count[0] += 1
        bar.set_postfix_str(f"{label}: {count[0]} points, at {kmh(cycle.p):.3f} km/h, {name} = "
                            f"{cycle.q / factor:.5g} {unit}")
    return tick


def add_parser(sub) -> None:
    p = sub.add_parser("cycles", help="limit cycles (shimmy amplitudes) born at the Hopf points, with their "
                                      "folds, torus and period-doubling points")
    add_model_options(p)
    add_braking_options(p)
    add_model_choice(p)
    add_speed_window(p, vmin=True)
    p.add_argument("--two-param", metavar="NAME", choices=TWO_PARAMS,
                   help="also continue every cycle fold, torus and period-doubling point in the (speed, NAME) plane "
                        f"(figures 8 and 18); NAME one of {', '.join(TWO_PARAMS)}; needs --range")
    p.add_argument("--range", nargs=2, type=float, metavar=("LO", "HI"),
                   help="window of NAME for --two-param (bar for pressure, SI otherwise)")
    p.add_argument("--at", type=speed_list, metavar="KMH[,KMH...]",
                   help="also the orbits exactly at these speeds, km/h, on every branch that passes them (located "
                        "on the branch like AUTO's user points); --vmin = --vmax = KMH asks for that speed alone")
    p.add_argument("--max-step", type=positive_float("--max-step"), metavar="KMH",
                   help="largest speed change between computed cycles, km/h (denser output)")
    p.add_argument("--tolerance", type=positive_float("--tolerance"), default=DEFAULT_SETTINGS.tolerance,
                   metavar="REL", help="collocation error allowed in every orbit, relative to each state's "
                                       f"amplitude (default {DEFAULT_SETTINGS.tolerance:g}); the mesh gains "
                                       "intervals until it is met, points that cannot meet it are marked")
    p.add_argument("--kick", action="store_true",
                   help="also, in the middle of every bistable window, the smallest initial yaw angle theta1 that "
                        "leaves the lower state, bracketed by simulations of the same model (tens of runs)")
    add_output_options(p, plot=True)
    p.set_defaults(run=run)


def _two_param_window(args: argparse.Namespace, model) -> tuple[str, float, float, float]:
    """(name, current value, lo, hi) in SI for --two-param, checked."""
    name = args.two_param
    if args.range is None:
        raise UsageError("--two-param needs --range LO HI")
    lo, hi = args.range
    unit, factor = interface_unit(name)
    check_window(lo, hi, name, unit)
    value = family_of(model, args.tyre_pressures, name, args.braking).nominal
    if not lo * factor <= value <= hi * factor:
        raise UsageError(f"--range {lo:g} {hi:g} {unit} must contain the current {name} = {value / factor:g} {unit}")
    return name, value, lo * factor, hi * factor


def _speeds(args: argparse.Namespace) -> tuple[float, float, tuple[float, ...]]:
    """(vmin, vmax, --at speeds), km/h, checked.  --vmin = --vmax = V asks for the orbits at V: the branches
    are then continued over the default window (they are born at Hopf points elsewhere)."""
    at = tuple(args.at or ())
    if args.vmin == args.vmax:
        if at and set(at) != {args.vmin}:
            raise UsageError(f"--vmin = --vmax = {args.vmin:g} km/h asks for that speed alone; --at "
                             f"{','.join(f'{v:g}' for v in at)} km/h differs")
        if args.vmin < kmh(MIN_SPEED) - 1e-12:
            raise UsageError(f"--vmin = --vmax = {args.vmin:g} km/h: cycles are computed from "
                             f"{kmh(MIN_SPEED):g} km/h on")
        return DEFAULT_WINDOW_KMH[0], max(DEFAULT_WINDOW_KMH[1], args.vmax), (args.vmin,)
    if not args.vmin < args.vmax:
        raise UsageError(f"--vmin must be below --vmax, got {args.vmin:g} and {args.vmax:g} km/h")
    outside = [v for v in at if not args.vmin <= v <= args.vmax]
    if outside:
        raise UsageError(f"--at {','.join(f'{v:g}' for v in outside)} km/h lies outside the window "
                         f"{args.vmin:g}-{args.vmax:g} km/h")
    return args.vmin, args.vmax, at


def run(args: argparse.Namespace) -> int:
    vmin_kmh, vmax_kmh, at_kmh = _speeds(args)
    if args.range is not None and args.two_param is None:
        raise UsageError("--range is only used with --two-param")
    model = build_model(args)
    if args.two_param:
        name, q, lo, hi = _two_param_window(args, model)
        family = build_family(args, name)
        family.validate(lo), family.validate(hi)
    else:
        family = build_family(args)
        q = family.nominal
    family.validate(q)
    vmin, vmax = vmin_kmh * KMH, vmax_kmh * KMH
    quiet = args.json or not sys.stderr.isatty()
    options = {"at": tuple(v * KMH for v in at_kmh),
               "max_step": args.max_step * KMH if args.max_step else None}
    if args.tolerance != DEFAULT_SETTINGS.tolerance:
        options["settings"] = CycleSettings(tolerance=args.tolerance)
    with progress(1, "cycle branches", quiet) as bar:
        diagram = cycle_diagram(family, q, vmin, vmax, progress=ticker(bar), accept_hook=cycle_ticker(bar),
                                **options)
    unstable = unstable_without_hopf(diagram, family, q)
    found_kicks = []
    if args.kick:
        from comparisons.studies.kick import kicks
        with progress(None, "kick thresholds: runs", quiet) as bar:
            found_kicks = kicks(family, diagram, progress=lambda text: (bar.set_postfix_str(text, refresh=False),
                                                                        bar.update(1)))
    curves: list[tuple[CycleCurve | None, str]] = []
    labels: list[str] = []
    same_curve: dict[str, str] = {}     # a point's label: the label of the computed curve it lies on
    if args.two_param:
        from comparisons.figures.cycle_plots import special_point_labels
        chosen = [(text, p) for text, p in special_point_labels(diagram)
                  if p.kind in (PointKind.CYCLE_FOLD, PointKind.TORUS, PointKind.PERIOD_DOUBLING)]
        with progress(len(chosen), "bifurcation curves", quiet) as bar:
            for text, p in chosen:
                on = next((label for (c, _), label in zip(curves, labels) if c is not None and c.passes(p)), None)
                if on is not None:       # its curve is computed already: one curve through two of the branch's folds
                    same_curve[text] = on
                    bar.update(1)
                    continue
                try:
                    # the branch's settings: its tolerance is what the curve's points are checked against
                    curves.append((cycle_bifurcation_curve(family, p, lo, hi, vmin, vmax,
                                                           options.get("settings", DEFAULT_SETTINGS),
                                                           accept_hook=curve_ticker(bar, text, name)), ""))
                except ConvergenceError as exc:
                    curves.append((None, f"newton_failed: {interface_text(exc)}"))
                labels.append(text)
                bar.update(1)
    if args.plot:
        if args.two_param:
            from comparisons.figures.cycle_plots import plot_cycle_curves
            from bifurcation.equilibria.hopf_curves import hopf_diagram
            plot_cycle_curves(hopf_diagram(family, lo, hi, vmin, vmax), [c for c, _ in curves], labels, family,
                              args.plot)
        else:
            from comparisons.figures.cycle_plots import plot_cycle_diagram
            effects = ",".join(model.effects.names) or "section 3 tyre"
            plot_cycle_diagram(diagram, family, args.plot, kicks=found_kicks,
                               title=f"Limit cycles at {pressure_label(args)}{braking_label(args)} "
                                     f"({model_text(args, family)}, "
                                     f"{effects}); solid stable, dashed unstable")
    factor = interface_unit(args.two_param)[1] if args.two_param else 1.0
    # every reported curve point of the MBS checked on Exudyn's own right-hand side (the curves ran on its twin)
    checks = None
    if args.model == "mbs" and curves:
        from comparisons.studies.exudyn_check import curve_on_exudyn
        checks = [None if c is None else curve_on_exudyn(family, c) for c, _ in curves]
    if args.json:
        out = diagram_json(diagram, family, to_interface(args.tyre_pressures.value("pressure"), "Pa"), model.effects.names)
        del out["pressure_bar"], out["effects"]
        out = {**inputs_json(args), **out}
        if args.model == "mbs":
            out["model"], out["fidelity"] = "mbs", family.model.fidelity.label
            add_exudyn_residuals(out, diagram, family)
        out.update({"tolerance": args.tolerance, "max_step_kmh": args.max_step,
                    "all_meet_tolerance": not inaccurate(diagram)})
        if at_kmh:
            out["at"] = at_json(diagram, at_kmh, family)
        if args.kick:
            out["kicks"] = [kick_row(k) for k in found_kicks]
            out["complete"] = out["complete"] and all(k.status.is_complete for k in found_kicks)
        if unstable is not None:
            out["complete"], out["note"] = False, unstable
        if args.two_param:
            out["two_param"] = {"param": args.two_param, "unit": interface_unit(args.two_param)[0],
                                "curves": curves_json(curves, labels, factor, checks), "same_curve": same_curve}
            out["complete"] = out["complete"] and all(c is not None and c.complete for c, _ in curves)
        emit_json(out)
    else:
        args.vmin, args.vmax = vmin_kmh, vmax_kmh    # the continuation window, for the header
        print_diagram(diagram, family, args)
        if at_kmh:
            print_at(diagram, at_kmh)
        if args.kick:
            print_kicks(found_kicks)
        if args.two_param:
            print_curves(curves, labels, args.two_param, checks)
            for text, on in same_curve.items():
                print(f"    {text:4s} lies on {on}'s curve: not continued again")
    problems = [f"branch from {kmh(b.start.p):.3f} km/h stopped: {interface_text(b.message)}"
                for b in diagram.branches if not b.complete]
    if unstable is not None:
        problems.append(unstable)
    problems += [f"kick at {k.speed / KMH:.2f} km/h: {k.status.value}" for k in found_kicks
                 if not k.status.is_complete]
    problems += [f"curve {label}: " + (error or "; ".join(interface_text(m) for m, s in zip(c.messages, c.status)
                                                         if not s.is_complete))
                 for (c, error), label in zip(curves, labels) if c is None or not c.complete]
    problems += [f"curve {label}: {check.text()}" for check, label in zip(checks or (), labels)
                 if check is not None and check.failing]
    missed = inaccurate(diagram)
    if missed:
        first = missed[0]
        sys.stderr.write(f"shimmy: warning: {len(missed)} cycles miss the error tolerance {args.tolerance:g} "
                         f"(marked in the output), first at {kmh(first.p):.3f} km/h on "
                         f"{len(first.orbit.mesh) - 1} mesh intervals (at most {DEFAULT_SETTINGS.max_intervals})\n")
    if problems:
        sys.stderr.write("shimmy: incomplete: " + "; ".join(problems) + "\n")
        return 3
    return 0


def print_kicks(found) -> None:
    if not found:
        print("  kicks: no bistable window in the speed window")
    for k in found:
        print(f"  kick at {k.speed / KMH:.2f} km/h: theta1 {degrees(k.stays):.3f} deg stays on the "
              f"{k.lower.label}, {degrees(k.leaves):.3f} deg leaves for the {k.upper.label} ({k.status.value}, "
              f"{k.runs} runs; the unstable cycle between has max|theta1| {degrees(k.unstable_theta1):.3f} deg)")


def inaccurate(diagram: CycleDiagram) -> list[CyclePoint]:
    return [p for b in diagram.branches for p in (*b.points, *b.user_points) if not p.meets_tolerance]


def print_at(diagram: CycleDiagram, speeds_kmh) -> None:
    print("  orbits at the requested speeds (located on the branches):")
    for v in speeds_kmh:
        rows = [(i, p) for i, b in enumerate(diagram.branches) for p in b.user_points
                if abs(kmh(p.p) - v) <= 1e-9 * max(1.0, v)]
        if not rows:
            print(f"    {v:g} km/h: no branch in the window passes this speed")
        for i, p in rows:
            mu = largest(p.multipliers)
            flag = "" if p.meets_tolerance else f"  [error estimate {p.error:.1e} above tolerance]"
            print(f"    {v:g} km/h, branch {i}: period {p.period:.6f} s ({p.frequency_hz:.5f} Hz), "
                  f"max|theta1| {degrees(p.max_abs('theta1')):.5f} deg, max|theta2| "
                  f"{degrees(p.max_abs('theta2')):.5f} deg, max|psi| {degrees(p.max_abs('psi')):.5f} deg, "
                  f"largest multiplier |mu| {abs(mu):.6f}, {'stable' if p.stable else 'unstable'}{flag}")
            print("      multipliers: " + ", ".join(f"{m.real:.6g}{m.imag:+.6g}i" for m in p.multipliers))


def unstable_without_hopf(diagram: CycleDiagram, family: SpeedFamily, q: float) -> str | None:
    """Why an empty diagram is not 'no shimmy': straight running unstable with its Hopf points outside the window."""
    if diagram.hopf:
        return None
    # From MIN_SPEED: at V = 0 the slip equations have zero eigenvalues that round-off can put on either side.
    speeds = np.linspace(max(diagram.p_min, MIN_SPEED), diagram.p_max, 81)
    bad = [V for V in speeds if np.max(np.linalg.eigvals(family.linear_matrix(V, q)).real) > 1e-9]
    if not bad:
        return None
    return (f"straight running is unstable at {kmh(min(bad)):.1f}-{kmh(max(bad)):.1f} km/h but no Hopf point lies "
            f"in the window: the shimmy cycles there are born outside it (widen --vmin/--vmax)")


def print_curves(curves, labels, name: str, checks=None) -> None:
    unit, factor = interface_unit(name)
    print(f"  two-parameter curves in (V, {name}):")
    for i, ((curve, error), label) in enumerate(zip(curves, labels)):
        if curve is None:
            print(f"    {label:4s} [INCOMPLETE] {error}")
            continue
        flag = "" if curve.complete else "  [INCOMPLETE]"
        print(f"    {label:4s} {curve.kind.value:10s} {len(curve.ps)} points, {name} "
              f"{curve.qs.min() / factor:.6g}-{curve.qs.max() / factor:.6g} {unit}{flag}")
        for message in curve.messages:
            print(f"         end: {interface_text(message)}")
        theta1 = np.degrees(curve.amplitudes[:, 0])
        print(f"         critical cycles: max|theta1| {theta1.min():.3g}-{theta1.max():.3g} deg")
        for p in curve.special_points:
            print(f"         {p.kind.value} at {kmh(p.p):.4f} km/h, {name} {p.q / factor:.6g} {unit} "
                  f"({p.status.value})")
        if curve.corners:
            dv = max(abs(kmh(c.after[0] - c.before[0])) for c in curve.corners)
            dq = max(abs(c.after[1] - c.before[1]) for c in curve.corners) / factor
            print(f"         stepped over {len(curve.corners)} gap(s) where a collocation node crosses a kink of the "
                  f"right-hand side (the largest step: {dv:.3g} km/h, {name} {dq:.3g} {unit})")
        check = checks[i] if checks else None
        if check is not None:
            print(f"         {check.text()}")


def model_text(args: argparse.Namespace, family) -> str:
    """Which model the command ran, for its header and its plot."""
    return f"MBS, fidelity {family.model.fidelity.label}" if args.model == "mbs" else "reduced model"


def print_diagram(diagram: CycleDiagram, family: SpeedFamily, args: argparse.Namespace) -> None:
    from comparisons.figures.cycle_plots import special_point_labels

    effects = ",".join(build_model(args).effects.names) or "none (section 3 model)"
    print(f"Limit cycles at {pressure_label(args)}{braking_label(args)}, {args.vmin:g}-{args.vmax:g} km/h ({model_text(args, family)}), "
          f"pressure effects: {effects}")
    print(f"  {build_axle(args).label()}")
    if not diagram.hopf:
        unstable = unstable_without_hopf(diagram, family, diagram.q)
        print(f"  [INCOMPLETE] {unstable}" if unstable else
              "  no Hopf point in the window and straight running stable throughout: no shimmy")
    labels = {id(p): text for text, p in special_point_labels(diagram)}
    for b in diagram.branches:
        onset = read_onset(family, b.start, diagram)
        crit = onset.criticality.value if onset.criticality else "criticality unknown"
        head = f"  branch from HB at {kmh(b.start.p):.3f} km/h ({b.start.frequency_hz:.3f} Hz, {crit}" \
               f"{'' if onset.by == 'l1' else ' by its ' + onset.by}" \
               f"{', ' + onset.kind + ' onset' if onset.kind else ''}): {len(b.points)} cycles"
        print(head + ("" if b.complete else "  [INCOMPLETE]"))
        if onset.by != "l1" and onset.detail:
            print(f"    onset: {onset.detail}")
        print(f"    end: {interface_text(b.message)}")
        if not b.points:
            continue
        peak = peaks(family, b)
        lo, hi = b.frequency_range
        stable = sum(p.stable for p in b.points)
        print(f"    peak max|theta1| {peak['theta1']['max_deg']:.4f} deg at {peak['theta1']['speed_kmh']:.2f} km/h,"
              f" peak max|psi| {peak['psi']['max_deg']:.4f} deg at {peak['psi']['speed_kmh']:.2f} km/h")
        print(f"    frequency {lo:.3f}-{hi:.3f} Hz; {stable} of {len(b.points)} cycles stable")
        for s in sorted(b.special_points, key=lambda s: s.bracket[0]):
            amp = s.data["amplitude"]
            print(f"    {labels[id(s)]:4s} {s.kind.value:16s} {kmh(s.p):10.3f} km/h  "
                  f"max|theta1| {degrees(amp[0]):7.3f} deg  max|psi| {degrees(amp[4]):6.3f} deg  "
                  f"({s.status.value})")
    if args.plot:
        print(f"  plot written to {args.plot}")
