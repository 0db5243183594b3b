"""Writing output files so that a failed or interrupted run never leaves a truncated file under the final name."""

from __future__ import annotations

import contextlib
import os
import tempfile
from typing import Iterator


@contextlib.contextmanager
def atomic_path(path: str) -> Iterator[str]:
    """Yield a temporary file name beside ``path``; on success it is renamed to ``path``, else removed.

    The writer writes (and may check) the temporary file; only a complete file ever carries the final name.
    Raises IsADirectoryError when a directory is in the way and OSError when the folder cannot take the file.
    """
    final = os.path.abspath(path)
    if os.path.isdir(final):
        raise IsADirectoryError(f"{path} is a directory, not a file")
    fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(final)}.", suffix=".tmp", dir=os.path.dirname(final))
    os.close(fd)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; outputs are for others to read
        os.replace(tmp, final)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
