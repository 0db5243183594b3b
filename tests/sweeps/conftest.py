"""Fixtures of the sweep fault tests: real Dask processes on localhost, stopped at the end."""

from __future__ import annotations

import pytest
from dask_processes import Dask


@pytest.fixture
def dask(tmp_path):
    d = Dask(str(tmp_path))
    yield d
    d.stop()


@pytest.fixture(scope="module")
def shared_cluster(tmp_path_factory):
    """One scheduler and two worker processes for the tests that do not kill the scheduler."""
    d = Dask(str(tmp_path_factory.mktemp("dask")))
    try:
        address, _ = d.scheduler()
        d.worker(address, 2)
        d.wait_for_workers(address, 2)
        yield d, address
    finally:
        d.stop()
