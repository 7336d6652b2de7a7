"""SIGINT and SIGTERM honoured at once in every stage of a command, meshing included.

Python runs a signal handler only when the main thread returns to the interpreter, and
netgen's mesher, a factorization or a dense solve may keep it away for minutes. `Interrupts`
(the command line's, one per command) closes that gap with a watcher thread woken through
`signal.set_wakeup_fd` by the signal itself:

- it sets netgen's terminate flag, so a mesher that is running stops within milliseconds
  and hands control back (the handler then raises, and the command unwinds as usual:
  workers stopped, temporary files removed, the finished work of `grow` written);
- if the main thread has not taken the signal within GRACE_S seconds (a long C call that
  checks no flag), or a second signal comes while the first is being handled, it ends the
  process itself: the temporary files of outputs being written are removed (files.py keeps
  their list), one line says what was and was not written, and the exit code is 128 + the
  signal's number, as for an interruption handled in the main thread.

The handler also remembers the signal: code that swallows a KeyboardInterrupt raised in a
callback (a library's C++ layer turns it into its own exception type, or drops it) cannot
lose it, as `pending()` still names it and `check()` raises it again at the next point
that looks. A signal that comes while outputs are being renamed into place waits until the
last one is (files.Staged): all old or all new, never a mix. This module imports nothing of
ngcrack but files.py and cli_errors.py.
"""

from __future__ import annotations

import os
import signal
import socket
import sys
import threading

from .cli_errors import Terminated
from .files import committing, hold, remove_staged_files

#: seconds the main thread has to take a signal before the watcher ends the process itself
GRACE_S = 1.0
#: the signals honoured
SIGNALS = (signal.SIGINT, signal.SIGTERM)

_active: Interrupts | None = None


def _stop_netgen() -> None:
    """Set netgen's terminate flag if netgen is loaded (its mesher checks it often)."""
    meshing = sys.modules.get("netgen.libngpy._meshing")
    if meshing is None:
        return
    try:
        meshing._SetTerminate(True)
    except Exception:  # noqa: BLE001 -- a netgen without the flag: the grace period still applies
        pass


def _clear_netgen() -> None:
    meshing = sys.modules.get("netgen.libngpy._meshing")
    if meshing is not None:
        try:
            meshing._SetTerminate(False)
        except Exception:  # noqa: BLE001
            pass


def interruption(signum: int) -> KeyboardInterrupt:
    """The exception a signal becomes: Terminated for SIGTERM, KeyboardInterrupt for SIGINT."""
    return Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def pending() -> int | None:
    """The signal received by the active `Interrupts` and not yet handled by the command, or None."""
    return None if _active is None else _active.signum


def check() -> None:
    """Raise the pending interruption again, if one was received (and lost on the way)."""
    if _active is not None and _active.signum is not None:
        raise interruption(_active.signum)


class Interrupts:
    """Install the handlers and the watcher for the block (main thread only; else a no-op).

    ``farewell(signum) -> str``: the line printed (on stderr) when the watcher has to end
    the process itself; it should say what was written.
    """

    def __init__(self, farewell=None) -> None:
        self.farewell = farewell or (lambda signum: "ngcrack: " + ("terminated" if signum == signal.SIGTERM
                                                                    else "interrupted"))
        self.signum: int | None = None
        self.taken = threading.Event()  # the main thread ran the handler
        self._installed = False

    # -------------------------------------------------------------- main thread
    def _handler(self, signum, frame):
        first = self.signum is None
        self.signum = signum if first else self.signum
        self.taken.set()
        if first and committing():  # outputs are being renamed into place: raised once the last one is
            hold(signum)
            return
        if first:
            raise interruption(signum)
        # a second signal while the first unwinds: the watcher ends the process

    def handled(self) -> None:
        """The command has dealt with the interruption (its message printed)."""
        self.signum = None

    def __enter__(self) -> Interrupts:
        global _active
        if threading.current_thread() is not threading.main_thread():
            return self
        self._read, self._write = socket.socketpair()
        self._write.setblocking(False)
        self._read.settimeout(None)
        try:
            self._old_fd = signal.set_wakeup_fd(self._write.fileno(), warn_on_full_buffer=False)
        except (ValueError, OSError):
            self._read.close()
            self._write.close()
            return self
        self._old = {s: signal.signal(s, self._handler) for s in SIGNALS}
        self._installed = True
        self._previous, _active = _active, self
        self._count = 0
        self._thread = threading.Thread(target=self._watch, name="ngcrack-signal-watcher", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        global _active
        if not self._installed:
            return
        for s, old in self._old.items():
            signal.signal(s, old)
        signal.set_wakeup_fd(self._old_fd)
        self._closing = True
        try:
            self._write.send(b"\0")  # wakes the watcher, which ends
        except OSError:
            pass
        self._thread.join(timeout=5)
        self._read.close()
        self._write.close()
        _active = self._previous
        _clear_netgen()  # the flag is process-wide: a later mesh in this process must not stop
        self._installed = False

    # -------------------------------------------------------------- watcher thread
    _closing = False

    def _watch(self) -> None:
        while True:
            try:
                data = self._read.recv(64)
            except OSError:
                return
            if self._closing or not data:
                return
            for signum in data:
                if signum not in SIGNALS:
                    continue
                self._count += 1
                _stop_netgen()
                if self._count > 1 and self.taken.is_set():
                    self._end(self.signum or signum)  # asked again while unwinding: stop now
                    return
                if not self.taken.wait(GRACE_S) and not self._closing:
                    self._end(signum)  # the main thread is in a long C call
                    return

    def _end(self, signum: int) -> None:
        try:
            remove_staged_files()
            line = self.farewell(signum)
            if line:  # (none from the other ranks of mpiexec)
                sys.stderr.write(line + "\n")
            sys.stderr.flush()
            sys.stdout.flush()
        except Exception:  # noqa: BLE001 -- ending regardless
            pass
        os._exit(128 + signum)
