"""What solvers compile once per robot, kept as long as the robot lives, safe between threads.

A solver that needs per-robot preparation (the compiled chain and buffers of
:func:`redik.solve_pose`'s ``"dls"`` kernel, the chain a whole-model robot is solved on, the
closed-form solver of a robot) keeps it in :func:`solver_cache` ``(robot)`` under a key of its
own. Each cache lives and dies with its robot (a :func:`weakref.finalize` drops it when the robot
is collected, so the ``id`` it is found under is never a later robot's), and two robots never
share one. :meth:`SolverCache.get_or_build` builds an entry at most once however many threads
ask for it at the same moment. Both look-ups are plain dictionary reads: :func:`redik.solve_pose`
makes them on every call.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Hashable, Iterator, MutableMapping
from typing import Any, TypeVar

from redik.kinematics.robot import Robot

T = TypeVar("T")

_CACHES: dict[int, SolverCache] = {}
_CACHES_LOCK = threading.Lock()


def solver_cache(robot: Robot) -> SolverCache:
    """The robot's solver cache, made on first use.

    Args:
        robot: The robot the cached state was built for.

    Returns:
        Its :class:`SolverCache`; every call for one robot returns the same one, whichever
        thread asks first.
    """
    cache = _CACHES.get(id(robot))
    if cache is None:
        with _CACHES_LOCK:
            cache = _CACHES.get(id(robot))
            if cache is None:
                cache = _CACHES[id(robot)] = SolverCache()
                weakref.finalize(robot, _CACHES.pop, id(robot), None)
    return cache


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
        """The entry under ``key``, built and stored first when missing or out of date.

        Args:
            key: The solver's key.
            build: Makes the entry, called under the cache's lock.
            valid: False for an entry that must be rebuilt (e.g. it was built for other held
                joint values); every entry is valid when None.

        Returns:
            The entry.
        """
        entry = self._entries.get(key)
        if entry is not None and (valid is None or valid(entry)):
            return entry
        with self._lock:
            entry = self._entries.get(key)
            if entry is None or (valid is not None and not valid(entry)):
                entry = self._entries[key] = build()
            return entry

    def get(self, key: Hashable, default: Any = None) -> Any:
        """The entry under ``key``, or ``default``: one dictionary read, no lock."""
        return self._entries.get(key, default)

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
