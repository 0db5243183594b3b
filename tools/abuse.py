"""Try the ``shimmy`` command as a careless or unlucky user would, and count what happens.

Every case runs ``python -m comparisons.cli ...`` in a fresh process with a time limit and is classified:

* **clean**: the expected exit code (2 bad input, 74 write fault, 0/3 for inputs inside the ranges), at most one
  line on stderr, no traceback, no temporary file left, no device replaced;
* **traceback**: a Python traceback on stderr (or exit 1 outside ``verify``);
* **hang**: still running at the time limit (killed);
* **nonsense**: exit 0 where a refusal or a fault was due, or a non-finite number in the JSON;
* **other**: anything else (wrong code, several lines, a temporary file left, a device replaced).

The catalogue: ``--set`` with absurd, tiny, huge and non-numbers for every axle entry; pressures, speeds, speed
windows, durations, ramps, initial states and parameter windows at and beyond their ranges; output paths (empty,
a folder, a missing folder, too long, a temporary name too long, non-UTF-8, the same file twice, devices, a
read-only and a full file system when a small tmpfs can be mounted, i.e. as root); stdout full, closed and a
broken pipe; SIGINT and SIGTERM during a run; and ``shimmy sweep`` against real Dask processes started here, with
its scheduler or a worker killed, parts damaged or foreign, its ``--out`` busy or its lock stale, a batch that kills
its workers, a full disk and Ctrl-C while the local cluster starts (:mod:`abuse_sweeps`).  Usage: ``python tools/abuse.py [--quick] [--jobs N] [--json]``;
exit 0 when no case is a traceback, a hang or nonsense.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import json
import math
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Callable

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from abuse_sweeps import Lab, sweep_cases  # noqa: E402  (beside this file; it needs ROOT on the path)

SHIMMY = [sys.executable, "-m", "comparisons.cli"]
FAST = ["hopf", "--pressure", "2.5", "--vmax", "200", "--json"]          # about a second
TIMEOUT_S = 120.0


@dataclass
class Case:
    name: str
    argv: list[str]
    expect: tuple[int, ...]                 # acceptable exit codes
    stdout: str = "pipe"                    # pipe | full | closed | broken
    signal_after: float | None = None       # send SIGINT/SIGTERM after this many seconds
    signum: int = signal.SIGINT
    watch: tuple[str, ...] = ()             # folders that must hold no temporary file afterwards
    devices: tuple[str, ...] = ()           # paths that must still be character devices afterwards
    must_exist: tuple[str, ...] = ()        # files the run must have written
    needs: str = ""                         # "tmpfs" when the case needs the mounted file systems
    timeout: float | None = None            # a longer time limit than --timeout (verify)
    makedirs: tuple[str, ...] = ()          # folders to create just before the run (inside the mounts)
    # Sweep faults (tools/abuse_sweeps.py): cases run one after the other, in order, each prepared by ``before``;
    # ``during(proc)`` injects the fault into the running command and returns when it did (time.monotonic());
    # ``within``: seconds the command may take after that; ``check(stdout, stderr)`` says what is wrong, or "".
    serial: bool = False
    before: Callable[[], None] | None = None
    during: Callable[[subprocess.Popen], float] | None = None
    within: float | None = None
    check: Callable[[bytes, str], str] | None = None


@dataclass
class Outcome:
    case: Case
    verdict: str
    code: int | None
    seconds: float
    detail: str = ""
    stderr: str = field(default="", repr=False)


def _json_has_nonfinite(text: str) -> bool:
    try:
        json.loads(text, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
    except ValueError:
        return True
    return False


def run_case(case: Case, timeout: float = TIMEOUT_S) -> Outcome:
    env = dict(os.environ, PYTHONPATH=ROOT, COLUMNS="200")
    for folder in case.makedirs:
        os.makedirs(folder, exist_ok=True)
    start = time.monotonic()
    if case.before is not None:
        try:
            case.before()
        except Exception as exc:  # noqa: BLE001 - a case that cannot be prepared is reported, the rest go on
            return _finish(case, "other", None, start, b"", f"preparation failed: {type(exc).__name__}: {exc}")
    preexec = None
    stdout = subprocess.PIPE
    opened = None
    if case.stdout == "full":
        opened = stdout = open("/dev/full", "wb")
    elif case.stdout == "closed":
        preexec = lambda: os.close(1)  # noqa: E731
        stdout = None
    proc = subprocess.Popen(SHIMMY + case.argv, stdout=stdout, stderr=subprocess.PIPE, env=env, cwd=ROOT,
                            preexec_fn=preexec)
    if case.stdout == "broken":
        proc.stdout.close()
        proc.stdout = None
    out = b""
    hang = False
    injected = None
    try:
        if case.during is not None:
            injected = case.during(proc)
        if case.signal_after is not None:
            time.sleep(case.signal_after)
            sent = time.monotonic()
            proc.send_signal(case.signum)
            try:
                out, err = proc.communicate(timeout=5.0)
            except subprocess.TimeoutExpired:
                hang = True
            else:
                if time.monotonic() - sent > 1.0:
                    return _finish(case, "other", proc.returncode, start, err,
                                   f"took {time.monotonic() - sent:.2f} s after the signal")
        else:
            out, err = proc.communicate(timeout=case.timeout or timeout)
    except subprocess.TimeoutExpired:
        hang = True
    finally:
        if opened is not None:
            opened.close()
    if hang:
        proc.kill()
        _, err = proc.communicate()
        return _finish(case, "hang", None, start, err, "killed at the time limit")
    out = out or b""
    text = err.decode("utf-8", "replace")
    code = proc.returncode
    if "Traceback (most recent call last)" in text or (code == 1 and case.argv[:1] != ["verify"]):
        return _finish(case, "traceback", code, start, err, text.strip().splitlines()[-1] if text.strip() else "")
    refusal_due = all(c != 0 for c in case.expect)
    if code == 0 and refusal_due:
        return _finish(case, "nonsense", code, start, err, "exit 0 where a refusal was due")
    if "--json" in case.argv and code in (0, 3) and out.strip() and _json_has_nonfinite(out.decode("utf-8", "replace")):
        return _finish(case, "nonsense", code, start, err, "NaN or Infinity in the JSON")
    problems = []
    if code not in case.expect:
        problems.append(f"exit {code}, expected {'/'.join(map(str, case.expect))}")
    # Progress lines of long commands ("verify: [3/7] ...", "sweep: ...") are not messages.
    lines = [ln for ln in text.splitlines() if ln.strip() and not re.match(r"(verify|sweep|figures): ", ln)]
    if len(lines) > 1:
        problems.append(f"{len(lines)} lines on stderr")
    if code != 0 and not lines:
        problems.append("no line on stderr")
    if injected is not None and case.within is not None and time.monotonic() - injected > case.within:
        problems.append(f"took {time.monotonic() - injected:.2f} s after the fault, more than {case.within:g} s")
    if case.check is not None:
        problem = case.check(out, text)
        if problem:
            problems.append(problem)
    for folder in case.watch:
        left = [n for n in os.listdir(folder) if n.endswith(".tmp")] if os.path.isdir(folder) else []
        if left:
            problems.append(f"temporary files left in {folder}: {left[:3]}")
    for dev in case.devices:
        if not stat.S_ISCHR(os.stat(dev).st_mode):
            problems.append(f"{dev} is no longer a device")
    for path in case.must_exist:
        if not os.path.exists(path):
            problems.append(f"{path!r} was not written")
    return _finish(case, "other" if problems else "clean", code, start, err, "; ".join(problems))


def _finish(case, verdict, code, start, err, detail) -> Outcome:
    return Outcome(case, verdict, code, time.monotonic() - start, detail,
                   err.decode("utf-8", "replace") if isinstance(err, bytes) else (err or ""))


# --- the catalogue ---------------------------------------------------------------------------------------------

def set_cases(quick: bool) -> list[Case]:
    from axles.axle import entries
    cases = []
    values = ["1e308", "1e-300", "-1e308", "nan", "inf", "abc", ""] if not quick else ["1e308", "1e-300", "nan"]
    for name, e in entries().items():
        lo, hi = e.range
        for text in values:
            try:
                v = float(text)
                inside = math.isfinite(v) and lo <= v <= hi
            except ValueError:
                inside = False
            cases.append(Case(f"--set {name}={text}", FAST + ["--set", f"{name}={text}"],
                              (0, 3) if inside else (2,)))
        if not quick:   # just outside each end of the physical range
            for v in (lo - max(abs(lo), 1.0) * 0.5, hi + max(abs(hi), 1.0) * 0.5):
                cases.append(Case(f"--set {name}={v:g}", FAST + ["--set", f"{name}={v!r}"], (2,)))
    return cases


def input_cases() -> list[Case]:
    R, O = (2,), (0, 3)
    sim = ["simulate", "--pressure", "2.5"]
    c = []
    for p in ["0", "-1", "1e-300", "0.049", "20.1", "1e308", "nan", "inf", "-inf", "abc", "", "0x10"]:
        c.append(Case(f"--pressure {p}", ["hopf", "--pressure", p, "--json"], R))
    for p in ["0.05", "20"]:
        c.append(Case(f"--pressure {p}", ["hopf", "--pressure", p, "--vmax", "200", "--json"], O + (2,)))
    c += [Case("--pressure-left alone", ["hopf", "--pressure-left", "2"], R),
          Case("--pressure-right 1e-300", ["hopf", "--pressure", "2", "--pressure-right", "1e-300"], R),
          Case("--pressure-left 1.5 --pressure-right 2.5", ["hopf", "--pressure-left", "1.5", "--pressure-right",
                                                             "2.5", "--vmax", "200", "--json"], O)]
    for v in ["0", "0.5", "-5", "1e308", "nan", "inf", "abc", "1e-300"]:
        c.append(Case(f"hopf --vmax {v}", ["hopf", "--pressure", "2.5", "--vmax", v], R))
    c.append(Case("hopf --vmax 0.51", ["hopf", "--pressure", "2.5", "--vmax", "0.51", "--json"], O))
    for lo, hi in [("0", "0.5"), ("0.1", "0.4"), ("300", "200"), ("0", "1e308"), ("-1", "100"), ("nan", "100"),
                   ("0.2", "0.2")]:
        c.append(Case(f"cycles --vmin {lo} --vmax {hi}", ["cycles", "--pressure", "2.5", "--vmin", lo, "--vmax", hi],
                      R))
    for v in ["0", "0.4", "1e308", "1e-300", "-3", "nan", "inf", "1001", "abc"]:
        c.append(Case(f"simulate --speed {v}", sim + ["--speed", v, "--duration", "0.5"], R))
    for d in ["0", "1e-300", "1e308", "0.005", "nan", "-1", "1001", "inf"]:
        c.append(Case(f"simulate --duration {d}", sim + ["--speed", "60", "--duration", d], R))
    c.append(Case("simulate --duration 0.01", sim + ["--speed", "60", "--duration", "0.01", "--json"], O))
    for r in ["100:200:1e308", "100:200:0", "100:200:1e-300", "0:100:10", "1e308:100:10", "100:nan:10", "100:200",
              "a:b:c", "100:200:10:5", ":::", ""]:
        c.append(Case(f"simulate --ramp {r!r}", sim + ["--ramp", r, "--duration", "1"], R))
    for i in ["theta1=1e308", "theta1=46", "theta1=-46", "psi_dot=2e4", "theta1=nan", "theta1=inf", "theta1=x",
              "theta1=", "=1", "phi=1", "theta1"]:
        c.append(Case(f"simulate --initial {i}", sim + ["--speed", "60", "--duration", "0.5", "--initial", i], R))
    c.append(Case("simulate --initial theta1=45 (degrees)", sim + ["--speed", "60", "--duration", "0.5",
                                                                  "--initial", "theta1=45", "--json"], O))
    c.append(Case("simulate k1=1e8 I1=0.1 (7 kHz mode)", sim + ["--speed", "100", "--set", "k1=1e8", "--set",
                                                               "I1=0.1"], R))
    for lo, hi in [("1e-300", "1e308"), ("nan", "1"), ("0", "1"), ("-1", "1"), ("1", "1"), ("2", "1"),
                   ("0.01", "3")]:
        c.append(Case(f"curves --param pressure --range {lo} {hi}",
                      ["curves", "--param", "pressure", "--range", lo, hi, "--vmax", "100"], R))
    c.append(Case("curves --param t0 --range 1e-300 1e308", ["curves", "--param", "t0", "--range", "1e-300",
                                                              "1e308"], R))
    c.append(Case("cycles --two-param t0 --range 1e-300 1e308", ["cycles", "--pressure", "2.5", "--two-param",
                                                                  "t0", "--range", "1e-300", "1e308"], R))
    c += [Case("figures --only 99", ["figures", "--only", "99"], R),
          Case("figures --only x", ["figures", "--only", "x"], R),
          Case("figures --jobs 0", ["figures", "--only", "2", "--jobs", "0"], R),
          Case("--effects bogus", ["hopf", "--pressure", "2", "--effects", "bogus"], R),
          Case("--axle missing", ["hopf", "--pressure", "2", "--axle", "/nonexistent/a.toml"], R),
          Case("--axle a folder", ["hopf", "--pressure", "2", "--axle", "/tmp"], R),
          Case("--axle not TOML", ["hopf", "--pressure", "2", "--axle", "/etc/hostname"], R),
          Case("no command", [], R),
          Case("unknown command", ["frobnicate"], R),
          Case("bench nosuch", ["bench", "nosuch"], R),
          Case("caster 10 rad (573 deg)", FAST + ["--set", "gamma=573"], R),
          Case("caster -10 rad", FAST + ["--set", "gamma=-573"], R),
          Case("f = 5", FAST + ["--set", "f=5"], R)]
    return c


def output_cases(scratch: str, quick: bool) -> list[Case]:
    R, O, W = (2,), (0,), (74,)
    sim = ["simulate", "--pressure", "2.5", "--speed", "60", "--duration", "0.3"]
    count = [0]

    def fresh() -> str:
        """A folder of its own per case: cases run two at a time."""
        count[0] += 1
        path = os.path.join(scratch, f"case{count[0]}")
        os.makedirs(path)
        return path
    d = [fresh() for _ in range(8)]
    long_name = os.path.join(d[0], "x" * 252 + ".png")        # 256 bytes: too long
    fits = os.path.join(d[1], "y" * 247 + ".png")             # 251 bytes: fits, its temporary name would not
    odd = os.path.join(d[2], os.fsdecode(b"\xff\xfe-run.rrd"))
    odd_png = os.path.join(d[3], os.fsdecode(b"plot-\xe9.png"))
    c = [Case("--plot ''", sim + ["--plot", ""], R),
         Case("--rerun ''", sim + ["--rerun", ""], R),
         Case("--plot '  '", sim + ["--plot", "  "], R),
         Case("--plot a folder", sim + ["--plot", d[4]], R, watch=(d[4],)),
         Case("--plot folder/", sim + ["--plot", d[5] + "/"], R),
         Case("--plot missing folder", sim + ["--plot", os.path.join(d[5], "no", "x.png")], R),
         Case("--plot name 256 bytes", sim + ["--plot", long_name], R, watch=(d[0],)),
         Case("--plot name 251 bytes (temporary name longer)", sim + ["--plot", fits], O, watch=(d[1],),
              must_exist=(fits,)),
         Case("--rerun non-UTF-8 name", sim + ["--rerun", odd], O, watch=(d[2],), must_exist=(odd,)),
         Case("--plot non-UTF-8 name", sim + ["--plot", odd_png], O, watch=(d[3],), must_exist=(odd_png,)),
         Case("--plot F --rerun F", sim + ["--plot", os.path.join(d[6], "same"), "--rerun",
                                           os.path.join(d[6], "same")], R, watch=(d[6],)),
         Case("--plot /dev/full", sim + ["--plot", "/dev/full"], W, devices=("/dev/full",)),
         Case("--rerun /dev/full", sim + ["--rerun", "/dev/full"], R, devices=("/dev/full",)),
         Case("--rerun /dev/null", sim + ["--rerun", "/dev/null"], R, devices=("/dev/null",)),
         Case("--plot /dev/null", sim + ["--plot", "/dev/null"], O, devices=("/dev/null",)),
         Case("params --write ''", ["params", "--write", ""], R),
         Case("params --write folder", ["params", "--write", d[7]], R),
         Case("params --write /dev/full", ["params", "--write", "/dev/full"], W, devices=("/dev/full",)),
         Case("figures --out a file", ["figures", "--only", "2", "--out", "/etc/hostname"], R),
         Case("verify --out a file", ["verify", "--quick", "--out", "/etc/hostname"], R),
         Case("params > /dev/full", ["params"], W, stdout="full"),
         Case("params --json > /dev/full", ["params", "--json"], W, stdout="full"),
         Case("hopf > /dev/full", ["hopf", "--pressure", "2.5", "--vmax", "100"], W, stdout="full"),
         Case("params >&- (closed)", ["params"], W, stdout="closed"),
         Case("params | (reader gone)", ["params"], W, stdout="broken"),
         Case("hopf --json | (reader gone)", ["hopf", "--pressure", "2.5", "--vmax", "100", "--json"], W,
              stdout="broken"),
         ]
    ro, full, tiny = (os.path.join(scratch, n) for n in ("ro", "full", "tiny"))
    c += [Case("--plot on a read-only mount", sim + ["--plot", os.path.join(ro, "x.png")], R, needs="tmpfs"),
          Case("--rerun on a read-only mount", sim + ["--rerun", os.path.join(ro, "x.rrd")], R, needs="tmpfs"),
          Case("params --write on a read-only mount", ["params", "--write", os.path.join(ro, "a.toml")], R,
               needs="tmpfs"),
          Case("figures --out on a read-only mount", ["figures", "--only", "2", "--out", os.path.join(ro, "f")], R,
               needs="tmpfs"),
          Case("verify --out on a read-only mount", ["verify", "--quick", "--out", os.path.join(ro, "r")], R,
               needs="tmpfs")]
    runs = 3 if quick else 10
    for k in range(runs):
        own = os.path.join(full, f"run{k}")   # a folder per case: two run at a time
        c.append(Case(f"simulate --rerun onto a full disk #{k + 1}",
                      ["simulate", "--pressure", "2.5", "--speed", "60", "--duration", "5", "--rerun",
                       os.path.join(own, "a.rrd")], W, watch=(own,), needs="tmpfs", makedirs=(own,)))
    c += [Case("--plot onto a full disk", sim + ["--plot", os.path.join(tiny, "big.png")], W, watch=(tiny,),
               needs="tmpfs"),
          Case("params --write onto a full disk", ["params", "--write", os.path.join(tiny, "a.toml")], R + W,
               watch=(tiny,), needs="tmpfs"),
          Case("figures onto a full disk", ["figures", "--only", "2", "--out", tiny], R + W, watch=(tiny,),
               needs="tmpfs"),
          ]
    if not quick:   # minutes: the first recording of verify fills the disk
        c.append(Case("verify --quick onto a full disk", ["verify", "--quick", "--out", os.path.join(full, "rep")],
                      R + W, watch=(os.path.join(full, "rep"),), needs="tmpfs", timeout=1200.0))
    return c


def signal_cases(scratch: str, quick: bool) -> list[Case]:
    # A tramp limit cycle at 180 km/h: LSODA cannot take long steps, 1000 s take minutes.
    long_sim = ["simulate", "--pressure", "1.5", "--set", "t0=0.25", "--speed", "180", "--duration", "1000",
                "--plot", os.path.join(scratch, "sig.png")]
    c = []
    for after in ((0.3, 1.5) if quick else (0.2, 0.8, 1.5, 3.0)):
        c.append(Case(f"SIGINT at {after} s of simulate", long_sim, (130,), signal_after=after, watch=(scratch,)))
        c.append(Case(f"SIGTERM at {after} s of simulate", long_sim, (143,), signal_after=after,
                      signum=signal.SIGTERM, watch=(scratch,)))
    if not quick:
        for after in (2.0, 6.0):
            c.append(Case(f"SIGINT at {after} s of verify --quick",
                          ["verify", "--quick", "--out", os.path.join(scratch, "rep")], (130,), signal_after=after,
                          watch=(os.path.join(scratch, "rep"),)))
            c.append(Case(f"SIGTERM at {after} s of figures",
                          ["figures", "--jobs", "2", "--out", os.path.join(scratch, "figs")],
                          (143,), signal_after=after, signum=signal.SIGTERM, watch=(os.path.join(scratch, "figs"),)))
    return c


@contextlib.contextmanager
def mounts(scratch: str):
    """A read-only, a 256 kB and a filled 64 kB tmpfs under ``scratch``; yields the reason when they cannot be made."""
    made = []
    reason = ""
    try:
        for name, opts in (("ro", "ro,size=64k"), ("full", "size=256k"), ("tiny", "size=64k"),
                           ("sweepdisk", "size=64k")):
            path = os.path.join(scratch, name)
            os.makedirs(path)
            r = subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", path], capture_output=True, text=True)
            if r.returncode != 0:
                reason = f"cannot mount a tmpfs ({r.stderr.strip() or 'not root'})"
                break
            made.append(path)
        if not reason:
            with open(os.path.join(scratch, "tiny", "filler"), "wb") as f, contextlib.suppress(OSError):
                f.write(b"\0" * 65536)
                f.flush()
        yield reason
    finally:
        for path in made:
            subprocess.run(["umount", "-l", path], capture_output=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a smaller catalogue (about a third)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=TIMEOUT_S)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--only", default="", help="run the cases whose name contains this text")
    a = ap.parse_args(argv)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))   # unmount and clean up when stopped
    scratch = tempfile.mkdtemp(prefix="shimmy-abuse-")
    lab = Lab(scratch)
    try:
        with mounts(scratch) as no_tmpfs:
            cases = (set_cases(a.quick) + input_cases() + output_cases(scratch, a.quick)
                     + signal_cases(scratch, a.quick))
            sweeps = sweep_cases(scratch, Case, lab, None if no_tmpfs else os.path.join(scratch, "sweepdisk"))
            if no_tmpfs:
                sweeps.append(Case("sweep onto a full disk", [], (74,), needs="tmpfs"))
            cases += sweeps
            skipped = [c for c in cases if c.needs == "tmpfs" and no_tmpfs]
            cases = [c for c in cases if c not in skipped and a.only in c.name]
            # Signal cases are timed: run them alone, after the rest; sweep faults are a story, told in order.
            timed = [c for c in cases if c.signal_after is not None]
            serial = [c for c in cases if c.serial]
            rest = [c for c in cases if c.signal_after is None and not c.serial]
            with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
                outcomes = list(pool.map(lambda c: run_case(c, a.timeout), rest))
            outcomes += [run_case(c, a.timeout) for c in timed]
            outcomes += [run_case(c, a.timeout) for c in serial]
    finally:
        lab.stop()
        shutil.rmtree(scratch, ignore_errors=True)
    counts = {v: sum(o.verdict == v for o in outcomes) for v in ("clean", "traceback", "hang", "nonsense", "other")}
    codes: dict[str, int] = {}
    for o in outcomes:
        codes[str(o.code)] = codes.get(str(o.code), 0) + 1
    bad = [o for o in outcomes if o.verdict != "clean"]
    if a.json:
        json.dump({"inputs": len(outcomes), **counts, "exit_codes": codes,
                   "skipped": [{"case": c.name, "reason": no_tmpfs} for c in skipped],
                   "problems": [{"case": o.case.name, "verdict": o.verdict, "code": o.code, "detail": o.detail,
                                 "stderr": o.stderr[-2000:]} for o in bad]}, sys.stdout, indent=2)
        print()
    else:
        for o in bad:
            print(f"{o.verdict:9s} {o.case.name}: exit {o.code}; {o.detail}")
        print(f"inputs tried {len(outcomes)}: clean {counts['clean']}, tracebacks {counts['traceback']}, "
              f"hangs {counts['hang']}, nonsense accepted {counts['nonsense']}, other {counts['other']}")
        print("exit codes: " + ", ".join(f"{k}: {v}" for k, v in sorted(codes.items())))
        if skipped:
            print(f"skipped {len(skipped)} fault cases: {no_tmpfs}")
    return 1 if counts["traceback"] or counts["hang"] or counts["nonsense"] else 0


if __name__ == "__main__":
    sys.exit(main())
