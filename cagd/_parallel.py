"""Chunks of work in a pool of worker processes on one machine, results in order
(issue 16, scan scale; stdlib only).

:func:`ordered_map` runs ``task(shared, item)`` for every item: in this process when
``workers`` is 1, else in a :class:`concurrent.futures.ProcessPoolExecutor` started with
the ``spawn`` method (the same on Linux, macOS and Windows; no state inherited from
this process). ``shared`` (the model's objects) is pickled once here and unpickled once
per worker by the pool's initializer, not sent with every item; items and results travel
one by one. At most IN_FLIGHT_PER_WORKER x workers items are submitted and not yet
taken, so memory stays bounded whatever the number of items; results come back in the
order of the items (a caller writing them gets the serial run's output).

Any failure in a worker (an exception, a worker process that dies, a result not there
after ``timeout`` seconds) raises :class:`cagd.CagdError` naming the item; the pool is
then shut down with its pending items cancelled and its processes terminated, so a
failure never leaves the caller waiting.
"""
from __future__ import annotations

import multiprocessing
import pickle
from collections import deque
from concurrent.futures import Future, ProcessPoolExecutor, TimeoutError as FutureTimeout
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Deque, Iterable, Iterator, Optional, Tuple, TypeVar

from . import _checks
from .errors import CagdError

__all__ = ["ordered_map", "checked_workers"]

S = TypeVar("S")
T = TypeVar("T")
R = TypeVar("R")

#: items submitted per worker before the oldest result is taken (bounds the memory held
#: by items and results in flight: about 2 x workers of them)
IN_FLIGHT_PER_WORKER = 2
#: seconds allowed for the pool's processes to end after a failure (they are terminated)
STOP_WAIT = 10.0

# per worker process: the shared value unpickled by the initializer, or why it failed
_SHARED: Any = None
_SHARED_ERROR: Optional[str] = None


def checked_workers(workers: Any, name: str = "workers") -> int:
    """``workers`` validated: an int >= 1 (bools and fractions refused, naming ``name``)."""
    return _checks.integer(workers, name, 1)


def _start_worker(blob: bytes) -> None:
    """The pool's initializer: unpickle the shared value once for this process. A failure
    is kept and reported by every task (an initializer that raises breaks the pool with
    a message that names nothing)."""
    global _SHARED, _SHARED_ERROR
    try:
        _SHARED = pickle.loads(blob)
    except BaseException as exc:            # reported with the first item this worker takes
        _SHARED_ERROR = f"{type(exc).__name__}: {exc}"


def _run(task: Callable[[Any, Any], Any], item: Any) -> Any:
    if _SHARED_ERROR is not None:
        raise RuntimeError(f"the shared objects could not be loaded in the worker ({_SHARED_ERROR})")
    return task(_SHARED, item)


def ordered_map(task: Callable[[S, T], R], shared: S, items: Iterable[T], workers: int = 1, *,
                timeout: Optional[float] = None, name: Callable[[int], str] = "chunk {}".format
                ) -> Iterator[R]:
    """``task(shared, item)`` for every item, yielded in the order of the items.

    Args:
        task: a module-level function (it is pickled by reference for the workers).
        shared: what every item needs (pickled once, unpickled once per worker).
        items: an iterable, consumed as the pool has room (at most IN_FLIGHT_PER_WORKER x
            workers items are held at once).
        workers: 1 runs here, in order, without pickling (errors propagate unchanged);
            more runs a pool of that many processes.
        timeout: seconds to wait for the next result (None: no limit).
        name: the item's name in error messages, from its index.

    Raises:
        CagdError: bad ``workers`` or ``timeout``; ``shared`` cannot be pickled; a task
            raised, its process died or its result took longer than ``timeout`` (naming
            the item: ``name(index)``).
    """
    workers = checked_workers(workers)
    if timeout is not None:
        timeout = _checks.positive(timeout, "timeout")
    if workers == 1:
        for item in items:
            yield task(shared, item)
        return
    try:
        blob = pickle.dumps(shared, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:
        raise CagdError(f"workers: the objects cannot be sent to worker processes ({type(exc).__name__}: "
                        f"{exc})") from None
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_start_worker, initargs=(blob,))
    pending: Deque[Tuple[int, Future]] = deque()
    done = False
    try:
        for index, item in enumerate(items):
            if len(pending) >= IN_FLIGHT_PER_WORKER * workers:
                yield _result(*pending.popleft(), timeout, name)
            try:
                future = pool.submit(_run, task, item)
            except BrokenProcessPool as exc:    # a worker died: the items before say which
                future = Future()
                future.set_exception(exc)
            pending.append((index, future))
        while pending:
            yield _result(*pending.popleft(), timeout, name)
        done = True
    finally:
        if done:
            pool.shutdown(wait=True)
        else:                               # a failure, or the caller stopped early
            _stop(pool, [f for _, f in pending])


def _result(index: int, future: Future, timeout: Optional[float], name: Callable[[int], str]) -> Any:
    """The future's result, or a CagdError naming the item."""
    try:
        return future.result(timeout=timeout)
    except FutureTimeout:
        raise CagdError(f"workers: {name(index)} gave no result within {timeout:g} s") from None
    except BrokenProcessPool as exc:
        # the whole pool is broken: the first item without a result is named (the process
        # that died may have held a later one)
        raise CagdError(f"workers: {name(index)} was not finished: a worker process ended abruptly "
                        f"({str(exc).rstrip('.')}; out of memory? a script run by python that starts workers "
                        f"needs its code under `if __name__ == \"__main__\":`, which spawned workers do not run)"
                        ) from None
    except CagdError as exc:
        raise CagdError(f"workers: {name(index)}: {exc}") from exc
    except Exception as exc:
        raise CagdError(f"workers: {name(index)} failed: {type(exc).__name__}: {exc}") from exc


def _stop(pool: ProcessPoolExecutor, pending: list) -> None:
    """Cancel what has not started, terminate the worker processes (a task that runs on
    would keep the pool, and the caller, waiting) and reap them: after the pool's own
    manager thread has ended (it joins the processes too; two threads reaping one
    process can leave it listed as running)."""
    for f in pending:
        f.cancel()
    procs = list((getattr(pool, "_processes", None) or {}).values())     # (private; Python 3.14 has terminate_workers)
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    if manager is not None:
        manager.join(STOP_WAIT)
    for p in procs:
        p.join(STOP_WAIT)
        if p.is_alive():
            p.kill()
            p.join(STOP_WAIT)
