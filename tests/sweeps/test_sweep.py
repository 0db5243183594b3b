"""``shimmy sweep``: sampling plan, results against direct ``shimmy hopf``, failed samples, resume, Dask clusters."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import numpy as np
import pyarrow.parquet as pq
import pytest

from axles.axle import AxleData
from axles.limits import UsageError
from axles.units import from_kmh
from comparisons.cli.main import main
from comparisons.sweeps.design import make_design, parse_vary
from comparisons.sweeps.run import run_sweep
from comparisons.sweeps.sample import SweepTask, evaluate_batch
from axles.pressures import TyrePressures


def _cli_json(capsys, argv: list[str]) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


# --- the sampling plan ---------------------------------------------------------------------------------------

def _random_design(seed: int, design: str = "sobol", samples: int = 64):
    return make_design([parse_vary("pressure=uniform:0.5:3.5"), parse_vary("wheel_mass=normal:40:5")], samples,
                       seed, design)


def test_same_seed_gives_same_samples_and_another_seed_others():
    a, b, c = _random_design(3), _random_design(3), _random_design(4)
    assert np.array_equal(a.values, b.values) and a.fingerprint() == b.fingerprint()
    assert not np.allclose(a.values, c.values) and a.fingerprint() != c.fingerprint()
    assert np.all((a.values[:, 0] >= 0.5) & (a.values[:, 0] <= 3.5))
    # the normal input has the asked mean and spread (a Sobol' sample of 64 points matches them closely)
    assert abs(a.values[:, 1].mean() - 40.0) < 0.5 and abs(a.values[:, 1].std() - 5.0) < 0.5


def test_saltelli_rows_are_A_AB_B_blocks():
    d = _random_design(1, "saltelli", samples=16)
    rows = d.values.reshape(16, 4, 2)          # per base sample: A, AB_1, AB_2, B
    A, AB1, AB2, B = rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3]
    assert np.array_equal(AB1[:, 0], B[:, 0]) and np.array_equal(AB1[:, 1], A[:, 1])
    assert np.array_equal(AB2[:, 1], B[:, 1]) and np.array_equal(AB2[:, 0], A[:, 0])
    assert len(d) == 16 * 4 and d.base_samples == 16


def test_grid_is_full_factorial_first_input_slowest():
    d = make_design([parse_vary("pressure=1:2:2"), parse_vary("t0=0.05:0.07:3")], None, None)
    assert np.allclose(d.values, [[1, 0.05], [1, 0.06], [1, 0.07], [2, 0.05], [2, 0.06], [2, 0.07]])


@pytest.mark.parametrize("argv, message", [
    (["--vary", "pressure=1:2"], "expected LO:HI:N"),
    (["--vary", "presure=1:2:3"], "did you mean 'pressure'"),
    (["--vary", "kk1=1:2:3"], "unknown input 'kk1'"),
    (["--vary", "t0=uniform:0.3:0.1", "--samples", "4"], "uniform needs LO < HI"),
    (["--vary", "t0=normal:0.1:0", "--samples", "4"], "positive standard deviation"),
    (["--vary", "t0=uniform:0.1:0.3"], "need --samples"),
    (["--vary", "t0=uniform:0.1:0.3", "--vary", "pressure=1:2:3", "--samples", "4"], "mixes grids"),
    (["--vary", "t0=0.1:0.3:3", "--compute", "hopf,cycels"], "unknown output 'cycels'"),
    (["--vary", "t0=0.1:0.3:3", "--compute", "margins", "--mbs", "full"], "it needs --compute hopf or cycles"),
    (["--vary", "t0=0.1:0.3:3", "--compute", "cycles", "--mbs", "fulll"], "unknown fidelity 'fulll'"),
    (["--vary", "t0=0.1:0.3:3", "--output", "hopf_kmh"], "needs an index"),
    (["--vary", "t0=0.1:0.3:3", "--vary", "t0=0.1:0.2:2"], "given twice"),
])
def test_bad_input_is_one_line_and_exit_2(capsys, tmp_path, argv, message):
    assert main(["sweep", *argv, "--out", str(tmp_path / "x.parquet")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and err.startswith("shimmy: error:")
    assert not os.path.exists(tmp_path / "x.parquet.parts")


# --- results --------------------------------------------------------------------------------------------------

def test_local_cluster_sweep_equals_shimmy_hopf_and_records_failed_samples(capsys, tmp_path):
    """Each sample against a direct `shimmy hopf` with the same --set/--pressure; pressure -0.5 bar and a
    negative kingpin stiffness are meaningless, recorded as failed, and the sweep completes."""
    out = tmp_path / "s.parquet"
    summary = _cli_json(capsys, ["sweep", "--vary", "pressure=-0.5:2.5:4", "--vary", "k1=-10000:70000:3",
                                 "--set", "t0=0.1", "--lyapunov", "--workers", "1", "--out", str(out), "--json"])
    assert summary["run"]["samples"] == 12 and summary["run"]["computed_batches"] == summary["run"]["batches"]
    table = pq.read_table(out).to_pylist()
    assert [r["sample"] for r in table] == list(range(12))
    ok = 0
    for r in table:
        if r["pressure"] <= 0.0 or r["k1"] < 0.0:
            assert r["status"] == "failed" and r["hopf_kmh"] is None
            assert "outside" in r["error"], r["error"]
            try:   # a pressure outside its range is refused by the option parser itself (SystemExit 2)
                code = main(["hopf", "--pressure", str(max(r["pressure"], 0.01)), "--set", f"k1={r['k1']!r}",
                             "--set", "t0=0.1", "--json"])
            except SystemExit as exc:
                code = exc.code
            assert code == 2
            capsys.readouterr()
            continue
        direct = _cli_json(capsys, ["hopf", "--pressure", repr(r["pressure"]), "--set", f"k1={r['k1']!r}",
                                    "--set", "t0=0.1", "--json"])["hopf"]
        assert r["status"] == "ok" and r["error"] is None
        assert r["hopf_kmh"] == [h["speed_kmh"] for h in direct]        # bit for bit: the same computation
        assert r["hopf_hz"] == [h["frequency_hz"] for h in direct]
        assert r["hopf_l1"] == [h["first_lyapunov"] for h in direct]
        assert r["n_hopf"] == len(direct)
        ok += 1
    assert ok == 6 and summary["run"]["failed"] == 6


def test_unstable_intervals_agree_with_eigenvalues():
    """The unstable speed intervals, from the Hopf points and one eigenvalue test per interval, against a dense
    eigenvalue scan."""
    from bifurcation.equilibria.hopf import eigenvalues
    from reduced_model.family import SpeedFamily
    from reduced_model.model import ShimmyModel
    task = SweepTask(AxleData(), (), 1.5, 1.5, ("pressure",))
    row = task.evaluate(np.array([1.5]))
    assert row["n_hopf"] == 4 and row["hopf_mode"][2] == "tramp" and row["hopf_mode"][0] == "yaw"
    family = SpeedFamily(ShimmyModel(), pressures=TyrePressures.uniform(1.5e5))
    for v in np.linspace(2.0, 399.0, 150):
        unstable = eigenvalues(family, from_kmh(v), 1.5e5)[0].real > 0
        inside = any(a <= v <= b for a, b in zip(row["unstable_from_kmh"], row["unstable_to_kmh"]))
        assert unstable == inside, v


def _interrupt_after(k: int):
    seen = []

    def progress(done: int, total: int) -> None:
        seen.append(done)
        if len(seen) > k:     # the first call reports the starting point
            raise KeyboardInterrupt
    return progress


def test_interrupted_sweep_resumes_without_recomputing_finished_batches(tmp_path):
    design = make_design([parse_vary("pressure=0.8:3.2:8")], None, None)
    task = SweepTask(AxleData(), (), 2.5, 2.5, design.names)
    out = str(tmp_path / "r.parquet")
    with pytest.raises(KeyboardInterrupt):
        run_sweep(task, design, out, workers=1, size=2, progress=_interrupt_after(2))
    parts = out + ".parts"
    finished = sorted(f for f in os.listdir(parts) if f.startswith("batch-") and f.endswith(".parquet"))
    assert 2 <= len(finished) < 4 and not os.path.exists(out)
    stamps = {f: os.stat(os.path.join(parts, f)).st_mtime_ns for f in finished}
    time.sleep(0.01)
    with pytest.raises(UsageError, match="--resume continues it"):
        run_sweep(task, design, out, workers=1, size=2)
    other = make_design([parse_vary("pressure=0.8:3.2:9")], None, None)
    with pytest.raises(UsageError, match="different sweep"):
        run_sweep(task, other, out, workers=1, size=2, resume=True)
    for f, stamp in stamps.items():   # refusals touch nothing
        assert os.stat(os.path.join(parts, f)).st_mtime_ns == stamp
    result = run_sweep(task, design, out, workers=1, resume=True)
    assert result.computed_batches == 4 - len(finished) and result.batches == 4 and result.batch_size == 2
    assert not os.path.exists(parts)
    # the resumed file equals a direct evaluation of every sample
    expect = evaluate_batch(task, 0, 0, design.values)
    got = pq.read_table(out)
    assert got.column("hopf_kmh").to_pylist() == expect.column("hopf_kmh").to_pylist()
    assert got.column("sample").to_pylist() == list(range(8))
    meta = json.loads(pq.read_schema(out).metadata[b"shimmy_sweep"])
    assert meta["fingerprint"] == design.fingerprint() and meta["design"]["inputs"][0]["name"] == "pressure"
    again = run_sweep(task, design, out, workers=1, resume=True)
    assert again.computed_batches == 0 and again.samples == 8


def test_external_scheduler_and_worker_give_identical_results(tmp_path):
    """`dask scheduler` and `dask worker` started here on localhost run the sweep; the rows equal a direct
    evaluation of every sample (which the local-cluster test ties to `shimmy hopf`)."""
    dask = os.path.join(os.path.dirname(sys.executable), "dask")
    sched_file = tmp_path / "scheduler.json"
    env = {**os.environ, "PYTHONPATH": os.path.dirname(os.path.dirname(os.path.abspath(__file__)))}
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "env": env, "cwd": tmp_path}
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                               "--scheduler-file", str(sched_file)], **quiet)]
    try:
        deadline = time.time() + 60
        address = None
        while address is None and time.time() < deadline:
            try:   # the scheduler creates the file before it writes it: read it once it parses
                address = json.loads(sched_file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        assert address is not None, "the scheduler did not write its address within 60 s"
        procs.append(subprocess.Popen([dask, "worker", address, "--nworkers", "1", "--nthreads", "1",
                                       "--no-dashboard"], **quiet))
        design = make_design([parse_vary("pressure=uniform:0.5:3.5"), parse_vary("t0=normal:0.07:0.01")], 40, 7)
        task = SweepTask(AxleData(), (), 2.5, 2.5, design.names, lyapunov=True)
        out = str(tmp_path / "remote.parquet")
        result = run_sweep(task, design, out, scheduler=address, size=5)
        assert result.scheduler == address and result.computed_batches == 8
        remote = pq.read_table(out)
        direct = evaluate_batch(task, 0, 0, design.values)
        for name in ("sample", "pressure", "t0", "status", "hopf_kmh", "hopf_hz", "hopf_l1", "unstable_from_kmh"):
            assert remote.column(name).to_pylist() == direct.column(name).to_pylist(), name
    finally:
        for p in reversed(procs):
            p.terminate()
            p.wait(timeout=30)


@pytest.mark.slow
def test_ctrl_c_at_the_terminal_keeps_finished_batches_and_resume_completes(tmp_path):
    """SIGINT to the whole process group, as a terminal's Ctrl-C: one line, exit 130, finished batches kept; the
    same command with --resume computes only the others."""
    import signal
    argv = [os.path.join(os.path.dirname(sys.executable), "shimmy"), "sweep", "--vary", "pressure=uniform:0.5:3.5",
            "--samples", "3000", "--batch-size", "100", "--out", "k.parquet"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    parts = tmp_path / "k.parquet.parts"
    deadline = time.time() + 120
    while len(list(parts.glob("batch-*.parquet"))) < 3 and time.time() < deadline:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    lines = [line for line in err.splitlines() if not line.startswith("sweep:")]
    assert proc.returncode == 130 and len(lines) == 1 and lines[0].endswith(" --resume"), err
    kept = len(list(parts.glob("batch-*.parquet")))
    assert 3 <= kept < 30
    done = subprocess.run(argv + ["--resume", "--json"], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    run = json.loads(done.stdout)["run"]
    assert run["computed_batches"] == 30 - kept and run["samples"] == 3000 and run["failed"] == 0


def test_margin_columns_equal_the_margin_api():
    """The sweep's margin outputs against ``stability_margins`` on the same speeds (the call of ``shimmy margins``),
    for the reduced model and both MBS fidelities, on one axle with other dimensions; with every assumption on the
    MBS has the reduced model's margin."""
    from comparisons.api import Axle as ApiAxle
    from comparisons.api import stability_margins
    from comparisons.sweeps.sample import MARGIN_SPEEDS
    task = SweepTask(AxleData(), (), 2.5, 2.5, ("drag_link_inclination",), compute=("hopf", "margins"),
                     mbs=("reduced", "full"))
    assert {"margin", "mbs_full_margin_kmh", "mbs_reduced_margin_mode"} <= set(task.schema().names)
    row = task.evaluate(np.array([11.0]))
    axle = ApiAxle(AxleData().with_values({"drag_link_inclination": np.radians(11.0)}))
    for prefix, model in (("", axle.reduced()), ("mbs_reduced_", axle.mbs("reduced")), ("mbs_full_", axle.mbs("full"))):
        low = stability_margins(model, (2.5, 2.5), 0.5, 400, pressure_points=1, speed_points=MARGIN_SPEEDS).minimum
        assert row[f"{prefix}margin"] == low.damping_ratio and row[f"{prefix}margin_kmh"] == low.speed_kmh
    assert abs(row["mbs_reduced_margin"] - row["margin"]) < 1e-9 and row["margin"] < 0 < row["mbs_full_margin"]


