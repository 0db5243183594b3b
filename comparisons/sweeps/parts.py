"""The parts folder of a sweep (``OUT.parts``): its manifest, its batch files and their checksums, and its lock.

* ``manifest.json`` says which sweep the folder holds (design fingerprint, task with the axle file's SHA-256, batch
  size).  A batch is ``batch-NNNNNN.parquet``; its Parquet metadata names the sweep (fingerprint) and the batch,
  and ``batch-NNNNNN.parquet.sha256`` (``sha256sum -c`` format) holds the SHA-256 of its bytes.  The checksum is
  renamed into place before the part, so a part is only ever kept with the checksum of exactly its bytes.
* :func:`check_parts` reads every kept part on ``--resume``: a part of another sweep is refused by name (computing
  it again would silently drop someone's results); a damaged one (unreadable, checksum, schema, row count or sample
  ids wrong) is reported and computed again.
* :class:`SweepLock` (``OUT.lock``, an ``flock``) keeps a second sweep out of the same ``--out``; the kernel drops
  the lock when its holder dies however it dies, so a lock file that nobody holds is stale and is taken over.
"""

from __future__ import annotations

import enum
import fcntl
import hashlib
import json
import os
import re
import socket
import time
from dataclasses import dataclass

import pyarrow as pa
import pyarrow.parquet as pq

from axles.limits import UsageError
from comparisons.files import atomic_path, write_atomically

MANIFEST = "manifest.json"
MANIFEST_VERSION = 2
BATCH_KEY = b"shimmy_batch"
CHECKSUM_SUFFIX = ".sha256"
_PART = re.compile(r"batch-(\d{6,})\.parquet")


def parts_folder(out: str) -> str:
    return out + ".parts"


def part_path(parts: str, batch: int) -> str:
    return os.path.join(parts, f"batch-{batch:06d}.parquet")


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def parquet_bytes(table: pa.Table) -> bytes:
    # Serialised in memory first: a checksum is then of exactly the bytes written, and a full disk is a plain
    # OSError with its errno from the write in write_bytes, not one of pyarrow's own I/O errors.
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink)
    return sink.getvalue().to_pybytes()


def write_bytes(tmp: str, data: bytes) -> None:
    with open(tmp, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())


def write_part(parts: str, batch: int, table: pa.Table, fingerprint: str) -> None:
    """Write one batch and its checksum; :class:`comparisons.files.OutputFault` when the storage fails."""
    meta = {BATCH_KEY: json.dumps({"fingerprint": fingerprint, "batch": batch, "rows": table.num_rows}).encode()}
    data = parquet_bytes(table.replace_schema_metadata(meta))
    path = part_path(parts, batch)
    with atomic_path(path) as tmp:
        write_bytes(tmp, data)
        write_atomically(path + CHECKSUM_SUFFIX, f"{_sha256(data)}  {os.path.basename(path)}\n")


def write_table(path: str, table: pa.Table) -> None:
    data = parquet_bytes(table)
    with atomic_path(path) as tmp:
        write_bytes(tmp, data)


def kept_batches(parts: str) -> int:
    """Batch files with their checksum in ``parts`` (what a resume can keep, before it checks them)."""
    try:
        names = set(os.listdir(parts))
    except OSError:
        return 0
    return sum(1 for n in names if _PART.fullmatch(n) and n + CHECKSUM_SUFFIX in names)


class Damage(enum.Enum):
    """Why a kept part is computed again."""

    UNREADABLE = "not a readable Parquet file"
    NO_CHECKSUM = "its checksum file is missing"
    CHECKSUM = "its bytes do not match its checksum"
    SCHEMA = "its columns are not the sweep's"
    ROWS = "it has the wrong number of rows"
    SAMPLES = "it holds other sample ids than its batch"


@dataclass(frozen=True)
class DamagedPart:
    name: str
    damage: Damage

    def to_json(self) -> dict:
        return {"part": self.name, "damage": self.damage.name.lower(), "reason": self.damage.value}


def _read_checksum(path: str) -> str | None:
    try:
        with open(path + CHECKSUM_SUFFIX, encoding="ascii") as fh:
            return fh.read().split()[0]
    except (OSError, ValueError, IndexError):
        return None


