"""A campaign of ``shimmy verify --quick`` on random axles: can its exit code gate a release on any axle?

Each axle is drawn from the paper's axle file as a new user would make one (issue 29): Table 1's vehicle entries
(:data:`VEHICLE`: inertias, stiffnesses, dampings and the geometry of the axle) each scaled by a factor uniform in
1 +- :data:`SCALE`, every chosen multibody dimension uniform in the file's own ``[plausible]`` range, and, for the
first ``--t0-axles`` of them, the pneumatic trail t0 uniform in 0.12-0.3 m (the paper's figures 8-9, where
bistable windows appear).  Dimensions with which the axle cannot exist (Table 1's I2 more than twice the wheel's
diametral inertia: no rigid wheel has that; wheels and knuckles with more roll inertia than I3; verify refuses such
an axle with exit 2) are drawn again from the same ranges.  The draws are seeded, each axle with its own stream: axle k of ``--seed`` is the same
axle in a campaign of any size.  Each axle is written as
an axle file and verified in a fresh process; the summary table gives each one's exit code, FAIL rows (section and
note), could-not-check rows and time.

    .venv/bin/python tools/verify_campaign.py --axles 8 --t0-axles 4 --seed 29 --out campaign

Exit 0 when every axle's verify exits 0, 1 otherwise, 2 on bad options.  ``--jobs`` runs that many verifies at once
(each uses about one core and a second one part of the time).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

VEHICLE = ("I1", "I2", "I3", "k1", "k2", "k3", "c1", "c2", "c3", "c4", "L", "l", "gamma")
SCALE = 0.25
T0_M = (0.12, 0.30)
TIMEOUT_S = 1800
MAX_REDRAWS = 100     # draws of the dimensions until the axle can exist (verify refuses it otherwise, exit 2)


def draw_axle(rng: np.random.Generator, name: str, t0: bool):
    """One random axle (module docstring) from the paper's axle; ``t0``: with the trail drawn from :data:`T0_M`
    (drawn either way, so that the other entries do not depend on it)."""
    import dataclasses

    from axles.axle import entries, paper_axle
    from axles.parameters import ParameterError
    base = paper_axle()
    values = {n: base.value(n) * rng.uniform(1 - SCALE, 1 + SCALE) for n in VEHICLE}
    for _ in range(MAX_REDRAWS):
        for n, e in entries().items():
            if e.section == "multibody":
                lo, hi = base.plausible_range(n)
                values[n] = rng.uniform(lo, hi)
        try:      # dimensions with which the axle cannot exist are drawn again
            exists(base.with_values(values))
            break
        except ParameterError:
            continue
    trail = rng.uniform(*T0_M)
    if t0:
        values["t0"] = trail
    return dataclasses.replace(base.with_values(values), name=name)


def exists(axle) -> None:
    """Raise :class:`axles.parameters.ParameterError` where the axle cannot exist: its dimensions cannot reproduce
    Table 1's I1 and I2 (no rigid wheel has them), or its wheels and knuckles carry more roll inertia than I3 (the
    full geometry's multibody system is built and linearised once, as verify does)."""
    from comparisons.verify.scan import Model, scan_family
    axle.dims.check(axle.params)
    family = scan_family(axle, Model.FULL)
    family.linear_matrix(10.0, family.nominal)


def campaign_axle(seed: int, number: int, t0: bool):
    """Axle ``number`` (from 1) of the campaign ``seed``: its own random stream, so that it is the same axle in a
    campaign of any size."""
    return draw_axle(np.random.default_rng((seed, number)), f"CAMPAIGN-{seed}-{number:02d}", t0)


@dataclass(frozen=True)
class Outcome:
    name: str
    t0_m: float
    exit_code: int
    fails: tuple[str, ...]          # "section: note" of each FAIL row
    unchecked: int                  # could-not-check rows
    seconds: float
    error: str = ""                 # the last line of stderr when verify gave no report

    def row(self) -> str:
        fails = "; ".join(self.fails) or ("-" if not self.error else self.error)
        return (f"| {self.name} | {self.t0_m:.3f} | {self.exit_code} | {len(self.fails)} | {self.unchecked} | "
                f"{self.seconds:.0f} | {fails.replace('|', '/')} |")


