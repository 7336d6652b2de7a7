"""The stability study: locking as nu -> 1/2, the incompressible limit, stiffness and scale.

Three parts, each a tidy pandas table (one row per run) and a figure:

1. Locking. Errors against nu in {0.3, ..., 0.5 - 1e-8, 0.5} for every element, on
   - a manufactured solution (unit square, clamped on three sides, traction on top):
     u = curl(psi) + w / lambda, sigma = 2 mu eps(curl psi) + mu/lambda (grad w + grad w^T)
     + div(w) I, exact for every nu including 1/2 (lambda = infinity), with psi =
     (sin(pi x) sin(pi y))^2 and w = (sin(pi x) sin(pi y), 0); relative L2 errors of u
     and sigma;
   - griffith: the opening against the closed form 4 p (1 - nu^2)/E sqrt(a^2 - s^2);
   - paper-2: u and sigma against bdm on a mesh of half the size at the same nu.
   The displacement baselines (h1p1, h1p2) lock; at nu = 1/2 they are refused (NaN).
2. Stiffness and scale, on paper-1 (contact active on part of the crack): E from 1e-3
   to 1e12, loads from 1e-9 to 1e9, domain sizes from 1e-3 to 1e3. The crack jumps
   must scale with load * size / E and the stresses with load: the table holds the
   relative deviation from that law, the KKT residuals and the condition estimates of
   K and of the crack Schur complement S.
3. Extreme geometry: a 1:100 strip with a crack under uniaxial compression (exact:
   uniform stress, closed crack) and griffith with the tip mesh size 1e-4 of maxh.

`run(quick, out)` runs all three and writes CSV, Markdown and PNG files.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError
from ..core.solve import solve
from ..planar.elements import ELEMENTS, MIXED, Loads
from ..planar.scene import BoundaryCondition, Crack, Material, Scene

NUS = (0.3, 0.49, 0.499, 0.4999, 0.49999, 0.5 - 1e-8, 0.5)
QUICK_NUS = (0.3, 0.499, 0.49999, 0.5)
E_FACTORS = (1e-3 / 206900.0, 1.0, 1e12 / 206900.0)
LOAD_FACTORS = (1e-9, 1.0, 1e9)
SIZE_FACTORS = (1e-3, 1.0, 1e3)


# ----------------------------------------------------------------------------- locking


def _mms_fields(nu: float, E: float = 1.0):
    """(u, sigma, f) of the manufactured solution, exact for every nu in (-1, 1/2]."""
    x, y = ngs.x, ngs.y
    mu = E / (2.0 * (1.0 + nu))
    inv_lam = 0.0 if nu == 0.5 else (1.0 + nu) * (1.0 - 2.0 * nu) / (E * nu)
    b = ngs.sin(math.pi * x) * ngs.sin(math.pi * y)
    psi = b * b
    w = ngs.CF((b, 0.0))
    u = ngs.CF((psi.Diff(y), -psi.Diff(x))) + inv_lam * w

    def grad(v):
        return ngs.CF((v[0].Diff(x), v[0].Diff(y), v[1].Diff(x), v[1].Diff(y)), dims=(2, 2))

    g = grad(u)
    gw = grad(w)
    sigma = mu * (g + g.trans) + (gw[0, 0] + gw[1, 1]) * ngs.Id(2)
    f = -ngs.CF((sigma[0, 0].Diff(x) + sigma[0, 1].Diff(y), sigma[1, 0].Diff(x) + sigma[1, 1].Diff(y)))
    return u, sigma, f


def _l2(cf, mesh, order: int = 6) -> float:
    return math.sqrt(max(ngs.Integrate(ngs.InnerProduct(cf, cf), mesh, order=order), 0.0))


def manufactured_errors(element: str, nu: float, maxh: float, order: int | None = None,
                        quadrature: int | None = None) -> dict:
    """L2 errors of u and sigma on the manufactured solution: relative (error_u, error_sigma)
    and absolute (abs_error_u, abs_error_sigma), with h = 1 / sqrt(triangles); `order` the
    element's order, `quadrature` the integration order of the errors (None: _l2's)."""
    u, sigma, f = _mms_fields(nu)
    labels = ("b", "r", "t", "l")
    scene = Scene(name="manufactured", polygon=((0, 0), (1, 0), (1, 1), (0, 1)), labels=labels,
                  material=Material(E=1.0, nu=nu), boundary={lab: BoundaryCondition("clamped") for lab in "brl"})
    loads = Loads(body_force=f, clamped=frozenset("brl"), traction={"t": sigma * ngs.CF((0.0, 1.0))})
    sol = solve(scene, element=element, maxh=maxh, loads=loads, **({"order": order} if order is not None else {}))
    q = {} if quadrature is None else {"order": quadrature}
    err_u, err_sigma = _l2(sol.u - u, sol.mesh, **q), _l2(sol.sigma - sigma, sol.mesh, **q)
    return {
        "error_u": err_u / _l2(u, sol.mesh, **q),
        "error_sigma": err_sigma / _l2(sigma, sol.mesh, **q),
        "abs_error_u": err_u,
        "abs_error_sigma": err_sigma,
        "h": 1.0 / math.sqrt(sol.mesh.ne),
        "ndof": sol.ndof["total"],
        "time_s": sol.timings["total"],
    }


def griffith_error(element: str, nu: float, **mesh) -> dict:
    """Relative L2 error of the griffith opening against the closed form (plane strain)."""
    from .. import scenes

    scene = scenes.load("griffith").with_(nu=nu)
    sol = solve(scene, element=element, **mesh)
    prof, ex = sol.profiles[0], scene.exact
    E, p, a = scene.material.E, ex["p"], ex["a"]
    s = prof.s
    weights = np.diff(np.concatenate([[0.0], 0.5 * (s[1:] + s[:-1]), [a]]))
    exact = 4.0 * p * (1.0 - nu**2) / E * np.sqrt(np.maximum(a * a - s * s, 0.0))
    err = math.sqrt(np.sum(weights * (prof.normal_jump - exact) ** 2) / np.sum(weights * exact**2))
    return {"error_opening": err, "ndof": sol.ndof["total"], "time_s": sol.timings["total"],
            "kkt": max(sol.kkt.values())}


def paper2_errors(element: str, nu: float, maxh: float, reference=None) -> dict:
    """u and sigma of paper-2 against a reference solution (bdm, maxh / 2) at the same nu."""
    from .. import scenes

    scene = scenes.load("paper-2").with_(nu=nu)
    ref = reference if reference is not None else solve(scene, element="bdm", maxh=maxh / 2)
    sol = solve(scene, element=element, maxh=maxh)
    mesh = ref.mesh
    pts = ref.crack_mesh.centroids
    mp_ref = mesh(pts[:, 0], pts[:, 1])
    mp = sol.mesh(pts[:, 0], pts[:, 1])

    def rel(a, b):
        a, b = np.asarray(a).reshape(len(pts), -1), np.asarray(b).reshape(len(pts), -1)
        return float(np.linalg.norm(a - b) / np.linalg.norm(b))

    return {"error_u": rel(sol.u(mp), ref.u(mp_ref)), "error_sigma": rel(sol.sigma(mp), ref.sigma(mp_ref)),
            "ndof": sol.ndof["total"], "time_s": sol.timings["total"], "kkt": max(sol.kkt.values())}


def locking_table(elements=ELEMENTS, nus=NUS, maxh: float = 0.1, paper_maxh: float = 0.1, griffith_mesh=None):
    """One row per (case, element, nu); NaN where an element refuses the case (h1 at nu = 1/2)."""
    import pandas as pd

    rows = []
    for nu in nus:
        reference = None
        for element in elements:
            for case in ("manufactured", "griffith", "paper-2"):
                row = {"case": case, "element": element, "nu": nu}
                try:
                    if case == "manufactured":
                        row.update(manufactured_errors(element, nu, maxh))
                    elif case == "griffith":
                        row.update(griffith_error(element, nu, **(griffith_mesh or {})))
                    else:
                        if reference is None:
                            from .. import scenes

                            reference = solve(scenes.load("paper-2").with_(nu=nu), element="bdm", maxh=paper_maxh / 2)
                        row.update(paper2_errors(element, nu, paper_maxh, reference))
                except InputError as exc:  # a refused case (h1 baselines at nu = 1/2)
                    row["refused"] = str(exc).split(":")[0]
                rows.append(row)
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------- stiffness, scale


def scaled_scene(scene: Scene, E: float = 1.0, load: float = 1.0, size: float = 1.0) -> Scene:
    """The scene with E, all loads and all lengths multiplied by the given factors
    (:meth:`~ngcrack.planar.scene.PlanarScene.scaled`: the displacements then scale with load * size / E)."""
    return scene.scaled(E=E, load=load, size=size)


def scale_table(elements=MIXED, scene_name: str = "paper-1", factors=None):
    """Deviation from the scaling laws, KKT residuals and condition estimates."""
    import pandas as pd

    from .. import scenes

    base = scenes.load(scene_name)
    factors = factors or ([("E", f) for f in E_FACTORS] + [("load", f) for f in LOAD_FACTORS]
                          + [("size", f) for f in SIZE_FACTORS])
    rows = []
    for element in elements:
        ref = solve(base, element=element)
        ref_j = np.concatenate([p.normal_jump for p in ref.profiles] + [p.tangential_jump for p in ref.profiles])
        ref_s = np.concatenate([p.normal_stress for p in ref.profiles])
        for kind, factor in factors:
            sc = scaled_scene(base, **{kind: factor})
            sol = solve(sc, element=element, condition=True)
            load, size, E = (factor if kind == "load" else 1.0), (factor if kind == "size" else 1.0), (factor if kind == "E" else 1.0)
            j = np.concatenate([p.normal_jump for p in sol.profiles] + [p.tangential_jump for p in sol.profiles])
            s = np.concatenate([p.normal_stress for p in sol.profiles])
            rows.append({
                "element": element, "scaled": kind, "factor": factor,
                "E": sc.material.E, "diameter": sc.diameter,
                "jump_law_deviation": float(np.max(np.abs(j * E / (load * size) - ref_j)) / np.max(np.abs(ref_j))),
                "stress_law_deviation": float(np.max(np.abs(s / load - ref_s)) / np.max(np.abs(ref_s))),
                **{f"kkt_{k}": v for k, v in sol.kkt.items()},
                "qp_kkt": max(sol.qp.kkt.values()) if sol.qp is not None else 0.0,
                "cond_K": sol.conditioning.get("K"), "cond_S": sol.conditioning.get("S"),
            })
    return pd.DataFrame(rows)


def strip_scene(aspect: float = 100.0, p: float = 1.0) -> Scene:
    """A 1 x aspect strip (height 1) with a crack across its middle under compression p."""
    L = aspect
    return Scene(
        name=f"strip-1:{aspect:g}",
        polygon=((0, 0), (L, 0), (L, 1), (0, 1)),
        labels=("bottom", "right", "top", "left"),
        material=Material(E=206900.0, nu=0.3),
        cracks=(Crack(((0.25 * L, 0.5), (0.75 * L, 0.5))),),
        boundary={"bottom": BoundaryCondition("roller"), "left": BoundaryCondition("roller"),
                  "top": BoundaryCondition("traction", (0.0, -p))},
        maxh=0.25,
    )


def extreme_table(elements=MIXED, aspect: float = 100.0, tip_ratio: float = 1e-4):
    """The 1:100 strip (exact uniform stress) and griffith with tip_h = tip_ratio * maxh."""
    import pandas as pd

    from .. import scenes

    rows = []
    for element in elements:
        sc = strip_scene(aspect)
        sol = solve(sc, element=element, condition=True)
        mesh = sol.mesh
        exact = ngs.CF((0.0, 0.0, 0.0, -1.0), dims=(2, 2))
        rows.append({"case": f"strip 1:{aspect:g}, compression", "element": element, "ndof": sol.ndof["total"],
                     "error": _l2(sol.sigma - exact, mesh) / _l2(exact, mesh),
                     "max_jump": float(max(np.abs(p.normal_jump).max() for p in sol.profiles)),
                     "kkt": max(sol.kkt.values()), "cond_K": sol.conditioning.get("K"),
                     "cond_S": sol.conditioning.get("S")})
        g = scenes.load("griffith")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the graded tip may hold poor triangles: reported below
            res = griffith_error(element, g.material.nu, tip_h=tip_ratio * g.maxh, grading=0.3)
        rows.append({"case": f"griffith, tip_h = {tip_ratio:g} maxh", "element": element, "ndof": res["ndof"],
                     "error": res["error_opening"], "kkt": res["kkt"]})
    return pd.DataFrame(rows)


# ------------------------------------------------------------------------------ report


def _markdown(df, floatfmt=".3g") -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, row in df.iterrows():
        cells = []
        for c in cols:
            v = row[c]
            cells.append(format(v, floatfmt) if isinstance(v, float) and not math.isnan(v) else ("" if isinstance(v, float) else str(v)))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def plot_locking(df, path) -> None:
    from ..planar.plots import new_figure

    cases = [("manufactured", "error_u", "manufactured solution: rel. L2 error of u"),
             ("griffith", "error_opening", "griffith: rel. L2 error of the opening"),
             ("paper-2", "error_sigma", "paper-2: rel. L2 difference of sigma to bdm (h/2)")]
    fig, axes = new_figure(path, nrows=1, ncols=3, figsize=(15, 4.5), constrained_layout=True)
    for ax, (case, col, title) in zip(axes, cases):
        sub = df[df["case"] == case]
        for element, g in sub.groupby("element", sort=False):
            g = g.dropna(subset=[col])
            ax.plot(0.5 - g["nu"] + 1e-9, g[col], "o-", label=element)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("1/2 - nu  (+1e-9, so that nu = 1/2 shows)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative error")
    axes[0].legend()
    fig.savefig(path, dpi=150)


def plot_scale(df, path) -> None:
    from ..planar.plots import new_figure

    fig, axes = new_figure(path, nrows=1, ncols=3, figsize=(15, 4.5), constrained_layout=True)
    for ax, kind in zip(axes, ("E", "load", "size")):
        sub = df[df["scaled"] == kind]
        xcol, xlabel = {"E": ("E", "E"), "load": ("factor", "load factor (tractions, body force)"),
                        "size": ("diameter", "domain diameter")}[kind]
        for element, g in sub.groupby("element", sort=False):
            line, = ax.plot(g[xcol], g["cond_K"], "o-", label=f"{element}: cond(K), Jacobi-scaled")
            ax.plot(g[xcol], g["cond_S"], "s--", color=line.get_color(), label=f"{element}: cond(S), Jacobi-scaled")
            ax.plot(g[xcol], np.maximum(g[["kkt_max_penetration", "kkt_max_tension"]].max(axis=1), 1e-17),
                    "^:", color=line.get_color(), label=f"{element}: KKT (penetration, tension)")
            ax.plot(g[xcol], np.maximum(g[["jump_law_deviation", "stress_law_deviation"]].max(axis=1), 1e-17),
                    "x-.", color=line.get_color(), label=f"{element}: deviation from the scaling law")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_title(f"paper-1 with {kind} scaled", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.savefig(path, dpi=150)


def run(quick: bool = False, out: str | Path = "stability") -> dict[str, Path]:
    """Run the whole study; returns the files written (name -> path)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    nus = QUICK_NUS if quick else NUS
    locking = locking_table(nus=nus, maxh=0.2 if quick else 0.1, paper_maxh=0.2 if quick else 0.1,
                            griffith_mesh=dict(maxh=2.0, crack_h=0.1, tip_h=0.01) if quick else None)
    scale = scale_table(factors=None if not quick else [("E", E_FACTORS[0]), ("E", 1.0), ("E", E_FACTORS[-1]),
                                                        ("load", 1e-9), ("load", 1e9), ("size", 1e-3), ("size", 1e3)])
    extreme = extreme_table(aspect=100.0)
    files = {}
    for name, df in (("locking", locking), ("scale", scale), ("extreme", extreme)):
        csv, md = out / f"{name}.csv", out / f"{name}.md"
        df.to_csv(csv, index=False)
        md.write_text(_markdown(df))
        files[f"{name} table (csv)"], files[f"{name} table (markdown)"] = csv, md
    plot_locking(locking, out / "locking.png")
    plot_scale(scale, out / "scale.png")
    files["error against nu"], files["KKT and condition against E, load, size"] = out / "locking.png", out / "scale.png"
    return files
