"""Where a solve's time goes, stage by stage, per element at about 2e5 and 1e6 unknowns.

For every element, on the griffith scene at the sizes of SIZES, in separate processes:

  (b) solve(..., crack_model="contact"): the full contact solve, timed per stage;
  (a) solve(..., crack_model="bonded"): the plain linear solve of the same system
      (jn = 0): its factorization + solve + recovery is "the linear solve".

Stages of (b), in seconds: mesh (netgen and the crack maps), forms (the element's spaces
and the assembly of its bilinear and linear forms, NGSolve's static condensation
included), of which "ngs asm" is NGSolve's own matrix assembly (its timer "Matrix
assembling"), condense/convert (hybrid.condense: the COO conversion to scipy, the
boundary conditions, the roller change of basis, the map to the crack unknowns),
factorize (with PARDISO's partial factorization it yields the Schur complement S),
schur (extra work for S), qp (constraint map, QP), recover (the rest for the crack
jumps and the local unknowns) and post (profiles, KKT residuals, the checks). Ratios:
asm/lin = (forms + condense) of (b) over the linear solve of (a), the target of issue 14
is <= 1.5; tot/fac = the whole contact solve (mesh included) over its factorization,
target <= 3 at 1e6 unknowns; B/dof the peak memory (ru_maxrss) of (b) per unknown,
target <= 1536 (1.5 KiB). "load" is the 1-minute load average when the solve started:
the machine is shared.

    python benchmarks/assembly.py                       # every element, both sizes
    python benchmarks/assembly.py --sizes 2e5           # the small size only
    python benchmarks/assembly.py --elements peers bdm --out results.jsonl

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import resource
import subprocess
import sys
import time
import types

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from contact_vs_linear import machine  # noqa: E402

#: (maxh, crack_h) on griffith giving about 2e5 and about 1e6 unknowns in total, per element
SIZES = {
    "2e5": {"peers": (0.2, 0.01), "bdm": (0.2, 0.01), "tdnns": (0.2, 0.01), "h1p1": (0.05, 0.0025),
            "h1p2": (0.1, 0.005)},
    "1e6": {"peers": (0.08, 0.004), "bdm": (0.1, 0.005), "tdnns": (0.1, 0.005), "h1p1": (0.025, 0.0012),
            "h1p2": (0.05, 0.0025)},
}
SCENE = "griffith"
#: issue 14's targets (printed here, never in tests)
TARGET_ASM_OVER_LINEAR = 1.5
TARGET_TOTAL_OVER_FACTOR = 3.0
TARGET_BYTES_PER_DOF = 1536
STAGES = ("mesh", "forms", "ngs_asm", "condense", "factorize", "schur", "qp", "recover", "post")


def run_case(element: str, maxh: float, crack_h: float, model: str) -> dict:
    """One solve in this process: wall times per stage, and CPU times (all threads) per stage."""
    import ngsolve as ngs

    import ngcrack.core.hybrid as hybrid
    import ngcrack.scenes as scenes

    S = importlib.import_module("ngcrack.core.pipeline")  # the stages' module: its functions are timed here
    wall: dict[str, float] = {}
    cpu: dict[str, float] = {}

    def timed(name, fn):
        def wrapper(*args, **kw):
            t0, c0 = time.perf_counter(), time.process_time()
            out = fn(*args, **kw)
            wall[name] = wall.get(name, 0.0) + time.perf_counter() - t0
            cpu[name] = cpu.get(name, 0.0) + time.process_time() - c0
            return out
        return wrapper

    S._elements = types.SimpleNamespace(**{**vars(S._elements), "build": timed("forms", S._elements.build)})
    S.condense = timed("condense", S.condense)
    S.make_mesh = timed("mesh", S.make_mesh)
    S.reduce_to_contact = timed("reduce", S.reduce_to_contact)
    S.solve_qp = timed("qp", S.solve_qp)
    hybrid.ContactReduction.recover = timed("recover", hybrid.ContactReduction.recover)
    hybrid.CondensedSystem.expand = timed("recover", hybrid.CondensedSystem.expand)
    load = os.getloadavg()[0]
    c0 = time.process_time()
    sol = importlib.import_module("ngcrack.core.solve").solve(scenes.load(SCENE), element, maxh=maxh, crack_h=crack_h,
                                                        crack_model=model)
    cpu["total"] = time.process_time() - c0
    cpu["post"] = cpu["total"] - sum(v for k, v in cpu.items() if k != "total")
    t = dict(sol.timings)
    timers = {x["name"]: x["time"] for x in ngs.Timers()}
    t["forms"] = wall["forms"]
    t["condense"] = wall["condense"]
    t["ngs_asm"] = timers.get("Matrix assembling", 0.0)
    t["post"] = t["total"] - sum(t[k] for k in ("mesh", "assemble", "factorize", "solve", "schur", "qp", "recover"))
    t["recover"] += t.pop("solve")
    return {"element": element, "maxh": maxh, "crack_h": crack_h, "model": model, "ndof": sol.ndof,
            "timings": t, "cpu": cpu, "maxrss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
            "load": load, "threads": os.environ.get("NGCRACK_THREADS", "")}


def in_subprocess(*args) -> dict:
    res = subprocess.run([sys.executable, __file__, "case", json.dumps(args)], capture_output=True, text=True)
    if res.returncode != 0:
        return {"error": res.stderr.strip().splitlines()[-1] if res.stderr.strip() else f"exit {res.returncode}"}
    return json.loads(res.stdout.strip().splitlines()[-1])


HEAD = (f"{'element':7s} {'size':>4s} {'ndof':>8s} {'mesh':>6s} {'forms':>6s} {'ngsasm':>6s} {'cond':>6s} "
        f"{'fac':>6s} {'schur':>6s} {'qp':>6s} {'recov':>6s} {'post':>6s} {'total':>6s} {'linear':>6s} "
        f"{'asm/lin':>7s} {'tot/fac':>7s} {'B/dof':>6s} {'load':>5s}")


def line(row: dict) -> str:
    a, b = row["a"], row["b"]
    if "error" in a or "error" in b:
        return f"{row['element']:7s} {row['size']:>4s} error: {a.get('error') or b.get('error')}"
    t = b["timings"]
    lin = a["timings"]["linear"]
    asm = t["forms"] + t["condense"]
    nd = b["ndof"]["total"]
    cells = " ".join(f"{t[k]:6.2f}" for k in STAGES)
    return (f"{row['element']:7s} {row['size']:>4s} {nd:8d} {cells} {t['total']:6.2f} {lin:6.2f} "
            f"{asm / lin:7.2f} {t['total'] / t['factorize']:7.2f} {b['maxrss'] / nd:6.0f} {b['load']:5.1f}")


CPU_STAGES = ("mesh", "forms", "condense", "reduce", "qp", "recover", "post")
CPU_HEAD = (f"{'element':7s} {'size':>4s} {'ndof':>8s} " + " ".join(f"{k:>7s}" for k in CPU_STAGES)
            + f" {'total':>7s} {'linear':>7s} {'asm/lin':>7s} {'tot/red':>7s}")


def cpu_line(row: dict) -> str:
    """CPU seconds per stage (all threads; with NGCRACK_THREADS=1 and MKL_NUM_THREADS=1 the
    single-thread work, which the machine's load hardly changes). reduce = factorization
    + Schur complement + the first solve; linear = reduce + recover of the bonded run."""
    a, b = row["a"], row["b"]
    if "cpu" not in a or "cpu" not in b:
        return f"{row['element']:7s} {row['size']:>4s} error or not measured"
    c, ca = b["cpu"], a["cpu"]
    lin = ca["reduce"] + ca["recover"]
    cells = " ".join(f"{c.get(k, 0.0):7.2f}" for k in CPU_STAGES)
    return (f"{row['element']:7s} {row['size']:>4s} {b['ndof']['total']:8d} {cells} {c['total']:7.2f} {lin:7.2f} "
            f"{(c['forms'] + c['condense']) / lin:7.2f} {c['total'] / c['reduce']:7.2f}")


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "case":
        print(json.dumps(run_case(*json.loads(sys.argv[2]))))
        return
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--elements", nargs="*", default=["peers", "bdm", "tdnns", "h1p1", "h1p2"])
    p.add_argument("--sizes", nargs="*", default=list(SIZES), choices=list(SIZES))
    p.add_argument("--out", default=None, help="append one JSON line per case to this file")
    p.add_argument("--show", default=None, help="print the tables of a file written by --out, and stop")
    args = p.parse_args()
    if args.show:
        rows = [json.loads(text) for text in open(args.show) if text.strip()]
        print(HEAD)
        print("-" * len(HEAD))
        for row in rows:
            print(line(row))
        print()
        print(CPU_HEAD)
        print("-" * len(CPU_HEAD))
        for row in rows:
            print(cpu_line(row))
        return
    print(machine(), flush=True)
    print(HEAD)
    print("-" * len(HEAD), flush=True)
    out = open(args.out, "a") if args.out else None
    rows = []
    for size in args.sizes:
        for element in args.elements:
            maxh, crack_h = SIZES[size][element]
            b = in_subprocess(element, maxh, crack_h, "contact")
            a = in_subprocess(element, maxh, crack_h, "bonded")
            row = {"element": element, "size": size, "a": a, "b": b}
            if out:
                out.write(json.dumps(row) + "\n")
                out.flush()
            rows.append(row)
            print(line(row), flush=True)
    print()
    print("CPU seconds (all threads):")
    print(CPU_HEAD)
    print("-" * len(CPU_HEAD))
    for row in rows:
        print(cpu_line(row))
    print(f"targets: asm/lin <= {TARGET_ASM_OVER_LINEAR}, tot/fac <= {TARGET_TOTAL_OVER_FACTOR} at 1e6, "
          f"B/dof <= {TARGET_BYTES_PER_DOF}")


if __name__ == "__main__":
    main()
