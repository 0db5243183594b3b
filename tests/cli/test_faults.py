"""Faults: output paths checked before the work, devices never renamed over, full and read-only file systems,
stdout full, closed or a broken pipe, and interrupts (SIGINT 130, SIGTERM 143) that leave no temporary file."""

from __future__ import annotations

import json
import os
import random
import signal
import stat
import subprocess
import sys
import time

import pytest

from comparisons.cli.main import EXIT_INTERRUPTED, EXIT_TERMINATED, EXIT_WRITE, main
from comparisons.files import LIVE_TEMPORARIES, OutputFault, atomic_path, temporary_name

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIM = ["simulate", "--pressure", "2.5", "--speed", "60", "--duration", "0.3"]


def shimmy(*args, stdout=subprocess.PIPE, preexec_fn=None, timeout=120):
    proc = subprocess.run([sys.executable, "-m", "comparisons.cli", *args], stdout=stdout, stderr=subprocess.PIPE,
                          timeout=timeout, cwd=ROOT, preexec_fn=preexec_fn)
    return proc.returncode, proc.stdout, proc.stderr.decode()


def one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def no_temporaries(folder) -> None:
    assert not [n for n in os.listdir(folder) if n.endswith(".tmp")]


# --- output paths, in process ----------------------------------------------------------------------------------

@pytest.mark.parametrize("make, fragment", [
    (lambda d: ["--plot", ""], "empty file name"),
    (lambda d: ["--rerun", " "], "empty file name"),
    (lambda d: ["--plot", str(d)], "a directory is in the way"),
    (lambda d: ["--plot", str(d / "no" / "x.png")], "does not exist"),
    (lambda d: ["--plot", str(d / ("x" * 256))], "longer than 255 bytes"),
    (lambda d: ["--plot", str(d / "same"), "--rerun", str(d / "same")], "name the same file"),
    (lambda d: ["--rerun", "/dev/null"], "not a regular file"),
])
def test_output_paths_refused_before_the_work(tmp_path, capsys, make, fragment):
    start = time.perf_counter()
    assert main(SIM + make(tmp_path)) == 2
    assert fragment in one_line(capsys.readouterr().err)
    assert time.perf_counter() - start < 5.0
    assert os.listdir(tmp_path) == []


def test_temporary_name_fits_when_the_name_nearly_fills_255_bytes(tmp_path, capsys):
    final = tmp_path / ("y" * 247 + ".png")
    tmp = temporary_name(str(final))
    assert len(os.path.basename(tmp).encode()) <= 255
    assert main(SIM + ["--plot", str(final), "--json"]) == 0
    assert final.stat().st_size > 10_000
    no_temporaries(tmp_path)


def test_non_utf8_file_names_for_recording_and_plot(tmp_path):
    rrd = os.path.join(str(tmp_path), os.fsdecode(b"\xff\xfe-run.rrd"))
    png = os.path.join(str(tmp_path), os.fsdecode(b"plot-\xe9.png"))
    code, out, err = shimmy(*SIM, "--rerun", rrd, "--plot", png)
    assert code == 0 and err == ""
    assert os.path.getsize(rrd) > 1000 and os.path.getsize(png) > 1000
    assert b"recording written to " + os.fsencode(rrd) in out     # the name printed as its bytes
    no_temporaries(tmp_path)


def test_a_device_is_written_directly_never_renamed_over(tmp_path):
    """``--plot /dev/full`` as root used to rename the PNG over the device node."""
    code, _, err = shimmy(*SIM, "--plot", "/dev/full")
    assert code == EXIT_WRITE and "No space left on device" in one_line(err)
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)
    code, _, err = shimmy(*SIM, "--plot", "/dev/null")
    assert code == 0 and stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_write_fault_inside_atomic_path_is_an_output_fault_and_leaves_nothing(tmp_path):
    with pytest.raises(OutputFault, match="No space left"):
        with atomic_path(str(tmp_path / "a.txt")) as tmp:
            raise OSError(28, "No space left on device")
    assert os.listdir(tmp_path) == [] and not LIVE_TEMPORARIES


def test_output_fault_is_not_an_exception():
    """Handlers that turn failed checks into FAIL rows (``except Exception``) must not catch a disk fault."""
    assert not issubclass(OutputFault, Exception)


def test_json_writes_null_for_non_finite(capsys):
    from comparisons.cli.options import emit_json
    emit_json({"a": float("nan"), "b": [float("inf"), 1.5]})
    assert json.loads(capsys.readouterr().out) == {"a": None, "b": [None, 1.5]}


# --- stdout ----------------------------------------------------------------------------------------------------

