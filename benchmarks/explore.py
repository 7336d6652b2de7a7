"""What a change costs in the interactive study, against a fresh solve.

    python benchmarks/explore.py                 # 1e4 and 1e5 unknowns, and the teaching mesh
    python benchmarks/explore.py --repeat 5

Scene: the teaching inclined crack (`nc.scenes.SCENE_FUNCTIONS["inclined-crack"]`, a = 1
at 30 degrees in [-5, 5]^2 under compression), BDM. For each mesh, an `Explorer` (the model) is set up
and then changed, alternately between two values, `repeat` times per kind:

- load: the load multiplier (reuses mesh, matrix, factorization and S: one solve and a QP);
- material: Poisson's ratio (re-assembles on the same mesh);
- geometry: the crack angle (remeshes);
- fresh: `nc.solve` of the same scene from nothing.

Median wall times of `Explorer.update` (no figure), the error estimate's part of a load
change, and one redraw of the figure (`Drawing.render`, held scales). Then the slider-to-figure latency on the
default teaching mesh: an `ExplorerWidget` (the ipywidgets view, no browser) has a control set
and the time until its image holds the new PNG is measured (`ExplorerWidget.latency`:
update, drawing and the widget's value). No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import statistics
import time

import ngcrack as nc

#: (label, maxh, tip_h) of the meshes: about 1e4 and 1e5 unknowns in total
MESHES = [("1e4", 2.5, 0.25), ("1e5", 0.22, 0.02)]
#: each kind of change: the control and the two values it alternates between
CHANGES = {"load": ("load", (0.8, 1.0)), "material": ("nu", (0.35, 0.3)), "geometry": ("angle", (35.0, 30.0))}


def _median_update(study, name, values, repeat):
    """Median wall and CPU (process) time of `repeat` updates of one control, and the
    median time of the error estimate in them."""
    times, cpu, est, redone = [], [], [], None
    for k in range(repeat):
        c0 = time.process_time()
        study.update(**{name: values[k % 2]})
        cpu.append(time.process_time() - c0)
        if study.error:
            raise RuntimeError(study.error)
        times.append(study.latency)
        est.append(float(study.solution.timings.get("estimate", 0.0)))
        redone = study.redone
    return statistics.median(times), statistics.median(cpu), statistics.median(est), redone


def bench_mesh(label, maxh, tip_h, repeat, element="bdm"):
    fn = nc.scenes.SCENE_FUNCTIONS["inclined-crack"]
    t0 = time.perf_counter()
    study = nc.Explorer(fn, element, maxh=maxh, solve_options={"tip_h": tip_h})
    first = time.perf_counter() - t0
    if study.error:
        raise RuntimeError(study.error)
    row = {"mesh": label, "unknowns": study.solution.ndof["total"], "global": study.solution.ndof["global"],
           "contact": study.solution.ndof["contact"], "first": first}
    for kind, (name, values) in CHANGES.items():
        row[kind], row[kind + "_cpu"], row[kind + "_estimate"], row[kind + "_redone"] = \
            _median_update(study, name, values, repeat)
    from ngcrack.shell.explorer import Drawing

    drawing = Drawing()
    drawing.render(study.solution)  # (the first render builds the figure)
    t0 = time.perf_counter()
    for _ in range(repeat):
        drawing.render(study.solution, hold=True)
    row["drawing"] = (time.perf_counter() - t0) / repeat
    fresh, fresh_cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        nc.solve(study.scene, element=element, maxh=maxh, tip_h=tip_h)
        fresh.append(time.perf_counter() - t0)
        fresh_cpu.append(time.process_time() - c0)
    row["fresh"], row["fresh_cpu"] = statistics.median(fresh), statistics.median(fresh_cpu)
    return row


def bench_widget(repeat, element="bdm"):
    """Slider-to-figure latency (update + draw + widget value) on the default teaching mesh."""
    w = nc.explore("inclined-crack", element)
    rows = []
    changes = list(CHANGES.items()) + [("stress field (redraw only)", ("field", ("von_mises", "sigma_nu")))]
    for kind, (name, values) in changes:
        times, cpu, splits = [], [], []
        for k in range(repeat):
            png = w.image.value
            c0 = time.process_time()
            w.controls[name].value = values[k % 2]
            cpu.append(time.process_time() - c0)
            if w.model.error or w.image.value == png:
                raise RuntimeError(f"{kind}: the figure did not change ({w.model.error})")
            times.append(w.latency)
            splits.append(dict(w.timing))
        keys = list(dict.fromkeys(k for s in splits for k in s))  # ("scales" only where a reference solve ran)
        split = {key: statistics.median(s.get(key, 0.0) for s in splits) for key in keys}
        rows.append((kind, statistics.median(times), statistics.median(cpu), split))
    return w.model.solution.ndof["total"], rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--meshes", default=",".join(m[0] for m in MESHES), help="which of 1e4,1e5")
    args = ap.parse_args(argv)
    wanted = args.meshes.split(",")
    print("wall time s (CPU time s), median of", args.repeat)
    print("| mesh | unknowns (global, contact) | first solve | load change | material change | "
          "geometry change | fresh solve | fresh / load | fresh / material | estimate in a load change | "
          "drawing |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for label, maxh, tip_h in MESHES:
        if label not in wanted:
            continue
        r = bench_mesh(label, maxh, tip_h, args.repeat)
        cells = " | ".join(f"{r[k]:.3f} ({r[k + '_cpu']:.3f})" for k in ("load", "material", "geometry", "fresh"))
        print(f"| {r['mesh']} | {r['unknowns']} ({r['global']}, {r['contact']}) | {r['first']:.2f} | {cells} | "
              f"{r['fresh'] / r['load']:.1f} | {r['fresh'] / r['material']:.1f} | "
              f"{r['load_estimate']:.3f} ({r['load_estimate'] / r['load']:.0%}) | {r['drawing']:.2f} |", flush=True)
    ndof, rows = bench_widget(args.repeat)
    print(f"\nslider-to-figure latency, default teaching mesh ({ndof} unknowns), median of {args.repeat}:")
    for kind, t, c, split in rows:
        parts = " + ".join(f"{k} {v:.3f}" for k, v in split.items())
        print(f"  {kind:<28} {t:.3f} s wall ({c:.3f} s CPU); split: {parts}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