def verify_one(path: str, out: str, name: str, t0_m: float) -> Outcome:
    start = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-m", "comparisons.cli", "verify", "--quick", "--no-recordings",
                               "--axle", path, "--out", out, "--json"], capture_output=True, text=True,
                              timeout=TIMEOUT_S, cwd=ROOT)
    except subprocess.TimeoutExpired:
        return Outcome(name, t0_m, -1, (), 0, time.perf_counter() - start, f"timed out after {TIMEOUT_S} s")
    seconds = time.perf_counter() - start
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "verify-stderr.txt"), "w") as fh:    # each section's time, any error
        fh.write(proc.stderr)
    try:
        summary = json.loads(proc.stdout)
    except json.JSONDecodeError:
        last = (proc.stderr.strip().splitlines() or ["no output"])[-1]
        return Outcome(name, t0_m, proc.returncode, (), 0, seconds, last)
    rows = [(s["title"], r) for s in summary["sections"] for r in s["rows"]]
    fails = tuple(f"{title}: {r.get('note') or r.get('error')}" for title, r in rows if r["status"] == "FAIL")
    unchecked = sum(r["status"] == "could not check" for _, r in rows)
    return Outcome(name, t0_m, proc.returncode, fails, unchecked, seconds)


def run_campaign(n: int, t0_axles: int, seed: int, out: str, jobs: int = 1, say=print,
                 numbers=None) -> list[Outcome]:
    """Draw axles 1..``n`` of campaign ``seed`` (or only those in ``numbers``; the first ``t0_axles`` with t0
    drawn), write them into ``out`` and verify each."""
    from axles.axle_file import format_axle
    from comparisons.files import write_atomically
    os.makedirs(out, exist_ok=True)
    work = []
    for number in numbers or range(1, n + 1):
        axle = campaign_axle(seed, number, t0=number <= t0_axles)
        path = os.path.join(out, f"{axle.name}.toml")
        write_atomically(path, format_axle(axle))
        work.append((path, os.path.join(out, axle.name), axle.name, axle.params.t0))

    def one(item):
        got = verify_one(*item)
        say(f"{got.name}: exit {got.exit_code}, {len(got.fails)} FAIL, {got.unchecked} could not check, "
            f"{got.seconds:.0f} s")
        return got
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        return list(pool.map(one, work))


def table(outcomes: list[Outcome]) -> str:
    lines = ["| axle | t0 [m] | exit code | FAIL rows | could not check | time [s] | FAIL rows (section: note) |",
             "|---|---|---|---|---|---|---|"]
    return "\n".join(lines + [o.row() for o in outcomes])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--axles", type=int, default=8, help="how many random axles (default 8)")
    p.add_argument("--t0-axles", type=int, default=None,
                   help="how many of them (the first) get t0 drawn from 0.12-0.3 m (default: half)")
    p.add_argument("--seed", type=int, default=29, help="seed of the draws (default 29)")
    p.add_argument("--jobs", type=int, default=1, help="verifies at once (default 1)")
    p.add_argument("--out", default="verify-campaign", help="folder for the axle files and reports")
    p.add_argument("--only", type=int, nargs="+", metavar="K", help="verify only these axles (numbers from 1)")
    args = p.parse_args(argv)
    t0_axles = args.axles // 2 if args.t0_axles is None else args.t0_axles
    if args.axles < 1 or not 0 <= t0_axles <= args.axles or args.jobs < 1 or \
            any(not 1 <= k <= args.axles for k in args.only or ()):
        sys.stderr.write("verify_campaign: need --axles >= 1, 0 <= --t0-axles <= --axles, --jobs >= 1 and every "
                         "--only K in 1..--axles\n")
        return 2
    outcomes = run_campaign(args.axles, t0_axles, args.seed, args.out, args.jobs,
                            say=lambda line: print(line, file=sys.stderr, flush=True), numbers=args.only)
    text = table(outcomes)
    from comparisons.files import write_atomically
    write_atomically(os.path.join(args.out, "campaign.md"), text + "\n")
    print(text)
    return 1 if any(o.exit_code != 0 for o in outcomes) else 0


if __name__ == "__main__":
    sys.exit(main())
