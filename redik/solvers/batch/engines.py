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
    ``pip install "redik[ray]"``; every node of a cluster needs the same redik installed.

**A worker that dies does not change the results.** A chunk is a pure function of its
targets, seeds, options and random key, so running it again gives the same bits. When the
process that runs a chunk dies (killed, out of memory, its node lost), the chunk runs again,
up to ``retries`` times (default :data:`RETRIES`): on ``"ray"`` Ray re-submits the task
(``max_retries``; an exception raised by the chunk function is not retried, since it would be
raised again), on ``"process"`` the broken pool is replaced and every chunk it lost is
submitted to the new one. A chunk whose worker dies on every attempt — one that exhausts
memory or crashes in compiled code — ends the map with a
:class:`~redik.core.exceptions.BackendError`.

**Ray clusters with token authentication.** Ray (≥ 2.52) authenticates every node and driver
of a cluster with one shared token when ``RAY_AUTH_MODE=token`` is in their environment. Ray
2.60 turns it on by itself for a local instance of ``ray.init()`` and for a ``ray start
--head`` that finds a token in ``~/.ray/auth_token``, but not for a node joining with ``ray
start --address`` nor for a driver given an address: give those the mode and the token. Make
the token once (``ray get-auth-token --generate`` prints it and saves it as
``~/.ray/auth_token``); each process reads it from ``RAY_AUTH_TOKEN``, else from the file
named by ``RAY_AUTH_TOKEN_PATH``, else from ``~/.ray/auth_token``::

    export RAY_AUTH_MODE=token RAY_AUTH_TOKEN=$(ray get-auth-token --generate)
    ray start --head --node-ip-address HEAD_IP --port 6379          # on the head
    ray start --address HEAD_IP:6379 --node-ip-address NODE_IP      # on each other node
    redik batch panda --random 100000 --engine ray --address HEAD_IP:6379 --out q.npz

The token is a secret: copy it to the other machines as you would a password, and export the
same two variables there. Ray reads them when it is imported: set them before the driver
starts, not from inside it. A driver without
``RAY_AUTH_MODE=token`` is refused by such a cluster even when it has the token; Ray reports
that only as a failure to connect, which redik raises as a
:class:`~redik.core.exceptions.BackendError` naming the two variables.

**Who owns the workers.** An engine owns what it starts — the process pool, the local Ray
instance, or its connection to a cluster — keeps it between calls and releases it in
:meth:`Engine.close` (or at the end of a ``with`` block)::

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
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from redik.core.exceptions import BackendError, InvalidInput
from redik.core.validate import integer

ENGINES = ("local", "process", "ray")

