"""What solvers compile once per robot, owned by the robot and safe to share between threads.

A solver that needs per-robot preparation (the compiled chain and buffers of
:func:`redik.solve_pose`'s ``"dls"`` kernel, the chain a whole-model robot is solved on)
keeps it in :attr:`Robot.solver_cache <redik.kinematics.robot.Robot.solver_cache>` under a key
of its own, so it lives and dies with the robot rather than in a module-level table.
:meth:`SolverCache.get_or_build` builds an entry at most once however many threads ask for it
at the same moment.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Hashable, Iterator, MutableMapping
from typing import Any, TypeVar

T = TypeVar("T")


class SolverCache(MutableMapping[Hashable, Any]):
    """A dictionary of per-robot solver state whose build-and-insert is atomic.

    Reads take no lock (a dictionary lookup is atomic in CPython); :meth:`get_or_build` takes
    the cache's re-entrant lock around the check, the build and the insert, so two threads
    asking for the same missing entry build it once and both receive that one. The entries
    themselves must be safe to share between threads if the robot is (those of redik's
    solvers are).
    """

    def __init__(self) -> None:
        self._entries: dict[Hashable, Any] = {}
        self._lock = threading.RLock()

    def get_or_build(
        self, key: Hashable, build: Callable[[], T], valid: Callable[[T], bool] | None = None
    ) -> T:
        """The entry under ``key``, built by ``build()`` and stored first when missing or
        when ``valid(entry)`` is False (e.g. it was built for other held joint values)."""
        entry = self._entries.get(key)
        if entry is not None and (valid is None or valid(entry)):
            return entry
        with self._lock:
            entry = self._entries.get(key)
            if entry is None or (valid is not None and not valid(entry)):
                entry = self._entries[key] = build()
            return entry

    def __getitem__(self, key: Hashable) -> Any:
        return self._entries[key]

    def __setitem__(self, key: Hashable, value: Any) -> None:
        with self._lock:
            self._entries[key] = value

    def __delitem__(self, key: Hashable) -> None:
        with self._lock:
            del self._entries[key]

    def __iter__(self) -> Iterator[Hashable]:
        return iter(list(self._entries))

    def __len__(self) -> int:
        return len(self._entries)

    def __repr__(self) -> str:
        return f"SolverCache({list(self._entries)!r})"
