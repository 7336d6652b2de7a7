"""Start-up: the CPU of `import ngsolve`, `import ngcrack`, `ngcrack --help` and a whole
`ngcrack solve`, and the import profile of `import ngcrack` and of a solve.

Each command runs in a fresh process, REPEAT times, interleaved, after one round that is
not counted; the table gives the least and the median CPU seconds (user + system of the
child, `resource.RUSAGE_CHILDREN`). The children run as an installed package does, with
their bytecode cached: PYTHONDONTWRITEBYTECODE is dropped and the bytecode goes to a
temporary PYTHONPYCACHEPREFIX (compiling ngcrack's modules from source costs about 0.3 s
more per process, which a user pays once).
The profile is `python -X importtime` summed per top-level package: the microseconds
each package's own modules took (self time, so nothing is counted twice), largest first.
The 1-minute load average is printed with the table: the machine may be shared.

The floor: a whole ngcrack process cannot cost less than the interpreter and `import
ngsolve` (with numpy and netgen's 2D geometry, what every solve must import); the table
prints it, ngcrack's own modules and the loose griffith solve's in-process CPU on top of
it, and GetFEM's whole cheapest griffith run (benchmarks/getfem_peer.py, h = 0.2) with
the 1.5x of it that the whole-process target allows.

    python benchmarks/startup.py                 # 5 repetitions
    python benchmarks/startup.py --repeat 11 --top 25

No number here is a test threshold (tests/test_startup.py asserts which modules load).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict

PY = sys.executable
SOLVE = "import ngcrack as nc; nc.solve('griffith')"
#: the peer benchmark's cheapest griffith configuration at loose targets (K_I within 4e-5)
LOOSE = "maxh=4, crack_h=0.5, tip_h=0.005, grading=0.5, order=2"
#: the system Python with GetFEM (the peer of benchmarks/getfem_peer.py), where installed
SYSTEM_PYTHON = "/usr/bin/python3"
JSON_OUT = os.path.join(tempfile.gettempdir(), "ngcrack-startup-griffith.json")
#: the loose solve in a child that prints its own in-process CPU (after the imports, as the peer benchmark)
LOOSE_CHILD = ("import json, time, ngcrack as nc; solve = nc.solve; t0 = time.process_time(); "
               f"sol = solve(nc.scenes.load('griffith'), {LOOSE}); "
               "print(json.dumps({'cpu': time.process_time() - t0, 'timings': sol.timings}))")
COMMANDS = {
    "python -c pass": [PY, "-c", "pass"],
    "import ngsolve": [PY, "-c", "import ngsolve"],
    "import ngsolve, netgen.geom2d (the floor: what every 2D solve imports)": [PY, "-c", "import ngsolve, netgen.geom2d"],
    "import ngsolve, scipy.sparse, shapely (what a solve imported before)": [PY, "-c", "import ngsolve, scipy.sparse, shapely"],
    "import ngcrack.core.solve (the floor and ngcrack's modules of a solve)": [PY, "-c", "import ngcrack as nc; nc.solve"],
    "import ngcrack": [PY, "-c", "import ngcrack"],
    "ngcrack --help": [PY, "-m", "ngcrack.shell.cli", "--help"],
    "ngcrack solve griffith --json": [PY, "-m", "ngcrack.shell.cli", "solve", "griffith", "--json", JSON_OUT],
    "python: import + nc.solve('griffith')": [PY, "-c", SOLVE],
    f"python: import + nc.solve('griffith', {LOOSE})": [PY, "-c", LOOSE_CHILD],
}
LOOSE_NAME = f"python: import + nc.solve('griffith', {LOOSE})"
FLOOR_NAME = "import ngsolve, netgen.geom2d (the floor: what every 2D solve imports)"
MODULES_NAME = "import ngcrack.core.solve (the floor and ngcrack's modules of a solve)"
if os.path.exists(SYSTEM_PYTHON):
    COMMANDS["GetFEM: /usr/bin/python3 -c 'import getfem'"] = [SYSTEM_PYTHON, "-c", "import getfem"]


#: the children's environment: bytecode written and read, as an installed package has it
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
ENV["PYTHONPYCACHEPREFIX"] = os.path.join(tempfile.gettempdir(), "ngcrack-startup-pycache")
for _v in ("NGCRACK_THREADS", "OMP_NUM_THREADS"):  # one thread, as the peer benchmark (unless set)
    ENV.setdefault(_v, "1")


def cpu(args: list[str], inner: list | None = None) -> float:
    """CPU seconds (user + system) of one run of `args` in a child process; the last line
    the child prints (JSON: its own in-process CPU and stage timings) goes to `inner`."""
    env = ENV
    if args[0] == SYSTEM_PYTHON:  # the system's own Python: its own bytecode and packages
        env = {k: v for k, v in ENV.items() if k not in ("PYTHONPATH", "PYTHONPYCACHEPREFIX")}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, check=True, env=env, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if inner is not None and out.stdout.strip():
        inner.append(json.loads(out.stdout.strip().splitlines()[-1]))
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def getfem_cheapest(repeat: int) -> float | None:
    """The least whole-process CPU of GetFEM's cheapest griffith run in the peer benchmark
    (h = 0.2, both radii 0.5a, a the crack's half length: K_I within 4e-5), or None where GetFEM is not installed."""
    if subprocess.run([SYSTEM_PYTHON, "-c", "import getfem"], capture_output=True, check=False).returncode:
        return None
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import getfem_peer

    return min(getfem_peer.run_peer("griffith", 0.2, {"enrich": 0.5, "radius": 0.5})["cpu_whole"] for _ in range(repeat))


def print_floor(times: dict, inner: list, getfem: float | None) -> None:
    """The whole loose griffith run against its floor (least of each)."""
    py, floor = min(times["python -c pass"]), min(times[FLOOR_NAME])
    modules, whole = min(times[MODULES_NAME]), min(times[LOOSE_NAME])
    best = min(inner, key=lambda r: r["cpu"])
    solve = best["cpu"]
    print(f"\nthe floor of a whole process (least CPU s): python alone {py:.3f}; `import ngsolve, netgen.geom2d` "
          f"{floor:.3f}")
    print(f"ngcrack's loose griffith run, whole process {whole:.3f} = floor {floor:.3f} + ngcrack's modules "
          f"{modules - floor:.3f} + the solve in-process {solve:.3f} + the rest {whole - modules - solve:+.3f} "
          "(leaving the interpreter, freeing the solve)")
    stages = ", ".join(f"{k} {v:.3f}" for k, v in best["timings"].items() if k not in ("total", "linear", "contact"))
    print(f"the loose solve's stages (wall s, one thread, of its least-CPU run): {stages}; total "
          f"{best['timings'].get('total', 0.0):.3f}")
    if getfem is not None:
        print(f"GetFEM's whole cheapest griffith run (h = 0.2): {getfem:.3f}; within 1.5x of it: at most "
              f"{1.5 * getfem:.3f}; the floor alone is {floor / getfem:.2f} times GetFEM's run, the floor and "
              f"the solve {(floor + solve) / getfem:.2f} times, ngcrack's whole run {whole / getfem:.2f} times")


def import_profile(code: str) -> tuple[dict[str, int], int]:
    """Self import time per top-level package (microseconds) of `python -X importtime -c code`."""
    err = subprocess.run([PY, "-X", "importtime", "-c", code], capture_output=True, text=True, check=True, env=ENV).stderr
    per: dict[str, int] = defaultdict(int)
    for line in err.splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        self_us, _, name = line[len("import time:"):].split("|")
        per[name.strip().split(".")[0]] += int(self_us)
    return dict(per), len(per)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--top", type=int, default=15, help="packages shown in each import profile")
    args = ap.parse_args()
    env_threads = ENV["OMP_NUM_THREADS"]
    print(f"python {sys.version.split()[0]}, OMP_NUM_THREADS={env_threads}, load average {os.getloadavg()[0]:.2f} "
          f"(1 min) at the start")
    times: dict[str, list[float]] = {k: [] for k in COMMANDS}
    inner: list[float] = []
    for cmd in COMMANDS.values():  # writes the bytecode; not counted
        cpu(cmd)
    for _ in range(args.repeat):  # interleaved: a change of load touches every command alike
        for name, cmd in COMMANDS.items():
            times[name].append(cpu(cmd, inner if name == LOOSE_NAME else None))
    getfem = getfem_cheapest(args.repeat)
    print(f"\n| command | CPU s, least of {args.repeat} | median |")
    print("|---|---:|---:|")
    for name, ts in times.items():
        print(f"| `{name}` | {min(ts):.3f} | {statistics.median(ts):.3f} |")
    base = min(times["import ngsolve"])
    print(f"\nimport ngcrack - import ngsolve: {min(times['import ngcrack']) - base:+.3f} s CPU (least of each)")
    print_floor(times, inner, getfem)
    print(f"load average {os.getloadavg()[0]:.2f} (1 min) at the end")
    for title, code in (("import ngcrack", "import ngcrack"), ("import ngcrack; nc.solve('griffith')", SOLVE)):
        per, _ = import_profile(code)
        total = sum(per.values())
        print(f"\nimport profile of `{title}` (python -X importtime, self time per top-level package): "
              f"{total / 1e6:.3f} s wall in {len(per)} packages")
        for name, us in sorted(per.items(), key=lambda kv: -kv[1])[:args.top]:
            print(f"  {name:<28s} {us / 1e3:8.1f} ms")


if __name__ == "__main__":
    main()