def _check_part(path: str, batch: int, start: int, rows: int, schema: pa.Schema, fingerprint: str) -> Damage | None:
    name = os.path.basename(path)
    with open(path, "rb") as fh:
        data = fh.read()
    try:
        table = pq.read_table(pa.BufferReader(data))
        meta = json.loads((table.schema.metadata or {}).get(BATCH_KEY, b"null"))
    except (pa.ArrowException, OSError, ValueError):
        return Damage.UNREADABLE
    if not isinstance(meta, dict) or meta.get("fingerprint") != fingerprint:
        theirs = meta.get("fingerprint") if isinstance(meta, dict) else None
        whose = f"sweep {str(theirs)[:12]}" if theirs else "no shimmy sweep"
        raise UsageError(f"--resume: {os.path.join(os.path.dirname(path), name)} is a part of {whose}, not of this "
                         f"one ({fingerprint[:12]}): move it away, or delete {os.path.dirname(path)} to start again")
    checksum = _read_checksum(path)
    if checksum is None:
        return Damage.NO_CHECKSUM
    if checksum != _sha256(data):
        return Damage.CHECKSUM
    if not table.schema.remove_metadata().equals(schema):
        return Damage.SCHEMA
    if table.num_rows != rows:
        return Damage.ROWS
    if meta.get("batch") != batch or table.column("sample").to_pylist() != list(range(start, start + rows)) or \
            set(table.column("batch").to_pylist()) != {batch}:
        return Damage.SAMPLES
    return None


def check_parts(parts: str, samples: int, size: int, schema: pa.Schema,
                fingerprint: str) -> tuple[set[int], list[DamagedPart]]:
    """(batches kept, parts to compute again); :class:`UsageError` for a file that is not of this sweep."""
    batches = -(-samples // size)
    kept, damaged = set(), []
    for name in sorted(os.listdir(parts)):
        m = _PART.fullmatch(name)
        if m is None:
            continue
        b = int(m.group(1))
        if b >= batches:
            raise UsageError(f"--resume: {os.path.join(parts, name)} is not a batch of this sweep (it has "
                             f"{batches} batches): move it away, or delete {parts} to start again")
        start = b * size
        damage = _check_part(os.path.join(parts, name), b, start, min(size, samples - start), schema, fingerprint)
        if damage is None:
            kept.add(b)
        else:
            damaged.append(DamagedPart(name, damage))
    return kept, damaged


# --- the manifest --------------------------------------------------------------------------------------------

def read_manifest(parts: str) -> dict | None:
    path = os.path.join(parts, MANIFEST)
    if not os.path.exists(path):
        return None
    try:
        with open(path, encoding="utf-8") as fh:
            found = json.load(fh)
    except (OSError, ValueError) as exc:
        raise UsageError(f"--resume: {path} cannot be read ({exc}): delete {parts} to start again") from None
    if not isinstance(found, dict) or found.get("version") != MANIFEST_VERSION:
        raise UsageError(f"--resume: {path} was written by another version of shimmy: delete {parts} to start "
                         f"again")
    return found


def write_manifest(parts: str, manifest: dict) -> None:
    os.makedirs(parts, exist_ok=True)
    write_atomically(os.path.join(parts, MANIFEST), json.dumps(manifest, indent=1))


# --- the lock ------------------------------------------------------------------------------------------------

def lock_path(out: str) -> str:
    return out + ".lock"


class SweepLock:
    """``OUT.lock``: held (``flock``) from before the parts folder is looked at until the sweep ends.

    ``stale`` is what the file said when it was found but held by nobody: a sweep that died (``kill -9``, a
    crash, a power cut) without removing it.
    """

    def __init__(self, out: str):
        self.out, self.path = out, lock_path(out)
        self.fd: int | None = None
        self.stale: str | None = None

    def __enter__(self) -> "SweepLock":
        while True:
            try:
                fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
            except OSError as exc:
                raise UsageError(f"--out {self.out}: cannot create the lock {self.path} ({exc.strerror})") from None
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _describe(_read_all(fd))
                os.close(fd)
                raise UsageError(f"--out {self.out}: another sweep writes there ({holder}, lock {self.path}); wait "
                                 f"for it to end or give another --out") from None
            # Its last holder may have removed the file between our open and flock: then this is no lock any more.
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(self.path))
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        previous = _read_all(fd)
        self.stale = _describe(previous) if previous.strip() else None
        self.fd = fd
        info = json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                           "started": time.strftime("%Y-%m-%d %H:%M:%S")})
        try:   # the lock is the flock; the text only names its holder, so a full disk may leave it empty
            os.ftruncate(fd, 0)
            os.pwrite(fd, info.encode(), 0)
        except OSError:
            pass
        return self

    def __exit__(self, *exc) -> None:
        if self.fd is None:
            return
        try:
            os.unlink(self.path)
        except OSError:
            pass
        os.close(self.fd)
        self.fd = None


def _read_all(fd: int) -> str:
    try:
        return os.pread(fd, 4096, 0).decode("utf-8", "replace")
    except OSError:
        return ""


def _describe(text: str) -> str:
    try:
        info = json.loads(text)
        return f"pid {info['pid']} on {info['host']} since {info['started']}"
    except (ValueError, KeyError, TypeError):
        return "holder unknown"
