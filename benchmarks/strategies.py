"""The crack problem's strategies: the same answers and no slower, before and after a change.

Each case is one solve; its record holds the crack unknowns (2D: the QP's j, or z with
friction; 3D: the normal jumps), the fracture parameters (2D tips' K_I, K_II; 3D fronts'
K_I, K_II, K_III), the KKT residuals, the CPU seconds of the whole solve (rank 0's under
mpiexec; the fastest of SOLVES solves after an untimed one, so imports excluded) and the
seconds of its crack problem (`timings["contact"]`, likewise). Cases:

    griffith          2D, dense Schur + pdas
    paper-1-<solver>  2D paper-1 with qp_solver pdas, uzawa, clarabel
    friction-2d       2D inclined-compression with Coulomb friction 0.3
    penny             3D bent penny (the crack's lower half closes), dense strategy
    penny-sparse      the same with the sparse active set (the Schur threshold set to 0)
    friction-3d       3D inclined penny pressed shut, friction 0.3
    friction-3d-sparse  the same on the sparse system
    mpi-griffith, mpi-penny   under mpiexec -n 2 (projected Krylov)

    python benchmarks/strategies.py --record out.json           # this checkout's answers and times
    python benchmarks/strategies.py --compare a.json b.json     # the largest differences, a table of times
    python benchmarks/strategies.py --before ../other-checkout  # both checkouts, interleaved, then the table

The sparse cases set the dense threshold to 0 in the process (a benchmark's device, not an option).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time

CASES = ("griffith", "paper-1-pdas", "paper-1-uzawa", "paper-1-clarabel", "friction-2d", "penny", "penny-sparse",
         "friction-3d", "friction-3d-sparse", "mpi-griffith", "mpi-penny")
#: processes of each case per checkout, interleaved (the fastest counts)
REPEATS = 2
#: timed solves of a case in one process, after one untimed (the fastest counts)
SOLVES = 3


def _force_sparse() -> None:
    """Set every Schur threshold this checkout has to 0 (the sparse strategy for any crack)."""
    import importlib

    for name in ("ngcrack.core.constraints", "ngcrack.solid.contact", "ngcrack.solid.friction"):
        try:
            mod = importlib.import_module(name)
        except ImportError:
            continue
        if hasattr(mod, "SCHUR_MAX_M"):
            mod.SCHUR_MAX_M = 0  # noqa: B010


def _scene3d(case: str):
    from ngcrack.scenes.coarse3d import bent_penny, inclined_penny
    from ngcrack.solid.scene import SolidScene

    return SolidScene.from_dict(bent_penny() if case.startswith("penny") or case == "mpi-penny" else inclined_penny(0.3))


def run_case(case: str) -> dict | None:
    """Solve one case in this process; its record (None on MPI ranks > 0)."""
    import numpy as np

    import ngcrack as nc

    if case.endswith("-sparse"):
        _force_sparse()

    def once():
        if case in ("griffith", "mpi-griffith"):
            return nc.solve(nc.scenes.load("griffith"))
        if case.startswith("paper-1-"):
            return nc.solve(nc.scenes.load("paper-1"), qp_solver=case.rpartition("-")[2])
        if case == "friction-2d":
            return nc.solve(nc.scenes.load("inclined-compression").with_(friction=0.3))
        return nc.solve(_scene3d(case))

    once()  # the lazy imports and the first use of the solvers, outside the timings
    seconds, contact = [], []
    for _ in range(SOLVES):
        t0 = time.process_time()
        sol = once()
        seconds.append(time.process_time() - t0)
        contact.append(float(sol.timings.get("contact", 0.0)) if sol is not None else 0.0)
    seconds, contact = min(seconds), min(contact)
    if sol is None:
        return None
    if getattr(sol, "fronts", None) and hasattr(sol, "normal_jumps") and getattr(sol, "smesh", None) is not None:
        unknowns = np.asarray(sol.normal_jumps(), dtype=float).ravel()
        K = [np.concatenate([np.ravel(f.K_I), np.ravel(f.K_II), np.ravel(f.K_III)]) for f in sol.fronts]
    else:
        qp = sol.qp
        unknowns = np.asarray(getattr(qp, "z", qp.j), dtype=float)
        K = [np.array([t.K_I, t.K_II]) for t in sol.tips]
    return {"unknowns": unknowns.tolist(), "K": (np.concatenate(K) if K else np.zeros(0)).tolist(), "kkt": {k: float(v) for k, v in sol.kkt.items()},
            "seconds": seconds, "contact": contact, "from": os.path.abspath(nc.__file__)}


def _mpiexec() -> str:
    return shutil.which("mpiexec") or os.path.join(os.path.dirname(sys.executable), "mpiexec")


def record(root: str, cases=CASES) -> dict:
    """Every case in its own process with `root` on the PYTHONPATH (MPI cases under mpiexec -n 2)."""
    out = {}
    env = dict(os.environ, PYTHONPATH=root, OMP_NUM_THREADS="1")
    for case in cases:
        target = os.path.join(root, f".strategies-{case}.json")
        cmd = [sys.executable, os.path.abspath(__file__), "--one", case, target]
        if case.startswith("mpi-"):
            cmd = [_mpiexec(), "-n", "2", *cmd]
        proc = subprocess.run(cmd, env=env, cwd=root, capture_output=True, text=True, timeout=900)
        if proc.returncode != 0:
            raise RuntimeError(f"{case} in {root}: {proc.stderr[-1500:]}")
        with open(target) as f:
            out[case] = json.load(f)
        os.remove(target)
        if not out[case]["from"].startswith(os.path.abspath(root) + os.sep):  # the checkout asked for, not another
            raise RuntimeError(f"{case}: ngcrack was imported from {out[case]['from']}, not from {root}")
    return out


def differences(a: dict, b: dict) -> dict:
    """Per case: the largest relative difference of the crack unknowns and of K, and the largest KKT residual of b."""
    import numpy as np

    rows = {}
    for case in a:
        if case not in b:
            continue
        d = {}
        for key in ("unknowns", "K"):
            x, y = np.array(a[case][key]), np.array(b[case][key])
            d[key] = float(np.max(np.abs(x - y)) / max(np.max(np.abs(x)), 1e-300)) if x.shape == y.shape and x.size else \
                (0.0 if x.shape == y.shape else float("inf"))
        d["kkt"] = max(b[case]["kkt"].values())
        rows[case] = d
    return rows


def table(before: dict, after: dict) -> str:
    lines = ["| case | solve CPU s before | solve CPU s after | contact s before | contact s after | rel diff jumps | rel diff K | KKT after |",
             "|---|---|---|---|---|---|---|---|"]
    for case, d in differences(before, after).items():
        b, a = before[case], after[case]
        lines.append(f"| {case} | {b['seconds']:.2f} | {a['seconds']:.2f} | {b['contact']:.3f} | {a['contact']:.3f} | "
                     f"{d['unknowns']:.1e} | {d['K']:.1e} | {d['kkt']:.1e} |")
    return "\n".join(lines)


def _fastest(runs: list[dict]) -> dict:
    out = {}
    for case in runs[0]:
        best = min(runs, key=lambda r: r[case]["seconds"])[case]
        out[case] = dict(best, contact=min(r[case]["contact"] for r in runs))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--one", nargs=2, metavar=("CASE", "OUT"), help=argparse.SUPPRESS)
    p.add_argument("--record", metavar="OUT")
    p.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    p.add_argument("--before", metavar="CHECKOUT")
    p.add_argument("--cases", nargs="*", default=list(CASES))
    p.add_argument("--root", help="the checkout --record solves with (default: this one)")
    p.add_argument("--repeats", type=int, default=REPEATS, help="runs of each case per checkout (the fastest counts)")
    args = p.parse_args(argv)
    if args.one:
        rec = run_case(args.one[0])
        if rec is not None:
            with open(args.one[1], "w") as f:
                json.dump(rec, f)
        return 0
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if args.record:
        root = os.path.abspath(args.root or here)
        with open(args.record, "w") as f:
            json.dump(_fastest([record(root, args.cases) for _ in range(1)]), f)
        return 0
    if args.compare:
        before, after = (json.load(open(x)) for x in args.compare)
        print(table(before, after))
        return 0
    if args.before:
        runs_b, runs_a = [], []
        for _ in range(args.repeats):  # interleaved: the machine's load falls on both alike
            runs_b.append(record(os.path.abspath(args.before), args.cases))
            runs_a.append(record(here, args.cases))
        print(table(_fastest(runs_b), _fastest(runs_a)))
        return 0
    p.print_help()
    return 0


if __name__ == "__main__":
    sys.exit(main())
