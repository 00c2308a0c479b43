"""The bad-input contract (issue 14) as test helpers.

Whatever the input, a public function either answers (the caller checks the answer
by an invariant or an independent evaluation) or raises :class:`cagd.CagdError`
whose message names the problem; no other exception escapes, and every case ends
within a time and memory bound. ``call`` checks one case in this process (a timer
and an address-space limit), ``run_child`` runs code that could kill the interpreter
(OCCT's file readers) in a child process and reports how it ended.
"""
from __future__ import annotations

import contextlib
import dataclasses
import os
import resource
import signal
import subprocess
import sys
import textwrap
from typing import Any, Callable, Iterator, Optional, Tuple

import cagd

#: wall-clock bound of one in-process case, in seconds (a hang guard, not a timing target)
CASE_SECONDS = 30.0
#: address space one case may add to the process (the issue's bound on peak memory)
CASE_MEMORY = 2 << 30
#: wall-clock bound of one child-process case, in seconds
CHILD_SECONDS = 120.0


class CaseTimeout(BaseException):
    """Raised by the case timer (a BaseException, so ``except Exception`` in the code
    under test cannot swallow it)."""


def _vm_size() -> Optional[int]:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        return None
    return None


@contextlib.contextmanager
def bounded(seconds: float = CASE_SECONDS, memory: int = CASE_MEMORY) -> Iterator[None]:
    """Run the block with a timer (SIGALRM raises :class:`CaseTimeout`) and a soft
    address-space limit of the current size plus ``memory`` (an allocation beyond it
    raises MemoryError, which the contract counts as a failure)."""
    old_handler = signal.signal(signal.SIGALRM, _timeout)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    size = _vm_size()
    limited = size is not None and (hard == resource.RLIM_INFINITY or size + memory < hard)
    if limited:
        resource.setrlimit(resource.RLIMIT_AS, (size + memory, hard))
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old_handler)
        if limited:
            resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def _timeout(signum: int, frame: Any) -> None:
    raise CaseTimeout("the case ran longer than its bound")


@dataclasses.dataclass(frozen=True)
class Outcome:
    """How one case ended: ``value`` when it answered, ``error`` when it raised CagdError."""

    value: Any = None
    error: Optional[cagd.CagdError] = None

    @property
    def ok(self) -> bool:
        return self.error is None


def call(fn: Callable[..., Any], *args: Any, seconds: float = CASE_SECONDS, memory: int = CASE_MEMORY,
         **kwargs: Any) -> Outcome:
    """``fn(*args, **kwargs)`` under the contract: an answer or a CagdError with a
    message; anything else (another exception, a timeout, MemoryError) fails the test
    with the case in the message."""
    try:
        with bounded(seconds, memory):
            value = fn(*args, **kwargs)
    except cagd.CagdError as exc:
        assert str(exc).strip(), f"{_name(fn)}: CagdError without a message"
        return Outcome(error=exc)
    except CaseTimeout:
        raise AssertionError(f"{_name(fn)} ran over {seconds} s on {_case(args, kwargs)}") from None
    except BaseException as exc:   # noqa: BLE001 - the contract: nothing else escapes
        raise AssertionError(f"{_name(fn)} raised {type(exc).__name__}: {exc} on {_case(args, kwargs)}") from exc
    return Outcome(value=value)


def _name(fn: Callable[..., Any]) -> str:
    return getattr(fn, "__qualname__", repr(fn))


def _case(args: Tuple[Any, ...], kwargs: dict) -> str:
    text = ", ".join([repr(a) for a in args] + [f"{k}={v!r}" for k, v in kwargs.items()])
    return text if len(text) < 600 else text[:600] + " ..."


@dataclasses.dataclass(frozen=True)
class ChildOutcome:
    """How a child process ended: its exit code (negative: killed by that signal), its
    output, and whether it ran over its time bound."""

    returncode: int
    stdout: str
    stderr: str
    timed_out: bool

    @property
    def crashed(self) -> bool:
        return self.returncode < 0 and not self.timed_out


def run_child(code: str, *args: str, seconds: float = CHILD_SECONDS, memory: int = 4 * CASE_MEMORY,
              cwd: Optional[str] = None) -> ChildOutcome:
    """Run ``code`` (Python source, dedented) in a fresh interpreter with ``args`` as
    ``sys.argv[1:]``, an address-space limit and a timeout."""
    def limit() -> None:   # runs in the child before exec
        resource.setrlimit(resource.RLIMIT_AS, (memory + (8 << 30), resource.RLIM_INFINITY))

    try:
        done = subprocess.run([sys.executable, "-c", textwrap.dedent(code), *args], capture_output=True,
                              text=True, errors="replace", timeout=seconds, cwd=cwd, preexec_fn=limit,
                              env={**os.environ, "PYTHONFAULTHANDLER": "1"})
    except subprocess.TimeoutExpired as exc:
        return ChildOutcome(-signal.SIGKILL, _text(exc.stdout), _text(exc.stderr), True)
    return ChildOutcome(done.returncode, done.stdout, done.stderr, False)


def _text(data: Any) -> str:
    if data is None:
        return ""
    return data.decode(errors="replace") if isinstance(data, bytes) else str(data)
