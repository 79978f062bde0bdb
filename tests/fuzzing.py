"""What the fuzz tests share: the one accepted failure, a per-case time limit, a memory ceiling
and the count of cases tried per target (printed at the end of the test run by conftest.py).

A fuzzed input has two acceptable outcomes: it works (the model runs for a short simulated
time, the sweep file is planned, the map becomes an arena), or it raises the project's own
error (:class:`abm.errors.ConfigError` or :class:`abm.errors.MapError`) naming the input.
Anything else - another exception, a case that runs past its time limit, memory exhausted -
fails the test.
"""

import contextlib
import os
import resource
import signal
from collections import Counter, defaultdict

from hypothesis import HealthCheck, settings

from abm.errors import ConfigError, MapError

#: Target -> outcome ("ok" / "rejected") -> cases tried, over this test session.
COUNTS: defaultdict[str, Counter] = defaultdict(Counter)

#: Wall-clock limit of one case (s). The slowest legitimate case seen: a stigmergy pheromone
#: disc covering the whole 100 m hall (pheromone_radius=1e300), whose sensing table takes ~16 s
#: to build on a loaded machine; most cases take milliseconds.
CASE_SECONDS = 60.0

#: Memory a case may take beyond what the test process holds already (bytes).
EXTRA_MEMORY = 4 * 2**30

#: The project's own errors: the only exceptions a fuzzed input may raise.
OWN_ERRORS = (ConfigError, MapError)


class CaseTimeout(BaseException):  # noqa: N818 - a BaseException so `except Exception` in the code under test cannot swallow it
    """A case ran past :data:`CASE_SECONDS`: a hang."""


def examples(default: int) -> settings:
    """Hypothesis settings of a fuzz target: ``default`` cases (``ABM_FUZZ_EXAMPLES`` overrides
    for a long session), derandomized so the suite tries the same cases every time.
    """
    n = int(os.environ.get("ABM_FUZZ_EXAMPLES", default))
    return settings(
        max_examples=n,
        deadline=None,  # the per-case limit below is the deadline
        derandomize="ABM_FUZZ_EXAMPLES" not in os.environ,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


def _on_alarm(signum, frame) -> None:
    raise CaseTimeout(f"the case ran longer than {CASE_SECONDS:g} s")


@contextlib.contextmanager
def case(target: str, names: list[str]):
    """Run one case of ``target``: fail on a hang or on an exception other than the project's
    own errors naming one of ``names``; count the outcome.
    """
    previous = signal.signal(signal.SIGALRM, _on_alarm)
    signal.setitimer(signal.ITIMER_REAL, CASE_SECONDS)
    try:
        yield
    except OWN_ERRORS as exc:
        text = str(exc)
        assert any(name in text for name in names), f"{type(exc).__name__} names none of {names}"
        COUNTS[target]["rejected"] += 1
    else:
        COUNTS[target]["ok"] += 1
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@contextlib.contextmanager
def memory_ceiling():
    """Cap this process's address space at its current size plus :data:`EXTRA_MEMORY`, so a
    case that asks for too much memory fails with MemoryError instead of starving the machine.
    """
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with open("/proc/self/statm") as statm:
        size = int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    cap = size + EXTRA_MEMORY
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def summary() -> list[str]:
    """One line per target: cases tried, of which ran / were rejected with a ConfigError."""
    lines = []
    for target in sorted(COUNTS):
        c = COUNTS[target]
        lines.append(
            f"{target}: {c['ok'] + c['rejected']} cases ({c['ok']} ran, {c['rejected']} rejected "
            "with the project's error naming the input)"
        )
    return lines
