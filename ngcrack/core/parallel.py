"""NGSolve's shared-memory parallelism for assembly and local solves.

NGSolve assembles element matrices, condenses them and applies the local solves on
all threads only inside `with ngs.TaskManager():`; outside it works on one thread.
`task_manager()` enters it with a thread count that respects the process's limits
(the study's worker processes set OMP_NUM_THREADS to their share of the cores), and
does nothing when a TaskManager is already active (NGSolve's own nesting is a no-op
too, but the thread count must not change under a running one).
"""

from __future__ import annotations

import os
from contextlib import contextmanager

import ngsolve as ngs

#: environment variable that overrides the thread count of NGSolve's TaskManager
THREADS_ENV = "NGCRACK_THREADS"

_depth = 0


def thread_count() -> int:
    """NGCRACK_THREADS, else OMP_NUM_THREADS, else every core of the machine."""
    for var in (THREADS_ENV, "OMP_NUM_THREADS"):
        value = os.environ.get(var, "")
        if value.strip().isdigit() and int(value) > 0:
            return int(value)
    return os.cpu_count() or 1


@contextmanager
def task_manager():
    """NGSolve's TaskManager with `thread_count()` threads (re-entrant)."""
    global _depth
    if _depth:
        _depth += 1
        try:
            yield
        finally:
            _depth -= 1
        return
    ngs.SetNumThreads(thread_count())
    _depth += 1
    try:
        with ngs.TaskManager():
            yield
    finally:
        _depth -= 1
