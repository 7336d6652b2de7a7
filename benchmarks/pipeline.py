"""What the staged pipeline costs against another checkout of ngcrack, side by side.

    python benchmarks/pipeline.py --baseline /path/to/other/checkout [--repeat 5]

Each case runs in its own process, alternately with this checkout and the baseline (so
that a busy machine slows both alike), single-threaded; the table gives the median CPU
seconds of each and their ratio. Cases: fresh one-shot solves (`nc.solve`) of griffith
(bdm), paper-1 (tdnns) and inclined-compression (peers), and the explorer's load change
on the teaching inclined crack at about 1e5 unknowns (the model's `update(load=...)`,
no figure). No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import statistics
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parents[1]

CASES = {
    "solve griffith bdm": "solve:griffith:bdm",
    "solve paper-1 tdnns": "solve:paper-1:tdnns",
    "solve inclined-compression peers": "solve:inclined-compression:peers",
    "explorer load change (1e5 unknowns)": "explore",
}


def run_case(spec: str) -> float:
    """CPU seconds of one case in this process."""
    import time

    import ngcrack as nc

    if spec == "explore":
        model = nc.Study("inclined-crack", element="bdm", maxh=0.22, solve_options={"tip_h": 0.02})
        times = []
        for k in range(6):
            c0 = time.process_time()
            model.update(load=(0.8, 1.0)[k % 2])
            times.append(time.process_time() - c0)
        assert model.error is None, model.error
        return statistics.median(times)
    _, scene, element = spec.split(":")
    sc = nc.scenes.load(scene)
    nc.solve(sc, element=element, maxh=2.0)  # warm-up: imports and compiled forms
    c0 = time.process_time()
    nc.solve(sc, element=element)
    return time.process_time() - c0


def in_process(checkout: pathlib.Path, spec: str) -> float:
    env = dict(os.environ, PYTHONPATH=str(checkout), NGCRACK_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    out = subprocess.run([sys.executable, __file__, "--case", spec], capture_output=True, text=True, env=env,
                         cwd=checkout, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", type=pathlib.Path, help="another checkout of ngcrack to compare with")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--case", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.case:
        print(run_case(args.case))
        return
    if args.baseline is None:
        ap.error("--baseline: the checkout to compare with is missing")
    print("| case | this checkout, CPU s | baseline, CPU s | ratio |\n|---|---|---|---|")
    for label, spec in CASES.items():
        new, old = [], []
        for _ in range(args.repeat):
            new.append(in_process(HERE, spec))
            old.append(in_process(args.baseline.resolve(), spec))
        n, o = statistics.median(new), statistics.median(old)
        print(f"| {label} | {n:.3f} | {o:.3f} | {n / o:.2f} |", flush=True)


if __name__ == "__main__":
    main()