RETRIES = 3
"""Times a chunk runs again after the process running it died (Ray's own default for tasks):
enough for a killed worker or a lost node now and then, few enough that a chunk which kills
its worker every time fails within four attempts instead of looping."""


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
        retries: Times a chunk runs again after the process running it died (see the module
            docstring); default :data:`RETRIES`.

    The process pool or local Ray instance starts on the first :meth:`map` and is kept until
    :meth:`close`; an engine is a context manager that closes itself. A ``"process"`` engine
    with one worker runs in this process (no pool to start). :meth:`map` may be called from
    several threads; each call keeps its own results in order.

    Raises:
        InvalidInput: an unknown kind, a worker count that is not a positive integer, a
            negative retry count, or an address for a kind other than ``"ray"``.
    """

    def __init__(
        self,
        kind: str = "local",
        workers: int | None = None,
        address: str | None = None,
        retries: int = RETRIES,
    ):
        if not isinstance(kind, str) or kind not in ENGINES:
            raise InvalidInput(f"engine must be one of {ENGINES}, got {kind!r}")
        workers = integer(workers, "workers", 1, allow_none=True)
        self.retries = integer(retries, "retries", 0)
        if address is not None and (kind != "ray" or not isinstance(address, str)):
            raise InvalidInput(
                f"address is a Ray cluster address (a string) for kind 'ray', got {address!r} "
                f"for kind {kind!r}"
            )
        self.kind = kind
        self.workers = workers if workers is not None else default_workers()
        self.address = address
        self._pool: ProcessPoolExecutor | None = None
        self._ray_owned = False  # this engine started the local Ray instance or connected
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
            BackendError: a ``"ray"`` engine without Ray installed or that cannot reach its
                cluster, or a chunk whose worker died on all ``1 + retries`` attempts.
        """
        if self._closed:
            raise InvalidInput(f"{self!r} is closed; create a new Engine")
        if self.in_process:
            results: Iterator[Any] = (function(shared, *chunk) for chunk in chunks)
        elif self.kind == "process":
            results = self._process_results(function, shared, chunks)
        else:
            results = self._ray_results(function, shared, chunks)
        collected = []
        for result in results:
            if on_result is not None:
                on_result(result)
            collected.append(result)
        return collected

    def close(self, wait: bool = True) -> None:
        """Shut down what this engine started: the process pool, or the Ray instance.

        A Ray cluster at ``address`` keeps running; this process disconnects from it. Closing
        twice is harmless.

        Args:
            wait: Wait until the pool's workers have exited; else cancel the pending chunks
                and return at once.
        """
        with self._lock:
            self._closed = True
            pool, self._pool = self._pool, None
            ray_owned, self._ray_owned = self._ray_owned, False
        if pool is not None:
            pool.shutdown(wait=wait, cancel_futures=not wait)
        if ray_owned:
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

    def _process_results(
        self, function: Callable[..., Any], shared: Any, chunks: Iterable[tuple]
    ) -> Iterator[Any]:
        """The results of the chunks on the pool, in order, ``2 × workers`` in flight."""
        pending: deque[_Attempt] = deque()
        for chunk in chunks:
            pending.append(_Attempt(self._process_pool(), function, shared, chunk))
            if len(pending) >= 2 * self.workers:
                yield self._process_result(pending)
        while pending:
            yield self._process_result(pending)

    def _process_result(self, pending: deque[_Attempt]) -> Any:
        """The result of the first pending chunk.

        A worker that dies breaks the whole pool: every pending chunk it lost then runs again
        on a new pool.
        """
        while True:
            head = pending[0]
            try:
                result = head.future.result()
            except BrokenProcessPool as error:
                broken = head.pool
                lost = [attempt for attempt in pending if attempt.lost(broken)]
                if any(attempt.number >= self.retries for attempt in lost):
                    self._drop_pool(broken)
                    raise BackendError(
                        f"a worker process died {self.retries + 1} times while a chunk was "
                        f"in flight (out of memory, or a crash in compiled code?); {self!r} "
                        f"runs a chunk again at most {self.retries} times"
                    ) from error
                self._drop_pool(broken)
                pool = self._process_pool()
                for attempt in lost:
                    attempt.retry(pool)
            else:
                pending.popleft()
                return result

    def _drop_pool(self, broken: ProcessPoolExecutor) -> None:
        """Forget the ``broken`` pool, so that the next chunk starts a new one.

        Another map may have replaced it already; its replacement is kept.
        """
        with self._lock:
            if self._pool is broken:
                self._pool = None
        broken.shutdown(wait=False, cancel_futures=True)

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
                self._ray_init(ray)
        task = ray.remote(num_cpus=1, max_retries=self.retries, retry_exceptions=False)(function)
        shared_ref = ray.put(shared)
        in_flight = 2 * max(self.workers, int(ray.cluster_resources().get("CPU", self.workers)))

        def submit(chunk: tuple) -> Future:
            return task.remote(shared_ref, *chunk)

        def result(ref: Any) -> Any:
            try:
                return ray.get(ref)
            except (ray.exceptions.WorkerCrashedError, ray.exceptions.NodeDiedError) as error:
                raise BackendError(
                    f"the Ray worker running a chunk died on each of its {self.retries + 1} "
                    f"attempts (out of memory, or a crash in compiled code?): {error}"
                ) from error

        return _bounded(submit, chunks, result, in_flight)

    def _ray_init(self, ray: Any) -> None:
        """Start a local Ray instance of ``workers`` CPUs, or connect to ``address``."""
        if self.address is None:
            ray.init(num_cpus=self.workers, include_dashboard=False, log_to_driver=False)
        else:
            try:
                ray.init(address=self.address, log_to_driver=False)
            except (ConnectionError, _ray_authentication_error(ray)) as error:
                raise BackendError(
                    f"cannot connect to the Ray cluster at {self.address!r} ({error}). Is it "
                    f"running there? A cluster with token authentication also needs "
                    f"RAY_AUTH_MODE=token and its token (RAY_AUTH_TOKEN, or "
                    f"~/.ray/auth_token) in this process's environment before Ray is imported "
                    f"(see redik.solvers.batch.engines)"
                ) from error
        self._ray_owned = True


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
    """The shared :class:`Engine` an engine name stands for.

    It is created on first use, kept for later calls, and closed at exit or by
    :func:`close_shared_engines`.

    Args:
        kind: As :class:`Engine`.
        workers: As :class:`Engine`.
        address: As :class:`Engine`.

    Returns:
        The engine of that kind, worker count and address.

    Raises:
        InvalidInput: as :class:`Engine`.
    """
    return _SHARED.get(kind, workers, address)


def close_shared_engines(wait: bool = True) -> None:
    """Close every shared engine; the next engine name starts a new one.

    Args:
        wait: As :meth:`Engine.close`.
    """
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
    """``[function(shared, *chunk) for chunk in chunks]`` on ``engine``, in chunk order.

    Args:
        function: As :meth:`Engine.map`.
        shared: As :meth:`Engine.map`.
        chunks: As :meth:`Engine.map`.
        engine: An :class:`Engine` or the name of a shared one (:func:`as_engine`).
        workers: As :func:`as_engine`.
        address: As :func:`as_engine`.
        on_result: As :meth:`Engine.map`.

    Returns:
        The results, in chunk order.

    Raises:
        InvalidInput: unknown engine or a non-positive worker count.
        BackendError: ``engine="ray"`` without Ray installed.
    """
    return as_engine(engine, workers, address).map(function, shared, chunks, on_result)


def _ray_authentication_error(ray: Any) -> type[Exception]:
    """Ray's error for a missing token (Ray before 2.52 has no tokens, nor this error)."""
    return getattr(ray.exceptions, "AuthenticationError", ConnectionError)


class _Attempt:
    """A chunk submitted to a process pool: its future, and how many times it ran again."""

    def __init__(self, pool: ProcessPoolExecutor, function: Callable, shared: Any, chunk: tuple):
        self.function, self.shared, self.chunk = function, shared, chunk
        self.number = 0
        self._submit(pool)

    def lost(self, broken: ProcessPoolExecutor) -> bool:
        """Whether the chunk died with the ``broken`` pool.

        A chunk that finished before the pool broke keeps its result.
        """
        return self.pool is broken and isinstance(self.future.exception(), BrokenProcessPool)

    def retry(self, pool: ProcessPoolExecutor) -> None:
        """Submit the chunk again, to ``pool``."""
        self.number += 1
        self._submit(pool)

    def _submit(self, pool: ProcessPoolExecutor) -> None:
        self.pool = pool
        try:
            self.future = pool.submit(self.function, self.shared, *self.chunk)
        except BrokenProcessPool as error:  # broke since it was handed out: lost like the rest
            self.future = Future()
            self.future.set_exception(error)


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
