"""Where a sweep's runs execute: in this process, in a pool of worker processes, or on a Dask cluster.

Each executor has the same small interface (capacity, submit, wait, prepare, close):
the sweep's plan submits cases up to the capacity and waits for the first to finish.

Worker processes die with the process that started them, however it ends: on Linux
the kernel kills them when their parent dies (prctl PR_SET_PDEATHSIG), elsewhere a
watchdog thread in each worker notices that its parent is gone. An interrupted or
failed sweep terminates its workers rather than waiting for their runs.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait

from ...core.errors import InputError

#: seconds between a worker's checks that its parent is alive (where the kernel cannot tell it)
WATCHDOG_PERIOD = 0.5


class _Serial:
    """Runs each case in this process when it is submitted."""

    capacity = 1

    def submit(self, fn, *args):
        fut: Future = Future()
        try:
            fut.set_result(fn(*args))
        except BaseException as exc:  # noqa: BLE001 -- handed back through the future
            if isinstance(exc, KeyboardInterrupt):
                raise
            fut.set_exception(exc)
        return fut

    def wait(self, futures):
        return wait(futures, return_when=FIRST_COMPLETED)

    def prepare(self, ref):
        return ref

    def close(self, cancel: bool = False):
        pass


def _die_with_parent(parent: int) -> None:
    """End this process when the process `parent` ends (SIGKILL included)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            PR_SET_PDEATHSIG = 1
            if ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0:
                if os.getppid() != parent:  # died before the request took effect
                    os._exit(1)
                return
        except (OSError, AttributeError):
            pass

    def watch():
        while os.getppid() == parent:
            time.sleep(WATCHDOG_PERIOD)
        os._exit(1)

    threading.Thread(target=watch, name="ngcrack-parent-watchdog", daemon=True).start()


def _worker_start(threads: int, parent: int) -> None:
    """Worker start: die with the sweep's process; at most `threads` threads for libraries
    loaded later (MKL PARDISO)."""
    _die_with_parent(parent)
    for var in ("MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        os.environ.setdefault(var, str(threads))


class _Processes(_Serial):
    """A pool of `jobs` worker processes (spawned: a clean NGSolve in each).

    Each worker's threaded libraries get cpu_count // jobs threads, so that the
    workers do not oversubscribe the cores.
    """

    def __init__(self, jobs: int) -> None:
        import multiprocessing

        self.capacity = jobs
        threads = max(1, (os.cpu_count() or 1) // jobs)
        self.pool = ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn"),
                                        initializer=_worker_start, initargs=(threads, os.getpid()))

        self._submitting: threading.Thread | None = None

    def submit(self, fn, *args):
        """Submit from a helper thread: a submit may start a worker, and a signal handled in
        the main thread (Ctrl-C, SIGTERM) that cut the start short would leave the new
        worker reading a half-sent start-up message and printing a traceback. The main
        thread still takes the signal at once; the worker's start completes meanwhile."""
        box: dict = {}

        def run():
            try:
                box["future"] = self.pool.submit(fn, *args)
            except BaseException as exc:  # noqa: BLE001 -- raised again in the caller's thread
                box["error"] = exc

        self._submitting = threading.Thread(target=run, name="ngcrack-submit")
        self._submitting.start()
        self._submitting.join()
        self._submitting = None
        if "error" in box:
            raise box["error"]
        return box["future"]

    def close(self, cancel: bool = False):
        """Wait for the workers to finish; cancel: stop them now (their runs are lost either way)."""
        if self._submitting is not None:  # a submit cut short in this thread: let its worker start
            try:
                self._submitting.join(timeout=60)
            except RuntimeError:  # the signal came before the helper thread started: nothing submitted
                pass
        if not cancel:
            self.pool.shutdown(wait=True)
            return
        workers = list((getattr(self.pool, "_processes", None) or {}).values())
        self.pool.shutdown(wait=False, cancel_futures=True)
        for proc in workers:
            if proc.is_alive():
                proc.terminate()
        for proc in workers:
            proc.join(timeout=10)


#: how long to wait for a dask scheduler before giving up
DASK_CONNECT_TIMEOUT = "15s"


def check_dask(dask) -> None:
    """Refuse, by name and before any run, a `dask` that is neither None, a scheduler's address (a non-empty string)
    nor a distributed.Client: a number of workers is `jobs`, not `dask`."""
    if dask is None or (isinstance(dask, str) and dask.strip()):
        return
    if not isinstance(dask, str):
        try:
            from distributed import Client
        except ImportError:
            Client = ()
        if Client and isinstance(dask, Client):
            return
    raise InputError(f"dask = {dask!r}: must be None, the address of a dask.distributed scheduler (a string such as "
                     f"'tcp://127.0.0.1:8786') or a distributed.Client; for worker processes on this machine give "
                     f"jobs = N instead")


class _Dask(_Serial):
    """A dask.distributed cluster: a scheduler address or an existing Client."""

    def __init__(self, address) -> None:
        check_dask(address)
        try:
            import distributed
        except ImportError:
            raise InputError("dask: the dask.distributed package is not installed (pip install 'dask[distributed]')") from None
        self._distributed = distributed
        if isinstance(address, distributed.Client):
            self.client, self._own = address, False
        else:
            try:
                self.client, self._own = distributed.Client(address, timeout=DASK_CONNECT_TIMEOUT), True
            except (OSError, TimeoutError, ValueError) as exc:
                raise InputError(f"dask = {address!r}: cannot connect to a scheduler there ({exc})") from None
        self.capacity = max(1, sum(self.client.nthreads().values()))

    def submit(self, fn, *args):
        return self.client.submit(fn, *args, pure=False)

    def wait(self, futures):
        done = self._distributed.wait(list(futures), return_when="FIRST_COMPLETED")
        return done.done, done.not_done

    def prepare(self, ref):
        return self.client.scatter(ref, hash=False) if ref is not None else None

    def close(self, cancel: bool = False):
        if self._own:
            self.client.close()


def _executor(jobs: int, dask):
    if dask is not None:
        return _Dask(dask)
    return _Processes(jobs) if jobs > 1 else _Serial()
