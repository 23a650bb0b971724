"""Where the chunks of a batch run: this process, a local process pool, or Ray.

An engine maps a picklable ``function(shared, *chunk)`` over a stream of chunks and returns
the results in chunk order. It knows nothing about kinematics: determinism comes from each
chunk carrying its own random seed, so a result never depends on which worker ran a chunk
or how many there were. At most ``2 × workers`` chunks are in flight, so memory stays
bounded however long the stream is.

``"local"``
    One chunk after another in this process (one core).
``"process"``
    A :class:`concurrent.futures.ProcessPoolExecutor` of ``workers`` processes (default: every
    core), started by ``fork`` where available, and kept for later calls.
``"ray"``
    Ray tasks on the cluster at ``address``, or on a local Ray instance started with
    ``workers`` CPUs when Ray is not initialised and no address is given. Ray is optional:
    ``pip install "redik[ray]"``.
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any

from redik.core.exceptions import BackendError, InvalidInput

ENGINES = ("local", "process", "ray")

_POOLS: dict[int, ProcessPoolExecutor] = {}


def default_workers() -> int:
    """Every core this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def map_chunks(
    function: Callable[..., Any],
    shared: Any,
    chunks: Iterable[tuple],
    engine: str,
    workers: int | None = None,
    address: str | None = None,
    on_result: Callable[[Any], None] | None = None,
) -> list[Any]:
    """``[function(shared, *chunk) for chunk in chunks]`` on ``engine``, in chunk order.

    ``on_result`` is called with each result as it arrives (in chunk order), e.g. to advance
    a progress bar.

    Raises:
        InvalidInput: unknown engine or a non-positive worker count.
        BackendError: ``engine="ray"`` without Ray installed.
    """
    if engine not in ENGINES:
        raise InvalidInput(f"engine must be one of {ENGINES}, got {engine!r}")
    if workers is not None and workers < 1:
        raise InvalidInput(f"workers must be a positive integer, got {workers!r}")
    workers = workers or default_workers()
    if engine == "local" or (engine == "process" and workers == 1):
        results = (function(shared, *chunk) for chunk in chunks)
    elif engine == "process":
        results = _bounded(
            lambda chunk: _pool(workers).submit(function, shared, *chunk),
            chunks,
            lambda future: future.result(),
            2 * workers,
        )
    else:
        results = _ray_results(function, shared, chunks, workers, address)
    collected = []
    for result in results:
        if on_result is not None:
            on_result(result)
        collected.append(result)
    return collected


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


def _pool(workers: int) -> ProcessPoolExecutor:
    pool = _POOLS.get(workers)
    if pool is None:
        # fork: workers start at once and unguarded scripts (no `if __name__ == "__main__"`)
        # work; where there is no fork, the chunk function and its data pickle for spawn.
        method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
        pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context(method))
        _POOLS[workers] = pool
    return pool


@atexit.register
def _shutdown_pools() -> None:
    for pool in _POOLS.values():
        pool.shutdown(wait=False, cancel_futures=True)
    _POOLS.clear()


def _ray_results(
    function: Callable[..., Any],
    shared: Any,
    chunks: Iterable[tuple],
    workers: int,
    address: str | None,
) -> Iterator[Any]:
    try:
        import ray
    except ImportError:
        raise BackendError(
            'engine="ray" needs Ray, which is not installed: pip install "redik[ray]"'
        ) from None
    if not ray.is_initialized():
        if address is None:
            ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
    task = ray.remote(num_cpus=1)(function)
    shared_ref = ray.put(shared)
    in_flight = 2 * max(workers, int(ray.cluster_resources().get("CPU", workers)))

    def submit(chunk: tuple) -> Future:
        return task.remote(shared_ref, *chunk)

    return _bounded(submit, chunks, ray.get, in_flight)
