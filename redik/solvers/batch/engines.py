"""Where the chunks of a batch run: this process, a local process pool, or Ray.

An :class:`Engine` maps a picklable ``function(shared, *chunk)`` over a stream of chunks and
returns the results in chunk order. It knows nothing about kinematics: determinism comes from
each chunk carrying its own random seed, so a result never depends on which worker ran a chunk
or how many there were. At most ``2 × workers`` chunks are in flight, so memory stays bounded
however long the stream is.

``"local"``
    One chunk after another in this process (one core).
``"process"``
    A :class:`concurrent.futures.ProcessPoolExecutor` of ``workers`` processes (default: every
    core), started by ``fork`` where available on the first :meth:`Engine.map`.
``"ray"``
    Ray tasks on the cluster at ``address``, or on a local Ray instance started with
    ``workers`` CPUs when Ray is not initialised and no address is given. Ray is optional:
    ``pip install "redik[ray]"``.

**Who owns the workers.** An engine owns what it starts — the process pool, or the local Ray
instance — keeps it between calls and releases it in :meth:`Engine.close` (or at the end of a
``with`` block)::

    with Engine("process", workers=8) as engine:
        for T in batches:
            solve_batch(chain, T, engine=engine)  # one pool, started once

An engine *name* (``solve_batch(..., engine="process")``) uses the shared engine of that
name, worker count and address (:func:`shared_engine`): it is created on first use and kept
for later calls, so a script that solves batch after batch starts its pool once. Shared
engines are closed at interpreter exit, or earlier by :func:`close_shared_engines`.
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any

from redik.core.exceptions import BackendError, InvalidInput
from redik.core.validate import integer

ENGINES = ("local", "process", "ray")


def default_workers() -> int:
    """Every core this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class Engine:
    """Runs chunks of work on ``kind`` (:data:`ENGINES`) and owns the workers it starts.

    Args:
        kind: ``"local"``, ``"process"`` or ``"ray"`` (see the module docstring).
        workers: Processes or Ray CPUs (on ``"local"``, the threads a chunk function may use);
            default every core this process may use (:func:`default_workers`).
        address: Ray cluster address (``kind="ray"`` only); default a local Ray instance.

    The process pool or local Ray instance starts on the first :meth:`map` and is kept until
    :meth:`close`; an engine is a context manager that closes itself. A ``"process"`` engine
    with one worker runs in this process (no pool to start). :meth:`map` may be called from
    several threads; each call keeps its own results in order.

    Raises:
        InvalidInput: an unknown kind, a worker count that is not a positive integer, or an
            address for a kind other than ``"ray"``.
    """

    def __init__(self, kind: str = "local", workers: int | None = None, address: str | None = None):
        if not isinstance(kind, str) or kind not in ENGINES:
            raise InvalidInput(f"engine must be one of {ENGINES}, got {kind!r}")
        workers = integer(workers, "workers", 1, allow_none=True)
        if address is not None and (kind != "ray" or not isinstance(address, str)):
            raise InvalidInput(
                f"address is a Ray cluster address (a string) for kind 'ray', got {address!r} "
                f"for kind {kind!r}"
            )
        self.kind = kind
        self.workers = workers if workers is not None else default_workers()
        self.address = address
        self._pool: ProcessPoolExecutor | None = None
        self._started_ray = False
        self._closed = False
        self._lock = threading.Lock()

    @property
    def closed(self) -> bool:
        """True after :meth:`close`."""
        return self._closed

    @property
    def in_process(self) -> bool:
        """True when chunks run in this process (``"local"``, or one ``"process"`` worker)."""
        return self.kind == "local" or (self.kind == "process" and self.workers == 1)

    def map(
        self,
        function: Callable[..., Any],
        shared: Any,
        chunks: Iterable[tuple],
        on_result: Callable[[Any], None] | None = None,
    ) -> list[Any]:
        """``[function(shared, *chunk) for chunk in chunks]`` on this engine, in chunk order.

        ``on_result`` is called with each result as it arrives (in chunk order), e.g. to
        advance a progress bar.

        Raises:
            InvalidInput: the engine is closed.
            BackendError: a ``"ray"`` engine without Ray installed.
        """
        if self._closed:
            raise InvalidInput(f"{self!r} is closed; create a new Engine")
        if self.in_process:
            results: Iterator[Any] = (function(shared, *chunk) for chunk in chunks)
        elif self.kind == "process":
            pool = self._process_pool()
            results = _bounded(
                lambda chunk: pool.submit(function, shared, *chunk),
                chunks,
                lambda future: future.result(),
                2 * self.workers,
            )
        else:
            results = self._ray_results(function, shared, chunks)
        collected = []
        for result in results:
            if on_result is not None:
                on_result(result)
            collected.append(result)
        return collected

    def close(self, wait: bool = True) -> None:
        """Shut down the process pool (``wait``: until its workers have exited; else cancel
        the pending chunks and return at once) or the Ray instance this engine started.
        Closing twice is harmless."""
        with self._lock:
            self._closed = True
            pool, self._pool = self._pool, None
            started_ray, self._started_ray = self._started_ray, False
        if pool is not None:
            pool.shutdown(wait=wait, cancel_futures=not wait)
        if started_ray:
            import ray

            ray.shutdown()

    def __enter__(self) -> Engine:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._closed else "started" if self._pool else "idle"
        where = f", address={self.address!r}" if self.address else ""
        return f"Engine({self.kind!r}, workers={self.workers}{where}; {state})"

    def _process_pool(self) -> ProcessPoolExecutor:
        with self._lock:
            if self._closed:
                raise InvalidInput(f"{self!r} is closed; create a new Engine")
            if self._pool is None:
                # fork: workers start at once and unguarded scripts (no `if __name__ ==
                # "__main__"`) work; where there is no fork, the chunk function and its data
                # pickle for spawn.
                method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
                self._pool = ProcessPoolExecutor(
                    self.workers, mp_context=multiprocessing.get_context(method)
                )
            return self._pool

    def _ray_results(
        self, function: Callable[..., Any], shared: Any, chunks: Iterable[tuple]
    ) -> Iterator[Any]:
        try:
            import ray
        except ImportError:
            raise BackendError(
                'engine="ray" needs Ray, which is not installed: pip install "redik[ray]"'
            ) from None
        with self._lock:
            if not ray.is_initialized():
                if self.address is None:
                    ray.init(num_cpus=self.workers, include_dashboard=False, log_to_driver=False)
                    self._started_ray = True
                else:
                    ray.init(address=self.address, log_to_driver=False)
        task = ray.remote(num_cpus=1)(function)
        shared_ref = ray.put(shared)
        in_flight = 2 * max(self.workers, int(ray.cluster_resources().get("CPU", self.workers)))

        def submit(chunk: tuple) -> Future:
            return task.remote(shared_ref, *chunk)

        return _bounded(submit, chunks, ray.get, in_flight)


