"""Screenshots of a recording in the real Rerun viewer, headless, at chosen simulated times (for the README).

    python -m comparisons.recordings.screenshots RECORDING.rrd --at 40,85 --out docs/screenshots [--size 1600x1000]

The viewer runs without a window (``rerun --headless``) on Mesa's software Vulkan driver (lavapipe, Debian
package ``mesa-vulkan-drivers``; the GL backend cannot draw Rerun's R32Float targets).  The script starts its own
viewer on a free port, opens the file, pauses at each time, saves ``<stem>_<seconds>s.png`` and stops the
viewer it started (by its process id).  Nothing here is needed to make or read recordings.
"""

from __future__ import annotations

import argparse
import glob
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

LAVAPIPE_ICDS = ("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json", "/usr/share/vulkan/icd.d/lvp_icd.aarch64.json")


class ScreenshotError(RuntimeError):
    """The headless viewer is unavailable or did not answer; the message says why in one line."""


def lavapipe_icd() -> str | None:
    found = [p for p in LAVAPIPE_ICDS if os.path.exists(p)] + glob.glob("/usr/share/vulkan/icd.d/lvp_icd*.json")
    return found[0] if found else None


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
        return True
    except ProcessLookupError:
        return False


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _rerun_executable() -> str:
    here = os.path.join(os.path.dirname(sys.executable), "rerun")
    return here if os.path.exists(here) else (shutil.which("rerun") or "rerun")


class HeadlessViewer:
    """A ``rerun --headless`` process of our own, with a client connected to it."""

    def __init__(self, size: str = "1600x1000", timeout: float = 120.0):
        icd = lavapipe_icd()
        if icd is None:
            raise ScreenshotError("no software Vulkan driver: apt-get install -y mesa-vulkan-drivers")
        self.port = _free_port()
        env = dict(os.environ, VK_ICD_FILENAMES=icd, WGPU_BACKEND="vulkan")
        self.log = tempfile.TemporaryFile()
        self.process = subprocess.Popen(
            [_rerun_executable(), "--headless", "--renderer", "vulkan", "--window-size", size, "--port",
             str(self.port), "--hide-welcome-screen"], env=env, stdout=self.log, stderr=subprocess.STDOUT,
            start_new_session=True)   # its own process group: the `rerun` script runs the viewer as a child
        self.client = self._connect(timeout)

    def _connect(self, timeout: float):
        from rerun.experimental import ViewerClient
        deadline = time.monotonic() + timeout
        while True:
            if self.process.poll() is not None:
                self.log.seek(0)
                tail = self.log.read().decode(errors="replace").strip().splitlines()[-1:]
                raise ScreenshotError(f"the headless viewer exited ({self.process.returncode}): {' '.join(tail)}")
            try:
                client = ViewerClient.connect(f"rerun+http://127.0.0.1:{self.port}/proxy")
                client.get_state()
                return client
            except Exception:  # not listening yet
                if time.monotonic() > deadline:
                    raise ScreenshotError(f"the headless viewer did not answer within {timeout:g} s") from None
                time.sleep(0.5)

    def open(self, path: str, timeout: float = 300.0) -> None:
        self.client.open(os.path.abspath(path))
        deadline = time.monotonic() + timeout
        time.sleep(1.0)
        while self.client.get_state().loading:
            if time.monotonic() > deadline:
                raise ScreenshotError(f"{path} did not finish loading within {timeout:g} s")
            time.sleep(0.5)

    def screenshot(self, seconds: float, png: str, settle: float = 2.0) -> None:
        self.client.set_time("sim_time", duration=seconds, play_state="paused")
        time.sleep(settle)      # let the software renderer draw the new frame
        self.client.save_screenshot(os.path.abspath(png))

    def close(self) -> None:
        """Stop the viewer: the process group this object started (the script and the viewer it runs)."""
        for sig in (signal.SIGTERM, signal.SIGKILL):
            try:
                os.killpg(self.process.pid, sig)
            except ProcessLookupError:
                break
            try:
                self.process.wait(timeout=10)
                if not _group_alive(self.process.pid):
                    break
            except subprocess.TimeoutExpired:
                continue
        self.log.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def take_screenshots(path: str, times: list[float], out: str, size: str = "1600x1000") -> list[str]:
    """One PNG per time in ``out``; returns their paths."""
    if not os.path.isfile(path):
        raise ScreenshotError(f"{path}: no such recording")
    os.makedirs(out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(path))[0]
    written = []
    with HeadlessViewer(size) as viewer:
        viewer.open(path)
        for t in times:
            png = os.path.join(out, f"{stem}_{t:g}s.png")
            viewer.screenshot(t, png)
            written.append(png)
    return written


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m comparisons.recordings.screenshots", description=__doc__.splitlines()[0])
    p.add_argument("recording", metavar="RECORDING.rrd")
    p.add_argument("--at", required=True, metavar="SECONDS[,SECONDS...]", help="simulated times")
    p.add_argument("--out", default=os.path.join("docs", "screenshots"), metavar="DIR")
    p.add_argument("--size", default="1600x1000", metavar="WxH", help="viewer size in logical points")
    args = p.parse_args(argv)
    try:
        times = [float(x) for x in args.at.split(",")]
    except ValueError:
        sys.stderr.write(f"screenshots: --at expects numbers separated by commas, got '{args.at}'\n")
        return 2
    try:
        for png in take_screenshots(args.recording, times, args.out, args.size):
            print(png)
    except ScreenshotError as exc:
        sys.stderr.write(f"screenshots: {exc}\n")
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
