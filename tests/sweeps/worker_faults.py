"""Preloaded into the test workers (``dask worker --preload``): slower batches, so that a fault lands mid-sweep,
and a sample that makes its worker process exit, as a segfaulting extension or the OOM killer would.

The client pickles ``evaluate_batch`` by reference, so the worker runs whatever
``comparisons.sweeps.sample.evaluate_batch`` is in its own process: the wrapper below.
"""

import os
import time

from comparisons.sweeps import sample

DELAY_S = float(os.environ.get("SHIMMY_TEST_BATCH_DELAY_S", "0"))
CRASH = os.environ.get("SHIMMY_TEST_CRASH_PRESSURE")     # a batch holding this pressure (bar) kills its worker
# Dask imports a preload file and then reloads it in the same module: wrap the original once, not the wrapper.
if sample.evaluate_batch.__module__ == sample.__name__:
    _evaluate_batch = sample.evaluate_batch


def evaluate_batch(task, batch, start, values):
    if CRASH is not None and "pressure" in task.names:
        column = values[:, task.names.index("pressure")]
        if any(abs(v - float(CRASH)) < 1e-12 for v in column):
            os._exit(1)
    time.sleep(DELAY_S)
    return _evaluate_batch(task, batch, start, values)


sample.evaluate_batch = evaluate_batch
