"""What this process may still allocate: the machine's memory and the limits it runs under.

The size guard (``ngcrack.planar.sizing``) compares a solve's estimated peak memory with the
least of the machine's available memory, the process's address-space limit
(``ulimit -v``, RLIMIT_AS) and its cgroup's memory limit (a container's or a batch job's),
so that a solve that cannot fit is refused before it starts, not killed in an
allocation. Linux reads /proc and /sys/fs/cgroup; elsewhere what is missing is left out.
This module imports nothing of ngcrack.
"""

from __future__ import annotations

import math
import os

import numpy as np

from .errors import InputError

__all__ = ["address_space_limit", "available_memory", "memory_limits"]


def _read_number(path: str) -> float | None:
    try:
        with open(path) as fh:
            text = fh.read().strip()
    except OSError:
        return None
    try:
        return float(text)
    except ValueError:
        return None  # "max": no limit


def _process_status(key: str) -> float | None:
    """A size in bytes from /proc/self/status (VmSize, VmRSS, ...), or None."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def memory_limits() -> dict[str, float]:
    """What this process may still allocate, by every limit that applies (bytes).

    ``machine``: the memory the machine can still give (Linux MemAvailable, else free
    pages); ``address space``: the soft ``RLIMIT_AS`` (``ulimit -v``) minus the address
    space already mapped; ``cgroup``: the cgroup's ``memory.max`` minus its
    ``memory.current`` (cgroup v2; v1's ``memory.limit_in_bytes`` and ``usage_in_bytes``).
    Limits that are absent or unlimited are left out.
    """
    out: dict[str, float] = {}
    avail = None
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    avail = float(line.split()[1]) * 1024
                    break
    except OSError:
        pass
    if avail is None:
        try:
            avail = float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError, AttributeError):
            avail = None
    if avail is not None:
        out["machine"] = avail
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
            used = _process_status("VmSize") or 0.0
            out["address space"] = max(float(soft) - used, 0.0)
    except (ImportError, OSError, ValueError):
        pass
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        limit = _read_number(limit_file)
        if limit is not None and limit < 2**60:  # v1 writes a huge number for "no limit"
            out["cgroup"] = max(limit - (_read_number(usage_file) or 0.0), 0.0)
            break
    return out


def available_memory() -> float | None:
    """The memory this process can still allocate: the least of the machine's available
    memory, its address-space limit and its cgroup's limit (`memory_limits`), or None."""
    limits = memory_limits()
    return min(limits.values()) if limits else None


def address_space_limit() -> float | None:
    """The process's soft address-space limit (``ulimit -v``, RLIMIT_AS) in bytes, or None if unlimited."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError):
        return None
    return None if soft in (resource.RLIM_INFINITY, -1) or soft <= 0 else float(soft)


#: the default ceiling on the estimated unknowns of one solve (about 7 GB for the mixed elements);
#: `max_dof=` / `--max-dof` replaces it
DEFAULT_MAX_DOF = 5_000_000
#: fraction of the machine's available memory a solve may plan to use
MEMORY_FRACTION = 0.8


def format_bytes(n: float) -> str:
    """A number of bytes as people read it (kB, MB, GB, TB)."""
    if n >= 1e15:
        return f"{n:.2g} bytes"
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"


def check_max_dof(max_dof) -> None:
    """max_dof must be None or a whole number >= 1 (an integer, or a float like 1e4)."""
    if max_dof is None:
        return
    ceiling = f"{DEFAULT_MAX_DOF:,}".replace(",", " ")
    what = f"must be None (the default ceiling, {ceiling}) or a whole number of unknowns >= 1"
    if isinstance(max_dof, (bool, np.bool_)) or not isinstance(max_dof, (int, float, np.integer, np.floating)):
        raise InputError(f"max_dof = {max_dof!r}: {what}")
    value = float(max_dof)
    if not math.isfinite(value) or not value >= 1:
        raise InputError(f"max_dof = {max_dof!r}: {what}")
    if value != math.floor(value):
        raise InputError(f"max_dof = {max_dof!r}: {what}; it is not a whole number (give "
                          f"{math.floor(value):.0f} or {math.ceil(value):.0f})")
