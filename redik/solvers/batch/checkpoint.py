"""Finished chunks of a batch on disk, so that a batch cut short resumes where it stopped.

A checkpoint is a directory that belongs to one batch:

- ``batch.json`` — the batch's *fingerprint*: what it solves (digests of the targets, the seeds
  and the robot's chain, the robot's name and the batch size), how (every solve option, the
  chunk size and the seed), the version of redik that solves it and the fields of its
  result, and the key its random streams derive from;
- ``chunk-<first>.npz`` — one file per finished chunk, ``first`` being the index in the batch
  of the chunk's first target, holding the chunk's result arrays.

**Safe against a kill.** Every file is written under a temporary name, flushed to disk
(``fsync``) and renamed onto its final name (:func:`os.replace`, atomic on POSIX file
systems), so a process killed in the middle of a write leaves either the whole file or none of
it. The temporaries such a kill leaves behind are removed the next time the checkpoint is
opened; one run at a time may use a checkpoint.

**The same batch, or none.** :meth:`Checkpoint.open` compares the fingerprint it is given with
the stored one entry by entry and raises
:class:`~redik.core.exceptions.CheckpointMismatch` naming every entry that differs. What may
change between runs is where the chunks run: engine, workers and address are not part of the
fingerprint, since results do not depend on them. The stored key is the one a resumed batch
uses, so a batch started with ``seed=None`` resumes with the random streams it started with.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import IO, Any

import numpy as np

from redik.core.exceptions import CheckpointMismatch, InvalidInput
from redik.kinematics.chain import Chain

FORMAT = 1
"""Version of the checkpoint layout, stored in the fingerprint."""

FINGERPRINT_FILE = "batch.json"
"""Name of the fingerprint inside a checkpoint directory."""

CHUNK_PATTERN = "chunk-*.npz"
"""Names of the chunk files inside a checkpoint directory."""


def digest(*arrays: np.ndarray) -> str:
    """SHA-256 of arrays' dtypes, shapes and bytes, as ``"sha256:<hex>"``.

    Args:
        *arrays: The arrays, in order.

    Returns:
        The digest; equal digests mean bit-identical arrays (up to SHA-256 collisions).
    """
    hash_ = hashlib.sha256()
    for array in arrays:
        array = np.ascontiguousarray(array)
        hash_.update(f"{array.dtype.str}{array.shape}".encode())
        hash_.update(array.data)
    return f"sha256:{hash_.hexdigest()}"


def redik_version() -> str:
    """The installed redik's version (``"unknown"`` when redik runs from an uninstalled tree)."""
    try:
        return importlib.metadata.version("redik")
    except importlib.metadata.PackageNotFoundError:
        return "unknown"


def batch_fingerprint(
    chain: Chain,
    T_targets: np.ndarray,
    q0: np.ndarray,
    options: Mapping[str, Any],
) -> dict[str, Any]:
    """The fingerprint of a batch (see the module docstring).

    Args:
        chain: The compiled chain the batch is solved on.
        T_targets: The checked ``B × 4 × 4`` targets, exactly as the chunks receive them.
        q0: The checked ``B × n`` seeds.
        options: Everything else the results depend on (solve options, chunk size, seed),
            as JSON-serialisable values.

    Returns:
        The fingerprint, a JSON-serialisable mapping from entry name to value.
    """
    arrays = [getattr(chain, name) for name in chain.__dataclass_fields__ if name != "name"]
    return {
        "format": FORMAT,
        "redik version": redik_version(),
        "robot": chain.name,
        "robot chain": digest(*arrays),
        "size": len(T_targets),
        "targets": digest(T_targets),
        "seeds": digest(q0),
        **options,
    }


def finished_chunks(path: str | os.PathLike) -> int:
    """The number of finished chunks in a checkpoint directory.

    Args:
        path: The directory (it need not exist).

    Returns:
        How many chunk files it holds (0 when it does not exist).
    """
    return sum(1 for _ in Path(path).glob(CHUNK_PATTERN))


