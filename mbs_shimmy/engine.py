"""Which of Exudyn's two compiled modules this package runs on.

Exudyn ships ``exudynCPP`` (range-checked, any 64-bit CPU) and ``exudynCPPfast`` (the same code without range
checks, built with AVX2), chosen by ``sys.exudynFast`` before Exudyn's first import (Exudyn's ``__init__.py``).
The fast module computes the same model (results within rounding: the MBS tests pass on both) and cuts the time
Exudyn spends in the kinematic tree and the linkage connectors by about 40 % (``mbs_shimmy/README.md``,
benchmark).  It is chosen here unless the caller already decided (``sys.exudynFast`` set, ``EXUDYN_MODULE`` in
the environment) or Exudyn was imported before this package; a CPU without AVX2 gets the regular module.  Exudyn
announces the choice on stdout, which would corrupt ``--json`` output, so the import is silenced.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys

if "exudyn" not in sys.modules and not hasattr(sys, "exudynFast") and "EXUDYN_MODULE" not in os.environ:
    sys.exudynFast = True
    with contextlib.redirect_stdout(io.StringIO()):
        import exudyn  # noqa: F401

import exudyn  # noqa: E402,F401


def fast() -> bool:
    """True if the loaded Exudyn is the build without range checks."""
    return getattr(exudyn, "_compiledModuleName", "") == "exudynCPPfast"