def test_a_slow_batch_holds_no_other_batch_behind_it(monkeypatch, tmp_path):
    """No more batches are in flight than the cluster has threads: a batch queued on a worker behind a slow sample
    waited there while the other worker stood idle (6 minutes of a 16-sample full-geometry sweep)."""
    import types

    import pyarrow as pa
    from distributed import Client, LocalCluster

    import comparisons.sweeps.run as sweep_run

    def batch(shared, b, start, values):     # runs in the workers (a copy): it says when it finished
        time.sleep(3.0 if b == 0 else 0.05)
        return pa.table({"sample": [start], "finished": [time.monotonic()]})

    monkeypatch.setattr(sweep_run, "evaluate_batch", batch)
    design = type("Design", (), {"values": np.zeros((12, 1)), "__len__": lambda self: 12})()
    parts = tmp_path / "parts"
    parts.mkdir()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as local, \
            Client(local) as client:
        start = time.monotonic()
        computed, killed = sweep_run._compute(types.SimpleNamespace(client=client), object(), design, str(parts),
                                              {"batch_size": 1, "fingerprint": "0" * 64}, set(), None)
        elapsed = time.monotonic() - start
    assert sorted(computed) == list(range(12)) and killed == []
    rows = [pq.read_table(parts / name).to_pylist()[0] for name in os.listdir(parts) if name.endswith(".parquet")]
    order = [r["sample"] for r in sorted(rows, key=lambda r: r["finished"])]
    assert len(order) == 12 and order[-1] == 0       # the eleven quick batches ran beside the slow one
    assert elapsed < 3.0 + 2.0