class Checkpoint:
    """The finished chunks of one batch in a directory (see the module docstring).

    Open one with :meth:`open`; read what is there with :meth:`finished`; add a chunk with
    :meth:`save`.

    Attributes:
        path: The directory.
        key: The key of the batch's random streams (the stored one when resuming).
    """

    def __init__(self, path: Path, key: int):
        self.path = path
        self.key = key

    @classmethod
    def open(cls, path: str | os.PathLike, fingerprint: Mapping[str, Any], key: int) -> Checkpoint:
        """Create the checkpoint of a batch, or open the one it left.

        Args:
            path: The directory; created when missing.
            fingerprint: The batch's fingerprint (:func:`batch_fingerprint`).
            key: The key of the batch's random streams, stored when the checkpoint is new.

        Returns:
            The checkpoint, its :attr:`key` the stored one.

        Raises:
            CheckpointMismatch: ``path`` holds the checkpoint of another batch (the message
                names every entry that differs), or a non-empty directory that is no
                checkpoint.
            InvalidInput: ``path`` is a file.
        """
        path = Path(path)
        if path.exists() and not path.is_dir():
            raise InvalidInput(f"checkpoint must be a directory, got the file {str(path)!r}")
        path.mkdir(parents=True, exist_ok=True)
        for temporary in path.glob(".*.tmp"):
            temporary.unlink(missing_ok=True)  # a write cut short by a kill
        stored_file = path / FINGERPRINT_FILE
        if not stored_file.is_file():
            if any(path.iterdir()):
                raise CheckpointMismatch(
                    f"{str(path)!r} is not empty and holds no {FINGERPRINT_FILE}: not a redik "
                    f"checkpoint; give an empty or new directory"
                )
            stored = {**fingerprint, "key": key}
            _write_atomic(
                stored_file, lambda file: file.write(json.dumps(stored, indent=1).encode())
            )
            return cls(path, key)
        stored = json.loads(stored_file.read_text())
        differences = _differences(dict(fingerprint), stored)
        if differences:
            raise CheckpointMismatch(
                f"checkpoint {str(path)!r} belongs to another batch: {'; '.join(differences)}. "
                f"Resume with the arguments that started it, or give another checkpoint "
                f"directory (delete this one to start over)"
            )
        return cls(path, int(stored["key"]))

    def finished(self) -> dict[int, dict[str, np.ndarray]]:
        """The chunks on disk.

        Returns:
            For each finished chunk, the index of its first target → its result arrays.

        Raises:
            CheckpointMismatch: A chunk file that cannot be read (it was not written by
                :meth:`save`, which never leaves a partial file).
        """
        chunks = {}
        for file in sorted(self.path.glob(CHUNK_PATTERN)):
            try:
                with np.load(file, allow_pickle=False) as data:
                    chunks[int(file.stem.removeprefix("chunk-"))] = dict(data)
            except (OSError, ValueError) as error:
                raise CheckpointMismatch(
                    f"checkpoint chunk {str(file)!r} cannot be read ({error}); delete it and "
                    f"it will be solved again"
                ) from None
        return chunks

    def save(self, first: int, arrays: Mapping[str, Any]) -> None:
        """Write a finished chunk atomically (see the module docstring).

        Args:
            first: Index in the batch of the chunk's first target.
            arrays: The chunk's result arrays, by name.
        """
        _write_atomic(self.path / f"chunk-{first:012d}.npz", lambda file: np.savez(file, **arrays))

    def __repr__(self) -> str:
        return f"Checkpoint({str(self.path)!r})"


def _write_atomic(path: Path, write: Callable[[IO[bytes]], object]) -> None:
    """``write`` into a temporary beside ``path``, flush it to disk and rename it onto ``path``."""
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(temporary, "wb") as file:
        write(file)
        file.flush()
        os.fsync(file.fileno())
    os.replace(temporary, path)
    if hasattr(os, "O_DIRECTORY"):  # the rename itself reaches the disk (POSIX)
        directory = os.open(path.parent, os.O_RDONLY | os.O_DIRECTORY)
        try:
            os.fsync(directory)
        finally:
            os.close(directory)


def _differences(current: dict[str, Any], stored: dict[str, Any]) -> list[str]:
    """Every fingerprint entry that differs, as ``"name: <here> here, <there> in the checkpoint"``.

    The ``key`` is not compared: it follows from the seed, or is the stored draw.
    """
    names = sorted((current.keys() | stored.keys()) - {"key"})
    return [
        f"{name}: {_shown(current.get(name))} here, {_shown(stored.get(name))} in the checkpoint"
        for name in names
        if current.get(name) != stored.get(name)
    ]


def _shown(value: object) -> str:
    """A fingerprint value for a message: digests shortened, anything else as repr."""
    if isinstance(value, str) and value.startswith("sha256:"):
        return value[:19] + "…"
    return "(none)" if value is None else repr(value)
