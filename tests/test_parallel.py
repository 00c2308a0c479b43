"""cagd._parallel.ordered_map (issue 16, scan scale): a pool of spawned worker processes
whose results come back in the order of the items, equal to the serial run's; memory
bounded by the items in flight; every failure in a worker (an exception, a process that
dies, a result that does not come, shared objects that do not load) a CagdError naming
the item, with the pool's processes ended. The tasks are stdlib functions (``eval`` of
an expression over the item), importable by the spawned workers."""
import multiprocessing
import operator
import re
import threading
import time

import pytest

from cagd import CagdError
from cagd._parallel import IN_FLIGHT_PER_WORKER, checked_workers, ordered_map


def no_children_left(wait: float = 30.0):
    """The pool's processes end (a failure must not leave one running: the tasks that
    fail here would run for 10 minutes); idle ones may take a moment on a loaded machine."""
    end = time.monotonic() + wait
    while multiprocessing.active_children() and time.monotonic() < end:
        time.sleep(0.1)
    left = multiprocessing.active_children()
    assert not left, [(p.name, p.pid, p.exitcode) for p in left]
    return True


def test_results_in_order_equal_to_the_serial_run():
    items = [{"x": k} for k in range(23)]
    expr = "(x * 7919) % 101 - x ** 0.5"                 # the oracle: Python evaluating it here
    want = [eval(expr, dict(i)) for i in items]
    assert list(ordered_map(eval, expr, [dict(i) for i in items], 1)) == want
    assert list(ordered_map(eval, expr, [dict(i) for i in items], 3)) == want
    assert no_children_left()


def test_items_are_taken_as_the_pool_has_room():
    """At most IN_FLIGHT_PER_WORKER x workers items are held before the first result is
    yielded (plus the one drawn that found the pool full): memory bounded for 10^7 points."""
    drawn = []

    def items():
        for k in range(40):
            drawn.append(k)
            yield {"x": k}

    results = ordered_map(eval, "x + 1", items(), 2)
    assert next(results) == 1
    assert len(drawn) <= IN_FLIGHT_PER_WORKER * 2 + 1
    assert list(results) == list(range(2, 41))
    assert no_children_left()


@pytest.mark.parametrize("expr, words", [
    ("1 / (x - 2)", ["chunk 2 failed: ZeroDivisionError"]),
    ("__import__('os')._exit(3) if x == 4 else x", ["was not finished: a worker process ended abruptly"]),
])
def test_a_failure_in_a_worker_is_a_cagd_error_naming_the_item(expr, words):
    with pytest.raises(CagdError) as err:
        list(ordered_map(eval, expr, [{"x": k} for k in range(6)], 2))
    for w in words:
        assert w in str(err.value)
    # a process that dies breaks the pool: the first item without a result is named
    assert re.match(r"workers: chunk [0-4] ", str(err.value))
    assert no_children_left()


def test_a_cagd_error_in_a_worker_keeps_its_message():
    """checked_workers(0, name) in the workers: the engine's message (naming its argument)
    after the item's name."""
    with pytest.raises(CagdError, match=r"^workers: chunk 0: first: out of range \(0\)"):
        list(ordered_map(checked_workers, 0, ["first", "second", "third"], 2))
    assert no_children_left()


def test_a_result_that_does_not_come_is_a_cagd_error_and_the_worker_is_ended():
    """A task that would run for 10 minutes: the timeout names the item, the pool's
    processes are terminated (nothing left running, nobody waiting on them)."""
    expr = "__import__('time').sleep(600) if x == 1 else x"
    with pytest.raises(CagdError, match=r"workers: chunk [01] gave no result within 20 s"):
        list(ordered_map(eval, expr, [{"x": k} for k in range(4)], 2, timeout=20.0))
    assert no_children_left()
    assert not [t for t in threading.enumerate() if "QueueManager" in type(t).__name__]


class Unsendable:
    """Pickles fine here; unpickling it (in a worker) divides by zero."""

    def __reduce__(self):
        return operator.truediv, (1, 0)


def test_shared_objects_that_do_not_load_in_a_worker():
    with pytest.raises(CagdError, match=r"chunk 0 failed: .*could not be loaded.*ZeroDivisionError"):
        list(ordered_map(operator.getitem, Unsendable(), [0, 1, 2], 2))
    assert no_children_left()


def test_shared_objects_that_cannot_be_pickled():
    with pytest.raises(CagdError, match="workers: the objects cannot be sent"):
        list(ordered_map(operator.getitem, [lambda: 0], [0, 1], 2))


def test_stopping_early_ends_the_pool():
    results = ordered_map(eval, "x", [{"x": k} for k in range(30)], 2)
    assert next(results) == 0
    results.close()
    assert no_children_left()


@pytest.mark.parametrize("bad", [0, -1, True, False, 2.5, "2", None])
def test_bad_workers(bad):
    with pytest.raises(CagdError, match="workers: "):
        checked_workers(bad)
    with pytest.raises(CagdError, match="workers: "):
        list(ordered_map(eval, "x", [{"x": 1}], bad))


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), "soon"])
def test_bad_timeout(bad):
    with pytest.raises(CagdError, match="timeout: "):
        list(ordered_map(eval, "x", [{"x": 1}], 2, timeout=bad))