def test_stdout_full_closed_and_broken_pipe():
    with open("/dev/full", "wb") as full:
        code, _, err = shimmy("params", stdout=full)
    assert code == EXIT_WRITE and "No space left" in one_line(err)
    code, _, err = shimmy("params", stdout=None, preexec_fn=lambda: os.close(1))
    assert code == EXIT_WRITE and "stdout is closed" in one_line(err)
    proc = subprocess.Popen([sys.executable, "-m", "comparisons.cli", "params", "--json"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=ROOT)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(60) == EXIT_WRITE and "Broken pipe" in one_line(err)


# --- small file systems (tmpfs, root only) ---------------------------------------------------------------------

@pytest.fixture
def tmpfs(tmp_path):
    """A read-only and a 256 kB tmpfs; skipped where mounting is not allowed."""
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    mounted = []
    paths = {}
    for name, opts in (("ro", "ro,size=64k"), ("full", "size=256k")):
        path = tmp_path / name
        path.mkdir()
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(path)], capture_output=True, text=True)
        if r.returncode != 0:
            for m in mounted:
                subprocess.run(["umount", "-l", m])
            pytest.skip(f"cannot mount a tmpfs here: {r.stderr.strip()}")
        mounted.append(str(path))
        paths[name] = path
    yield paths
    for m in mounted:
        subprocess.run(["umount", "-l", m])


def test_read_only_file_system_refused_before_the_work(tmpfs, capsys):
    for option, name in (("--plot", "x.png"), ("--rerun", "x.rrd")):
        assert main(SIM + [option, str(tmpfs["ro"] / name)]) == 2
        line = one_line(capsys.readouterr().err)
        assert "is not writable" in line or "Read-only file system" in line
    assert main(["params", "--write", str(tmpfs["ro"] / "a.toml")]) == 2
    line = one_line(capsys.readouterr().err)
    assert "is not writable" in line or "Read-only file system" in line


def test_recording_onto_a_full_disk_ends_with_one_line_and_no_temporary_file(tmpfs):
    """The Rerun file sink used to hang in 7 of 20 runs here; each run must now end within the time limit."""
    for _ in range(2):
        code, _, err = shimmy("simulate", "--pressure", "2.5", "--speed", "60", "--duration", "5", "--rerun",
                              str(tmpfs["full"] / "a.rrd"), timeout=60)
        assert code == EXIT_WRITE and "no space left on device" in one_line(err).lower()
        assert os.listdir(tmpfs["full"]) == []


def test_plot_onto_a_full_disk(tmpfs, capsys):
    big = ["simulate", "--pressure", "2.5", "--speed", "60", "--duration", "5"]
    (tmpfs["full"] / "filler").write_bytes(b"\0" * (250 * 1024))
    assert main(big + ["--plot", str(tmpfs["full"] / "big.png")]) == EXIT_WRITE
    assert "No space left on device" in one_line(capsys.readouterr().err)
    assert sorted(os.listdir(tmpfs["full"])) == ["filler"]


# --- interrupts ------------------------------------------------------------------------------------------------

def wait_for_shimmy_handlers(pid: int, timeout: float = 10.0) -> None:
    """Wait until process ``pid`` catches SIGTERM (bit in /proc/PID/status SigCgt): Python itself catches only
    SIGINT, so that bit says shimmy's own handlers are in place (``cli.main.entry``, before any model package).

    A signal before that moment meets the interpreter's start-up (a Python traceback, or the kernel's default
    action); timing from the process start measured the machine's load, not shimmy."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open(f"/proc/{pid}/status") as f:
            caught = next(int(line.split()[1], 16) for line in f if line.startswith("SigCgt:"))
        if caught >> (signal.SIGTERM - 1) & 1:
            return
        time.sleep(0.002)
    raise AssertionError(f"process {pid} never installed its signal handlers")


def interrupt(args, after: float, signum: int, cwd=ROOT):
    """Start ``shimmy args``, send ``signum`` ``after`` s after its signal handlers are in place; (exit code,
    stderr, seconds from signal to exit)."""
    proc = subprocess.Popen([sys.executable, "-m", "comparisons.cli", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=cwd)
    wait_for_shimmy_handlers(proc.pid)
    time.sleep(after)
    sent = time.monotonic()
    proc.send_signal(signum)
    out, err = proc.communicate(timeout=30)
    return proc.returncode, err.decode(), time.monotonic() - sent


@pytest.mark.parametrize("signum, code, line", [(signal.SIGINT, EXIT_INTERRUPTED, "shimmy: interrupted"),
                                                (signal.SIGTERM, EXIT_TERMINATED, "shimmy: terminated")])
def test_signal_during_simulate_within_a_second(tmp_path, signum, code, line):
    # A tramp limit cycle at 180 km/h: LSODA cannot take long steps, 1000 s take minutes.
    args = ["simulate", "--pressure", "1.5", "--set", "t0=0.25", "--speed", "180", "--duration", "1000",
            "--plot", str(tmp_path / "p.png")]
    got, err, seconds = interrupt(args, 1.5, signum)
    assert got == code and one_line(err) == line
    assert seconds < 1.0
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("after", [0.0, 0.05, 0.1, 0.2])
def test_ctrl_c_while_the_model_packages_load(after):
    """A KeyboardInterrupt inside a C extension's import used to end the process by SIGINT (status -2)."""
    args = ["simulate", "--pressure", "1.5", "--set", "t0=0.25", "--speed", "180", "--duration", "1000"]
    got, err, seconds = interrupt(args, after, signal.SIGINT)
    # the whole stderr in the message: a rare failure under load (exit 1 once in CI beside a full verify, 0 of 50
    # runs on this machine with and without three busy loops) must say what it was
    assert got == EXIT_INTERRUPTED and one_line(err) == "shimmy: interrupted" and seconds < 1.0, (got, err, seconds)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3))
