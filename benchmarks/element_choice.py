"""Which element when: accuracy, unknowns and run time of every element on two closed forms.

    python benchmarks/element_choice.py

At each scene's default mesh: the Griffith crack's opening (relative L2 error against
4 p (1 - nu^2) / E sqrt(a^2 - s^2), of which about 0.6% is the finite plate's own
effect) and the closed inclined crack's sliding under compression (relative l2 error
over the edge mid points against 4 (1 - nu^2) / E tau sqrt(a^2 - s^2)). Each solve runs twice; the faster wall
time is printed (2 shared cores: expect +-30%). Prints a Markdown table.
"""

from __future__ import annotations

import time

import numpy as np

import ngcrack as nc
from ngcrack.elements import ELEMENTS
from ngcrack.scenes import inclined_closed_form
from ngcrack.study import opening_error


def sliding_error(sol) -> float:
    """Relative l2 error of the tangential jump over the crack's edge mid points (as tests/test_inclined.py)."""
    cf = inclined_closed_form(sol.scene)
    prof = sol.profiles[0]
    a, nu, E = sol.scene.exact["a"], sol.scene.material.nu, sol.scene.material.E
    s = prof.s - a
    exact = 4 * (1 - nu**2) / E * cf["tau"] * np.sqrt(np.clip(a**2 - s**2, 0, None))
    return float(np.linalg.norm(prof.tangential_jump - exact) / np.linalg.norm(exact))


def measure(name: str, element: str, error) -> dict:
    scene = nc.scenes.load(name)
    best = None
    for _ in range(2):
        t0 = time.perf_counter()
        sol = nc.solve(scene, element=element)
        t = time.perf_counter() - t0
        best = t if best is None else min(best, t)
    return {"error": error(sol), "time": best, "ndof": sol.ndof["total"], "global": sol.ndof["global"]}


def main() -> None:
    rows = {el: (measure("griffith", el, opening_error), measure("inclined-compression", el, sliding_error))
            for el in ELEMENTS}
    print("| element | griffith: opening error | unknowns (global) | time | inclined: sliding error | unknowns (global) | time |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for el, (g, i) in sorted(rows.items(), key=lambda kv: kv[1][0]["error"]):
        print(f"| {el} | {100 * g['error']:.2f}% | {g['ndof']} ({g['global']}) | {g['time']:.1f} s "
              f"| {100 * i['error']:.2f}% | {i['ndof']} ({i['global']}) | {i['time']:.1f} s |")


if __name__ == "__main__":
    main()
