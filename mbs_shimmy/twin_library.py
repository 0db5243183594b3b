"""The twin's functions compiled to machine code: CasADi's C code generation, built by the system's C compiler.

CasADi evaluates an SX function in its virtual machine; the same function generated as C and compiled runs the
Jacobian about ten times faster (measured on the full geometry, 100 states per call: 110-170 us a state in the
virtual machine, 12 us compiled with -O1; -O0 gave 34 us, -O2 no better than -O1 and compiles longer).  Compiling
costs seconds (about 6 s for the four functions at -O1), so :class:`~mbs_shimmy.twin.TwinGraph` compiles only once
a structure has been evaluated often (:data:`COMPILE_AFTER` states) and keeps the library on disk: the file name is
the hash of the C text, the flags and the compiler, so a changed graph is a new file and an unchanged one is loaded
in milliseconds by the next process.  The libraries live next to numba's cache, in this package's
``__pycache__`` (a temporary folder where that is not writable).  Without a C compiler the virtual machine stays.

The compiled functions compute the same expressions in the same order as the virtual machine (results equal to the
last bit on the states measured; ``tests/mbs/test_mbs_twin.py`` checks both against Exudyn).
"""

from __future__ import annotations

import hashlib
import os
import pathlib
import shutil
import subprocess
import tempfile

import casadi as ca

FLAGS = ("-O1", "-shared", "-fPIC")
# states evaluated in the virtual machine before a structure is compiled: about a second of its work, more than
# a test's handful of states, less than a tenth of one continued branch
COMPILE_AFTER = 8000


def _folder() -> pathlib.Path:
    here = pathlib.Path(__file__).resolve().parent / "__pycache__" / "twin"
    try:
        here.mkdir(parents=True, exist_ok=True)
        if os.access(here, os.W_OK):
            return here
    except OSError:
        pass
    fallback = pathlib.Path(tempfile.gettempdir()) / "shimmy-twin"
    fallback.mkdir(parents=True, exist_ok=True)
    return fallback


def compiler() -> str | None:
    """The C compiler's path, or None (then the twin stays in CasADi's virtual machine)."""
    return shutil.which(os.environ.get("CC", "gcc")) or shutil.which("cc")


def compiled(functions: list, cached_only: bool = False) -> dict | None:
    """{name: compiled function} for the CasADi SX ``functions``, from the disk cache or compiled now (one library
    each, compiled side by side); None where there is no compiler, where ``cached_only`` and a library was never
    built, or where compiling failed."""
    cc = compiler()
    if cc is None:
        return None
    folder = _folder()
    libraries, jobs = {}, []
    for fn in functions:
        generator = ca.CodeGenerator(f"{fn.name()}.c", {"with_header": False})
        generator.add(fn)
        text = generator.dump()
        key = hashlib.sha256("\n".join([text, " ".join(FLAGS), cc, ca.__version__]).encode()).hexdigest()[:24]
        library = libraries[fn.name()] = folder / f"twin_{key}.so"
        if library.exists():
            continue
        if cached_only:
            return None
        source, partial = folder / f"twin_{key}_{os.getpid()}.c", folder / f"twin_{key}_{os.getpid()}.so"
        source.write_text(text)
        jobs.append((subprocess.Popen([cc, *FLAGS, str(source), "-o", str(partial)], stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL), source, partial, library))
    failed = False
    for process, source, partial, library in jobs:
        try:
            failed |= process.wait() != 0
            if not failed:
                os.replace(partial, library)      # atomic: a parallel process never loads a half-written file
        finally:
            source.unlink(missing_ok=True)
            partial.unlink(missing_ok=True)
    if failed:
        return None
    return {name: ca.external(name, str(library)) for name, library in libraries.items()}