class _SharedEngines:
    """The engines that engine names stand for, one per (kind, workers, address)."""

    def __init__(self) -> None:
        self._engines: dict[tuple[str, int, str | None], Engine] = {}
        self._lock = threading.Lock()

    def get(self, kind: str, workers: int | None, address: str | None) -> Engine:
        probe = Engine(kind, workers, address)  # validates; holds nothing until used
        key = (probe.kind, probe.workers, probe.address)
        with self._lock:
            engine = self._engines.get(key)
            if engine is None or engine.closed:
                engine = self._engines[key] = probe
            return engine

    def close(self, wait: bool = True) -> None:
        with self._lock:
            engines, self._engines = list(self._engines.values()), {}
        for engine in engines:
            engine.close(wait=wait)


_SHARED = _SharedEngines()
atexit.register(_SHARED.close, wait=False)


def shared_engine(kind: str, workers: int | None = None, address: str | None = None) -> Engine:
    """The shared :class:`Engine` an engine name stands for (created on first use, kept for
    later calls, closed at exit or by :func:`close_shared_engines`).

    Raises:
        InvalidInput: as :class:`Engine`.
    """
    return _SHARED.get(kind, workers, address)


def close_shared_engines(wait: bool = True) -> None:
    """Close every shared engine (their pools stop now, not at exit); the next engine name
    starts a new one."""
    _SHARED.close(wait=wait)


def as_engine(
    engine: str | Engine, workers: int | None = None, address: str | None = None
) -> Engine:
    """``engine`` itself, or the shared engine of that name (:func:`shared_engine`).

    Raises:
        InvalidInput: an unknown name, bad ``workers`` or ``address``, or ``workers`` or
            ``address`` given beside an :class:`Engine` (it has its own).
    """
    if isinstance(engine, Engine):
        if workers is not None or address is not None:
            raise InvalidInput(
                f"workers and address belong to the engine ({engine!r}); pass them to Engine(), "
                f"not beside it (got workers={workers!r}, address={address!r})"
            )
        return engine
    return shared_engine(engine, workers, address)


def map_chunks(
    function: Callable[..., Any],
    shared: Any,
    chunks: Iterable[tuple],
    engine: str | Engine,
    workers: int | None = None,
    address: str | None = None,
    on_result: Callable[[Any], None] | None = None,
) -> list[Any]:
    """``[function(shared, *chunk) for chunk in chunks]`` on ``engine`` (an :class:`Engine` or
    a name, :func:`as_engine`), in chunk order; ``on_result`` as in :meth:`Engine.map`.

    Raises:
        InvalidInput: unknown engine or a non-positive worker count.
        BackendError: ``engine="ray"`` without Ray installed.
    """
    return as_engine(engine, workers, address).map(function, shared, chunks, on_result)


def _bounded(
    submit: Callable[[tuple], Any],
    chunks: Iterable[tuple],
    wait: Callable[[Any], Any],
    in_flight: int,
) -> Iterator[Any]:
    """Submit chunks keeping at most ``in_flight`` pending, and yield results in order."""
    pending: deque = deque()
    for chunk in chunks:
        pending.append(submit(chunk))
        if len(pending) >= in_flight:
            yield wait(pending.popleft())
    while pending:
        yield wait(pending.popleft())