def test_interrupts_at_random_moments_of_verify_and_figures(tmp_path, seed):
    """Ctrl-C or SIGTERM at a random moment: out within a second, one line, no temporary file; what was complete
    stays."""
    rnd = random.Random(seed)
    for args, out in ((["verify", "--quick", "--out", str(tmp_path / "rep")], tmp_path / "rep"),
                      (["figures", "--jobs", "2", "--out", str(tmp_path / "figs")],
                       tmp_path / "figs")):
        signum = rnd.choice([signal.SIGINT, signal.SIGTERM])
        got, err, seconds = interrupt(args, rnd.uniform(0.5, 20.0), signum)
        if got == 0:
            continue   # finished before the signal
        err = "\n".join(line for line in err.splitlines() if not line.startswith(("verify: ", "figures: ")))
        assert got == (EXIT_INTERRUPTED if signum == signal.SIGINT else EXIT_TERMINATED), err
        assert one_line(err) in ("shimmy: interrupted", "shimmy: terminated")
        assert seconds < 1.0
        if out.exists():
            for dirpath, _, names in os.walk(out):
                assert not [n for n in names if n.endswith(".tmp")], (dirpath, names)


def test_an_interrupt_swallowed_by_a_callback_exits_at_once_without_a_traceback(monkeypatch):
    """Ctrl-C inside a weakref callback of importlib's module locks was printed as 'Exception ignored in ...' with
    a traceback, and the run went on until the watchdog (seen once in the parametrised test above under load)."""
    import types

    from comparisons.cli import main as cli_main
    exits, passed_on = [], []
    monkeypatch.setattr(cli_main, "hard_exit", lambda code, line: exits.append((code, line)))
    signals = cli_main._Signals()
    signals.previous_hook = passed_on.append
    signals.unraisable(types.SimpleNamespace(exc_value=KeyboardInterrupt()))     # no signal yet: Python's hook
    assert exits == [] and len(passed_on) == 1
    signals.code = cli_main.EXIT_INTERRUPTED
    signals.unraisable(types.SimpleNamespace(exc_value=KeyboardInterrupt()))
    assert exits == [(cli_main.EXIT_INTERRUPTED, "shimmy: interrupted")]


def test_an_interrupt_that_comes_out_as_another_error_still_ends_in_its_one_line(monkeypatch, capsys):
    """Ctrl-C inside CPython's import lock came out as a KeyError from ``_ModuleLock.acquire`` with the
    KeyboardInterrupt as its context: exit 1 and a traceback (once in the parametrised test above, under load).
    After a signal, whatever error ends the run ends it as the signal does."""
    from comparisons.cli import main as cli_main

    def interrupted_import(argv, parser=None):
        try:
            os.kill(os.getpid(), signal.SIGINT)     # the handler raises KeyboardInterrupt here
            time.sleep(5.0)
        except KeyboardInterrupt:
            raise KeyError(140000000000000) from None

    monkeypatch.setattr(cli_main, "parse_command", interrupted_import)
    assert main(["params"]) == EXIT_INTERRUPTED
    assert one_line(capsys.readouterr().err) == "shimmy: interrupted"

    def plain_error(argv, parser=None):      # without a signal the same error is a bug, and it is raised
        raise KeyError(1)

    monkeypatch.setattr(cli_main, "parse_command", plain_error)
    with pytest.raises(KeyError):
        main(["params"])
