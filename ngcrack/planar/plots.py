"""Matplotlib figures of a solution (matplotlib is imported lazily, headless-safe).

- isolines of sigma_nu = (sigma nu).nu, nu the first crack's normal ((0, 1) without a crack),
  as in the paper's Figures 7-8;
- the deformed body, each triangle moved by the locally post-processed displacement
  u*(x) = u_T + (A sigma + r W)(x - c_T) (the constitutive law grad u = A sigma + r W,
  W = [[0, -1], [1, 0]]), magnified so that the crack opening is visible.
"""

from __future__ import annotations

import numpy as np

#: the largest displacement of the deformed plot, as a fraction of the body's diameter
DEFORMED_FRACTION = 0.06


def _element_data(sol):
    verts, tris = sol.crack_mesh.points, sol.crack_mesh.triangles
    cent = verts[tris].mean(axis=1)
    return verts, tris, cent


def sigma_nu_field(sol):
    """(vertices, triangles, vertex values of sigma_nu, nu): sigma_nu averaged at the vertices."""
    verts, tris, cent = _element_data(sol)
    nu = sol.crack_mesh.cracks[0].normal[0] if sol.crack_mesh.cracks else np.array([0.0, 1.0])
    mp = sol.mesh(cent[:, 0], cent[:, 1])
    sig = np.asarray(sol.sigma(mp)).reshape(-1, 2, 2)
    snn = np.einsum("i,eij,j->e", nu, sig, nu)
    vals = np.zeros(len(verts))
    cnt = np.zeros(len(verts))
    np.add.at(vals, tris.ravel(), np.repeat(snn, 3))
    np.add.at(cnt, tris.ravel(), 1.0)
    return verts, tris, vals / np.maximum(cnt, 1), nu


def centroid_points(sol):
    """The triangles' centroids as NGSolve mesh points, in element order (built in their
    own triangles, geometry.element_points; found by the point search where they cannot be)."""
    from .geometry import element_points

    mp = element_points(sol.crack_mesh, np.full((1, 3), 1.0 / 3.0))
    if mp is None:
        cent = sol.crack_mesh.points[sol.crack_mesh.triangles].mean(axis=1)
        mp = sol.mesh(cent[:, 0], cent[:, 1])
    return mp


def centroid_stress(sol, points=None) -> np.ndarray:
    """(ne, 2, 2) the stress at the triangles' centroids (the tree compiled first: the
    same operations, several times faster on 1e5 points, measured)."""
    mp = centroid_points(sol) if points is None else points
    return np.asarray(sol.sigma.Compile()(mp)).reshape(-1, 2, 2)


def element_displacements(sol, sigma: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(corner points (ne, 3, 2), corner displacements (ne, 3, 2)) of u* per triangle
    (`sigma`: the stress at the centroids, if the caller has it)."""
    from .materials import compliance

    verts, tris, cent = _element_data(sol)
    mp = centroid_points(sol)
    u = np.asarray(sol.u(mp)).reshape(-1, 2)
    sig = centroid_stress(sol, mp) if sigma is None else sigma
    mat = sol.scene.material
    A = compliance(mat.E, mat.nu, mat.plane)
    grad = A.apply(sig)
    if sol.rotation is not None:
        r = np.asarray(sol.rotation(mp)).reshape(-1)
        grad = grad + r[:, None, None] * np.array([[0.0, -1.0], [1.0, 0.0]])[None]
    corners = verts[tris]
    disp = u[:, None, :] + np.einsum("eij,ekj->eki", grad, corners - cent[:, None, :])
    return corners, disp


def crack_faces(sol, corners: np.ndarray, disp: np.ndarray, side: np.ndarray | None = None) -> list[dict]:
    """Per crack: its vertices' points, the displacement of each face there (the mean of
    the corner displacements of the triangles on that side; a tip inside the body, where
    the faces meet, takes the mean of all), the normals, and the opening [u].nu = (u+ - u-).nu."""
    from .geometry import crack_side

    cm = sol.crack_mesh
    if not cm.cracks:
        return []
    if side is None:
        side = crack_side(cm)
    nv = len(cm.points)
    acc = {s: np.zeros((nv, 2)) for s in (1.0, -1.0)}
    cnt = {s: np.zeros(nv) for s in (1.0, -1.0)}
    tris = cm.triangles
    for s in (1.0, -1.0):
        rows = np.flatnonzero(side == s)
        np.add.at(acc[s], tris[rows].ravel(), disp[rows].reshape(-1, 2))
        np.add.at(cnt[s], tris[rows].ravel(), 1.0)
    faces = []
    for crack in cm.cracks:
        vs = crack.vertices()
        n_edge = crack.normal
        normal = np.vstack([n_edge[:1], 0.5 * (n_edge[1:] + n_edge[:-1]), n_edge[-1:]])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        up = acc[1.0][vs] / np.maximum(cnt[1.0][vs], 1.0)[:, None]
        um = acc[-1.0][vs] / np.maximum(cnt[-1.0][vs], 1.0)[:, None]
        tip = np.array([int(v) in cm.tip_vertices for v in vs])
        mean = (acc[1.0][vs] + acc[-1.0][vs]) / np.maximum(cnt[1.0][vs] + cnt[-1.0][vs], 1.0)[:, None]
        up[tip], um[tip] = mean[tip], mean[tip]
        faces.append({"crack": crack.index, "points": cm.points[vs], "plus": up, "minus": um, "normal": normal,
                      "opening": np.einsum("ij,ij->i", up - um, normal)})
    return faces


def tip_names(tips) -> list[str]:
    """A name per tip, by position: "left tip" / "right tip" at the ends of a crack closer
    to horizontal, "lower tip" / "upper tip" of a steeper one; prefixed "crack k, " where
    the tips belong to more than one crack. `tips`: objects or dicts with crack, end, x, y."""
    def get(t, k):
        return t.get(k) if isinstance(t, dict) else getattr(t, k, None)

    by_crack: dict = {}
    for t in tips:
        by_crack.setdefault(get(t, "crack"), []).append(t)
    several = len(by_crack) > 1
    names = []
    for t in tips:
        crack = get(t, "crack")
        mates = by_crack[crack]
        name = "tip"
        if len(mates) == 2 and get(t, "x") is not None:
            a = np.array([get(t, "x"), get(t, "y")], float)
            other = mates[1] if mates[0] is t else mates[0]
            d = a - np.array([get(other, "x"), get(other, "y")], float)
            if abs(d[0]) >= abs(d[1]):
                name = "right tip" if d[0] > 0 else "left tip"
            else:
                name = "upper tip" if d[1] > 0 else "lower tip"
        elif get(t, "end") is not None:
            name = f"{get(t, 'end')} tip"
        names.append(f"crack {int(crack) + 1}, {name}" if several and crack is not None else name)
    return names


def plot_solution(sol, path=None, levels: int = 20):
    """Isolines of sigma_nu next to the magnified deformed body; saved to `path` if given
    (then on a figure of its own, `new_figure`: pyplot's backend is left alone).

    The cracks are drawn where the deformed body has them: each crack's two faces moved by
    the displacement of the triangles on their side (`explorer.fields.crack_faces`), the
    undeformed crack dashed grey beneath them."""
    from matplotlib.collections import PolyCollection
    from matplotlib.tri import Triangulation

    verts, tris, snn, nu = sigma_nu_field(sol)
    poly = np.asarray(sol.scene.polygon)
    width = np.ptp(poly[:, 0])
    height = np.ptp(poly[:, 1])
    horizontal = width >= height
    fig, axes = new_figure(path, nrows=2 if horizontal else 1, ncols=1 if horizontal else 2,
                           figsize=(9, 6) if horizontal else (11, 5), constrained_layout=True)
    ax = axes[0]
    tri = Triangulation(verts[:, 0], verts[:, 1], tris)
    corners = verts[tris]
    a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = np.zeros(len(verts))  # a vertex's share of the area: the tip's many small triangles weigh little
    np.add.at(area, tris.ravel(), np.repeat(0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) / 3.0, 3))
    lo, hi = robust_limits(snn, weights=area)
    bounds = np.linspace(lo, hi, levels + 1)
    # red tension, blue compression: a diverging map about 0 where both occur, else one side of it
    cmap = "RdBu_r" if lo < 0 < hi else ("Reds" if lo >= 0 else "Blues_r")
    cf = ax.tricontourf(tri, np.clip(snn, lo, hi), levels=bounds, cmap=cmap, extend="both")
    ax.tricontour(tri, snn, levels=bounds, colors="k", linewidths=0.3)
    from matplotlib.ticker import MaxNLocator

    cb = fig.colorbar(cf, ax=ax, label=r"$\sigma_\nu$ (clipped at the area's 1st and 99th percentiles)")
    ticks = MaxNLocator(7).tick_values(lo, hi)
    cb.set_ticks(ticks[(ticks >= lo) & (ticks <= hi)])
    for pts in sol.crack_mesh.polylines:
        ax.plot(pts[:, 0], pts[:, 1], "k-", lw=2.0)
    ax.set_title(rf"$\sigma_\nu$, $\nu$ = ({nu[0] + 0.0:.2f}, {nu[1] + 0.0:.2f})" + f"\n{sol.scene.name}, {sol.element}",
                 fontsize=10)
    ax = axes[1]
    corners, disp = element_displacements(sol)
    diam = sol.scene.diameter
    umax = float(np.max(np.linalg.norm(disp, axis=2)))
    scale = DEFORMED_FRACTION * diam / umax if umax > 0 else 0.0
    ax.add_collection(PolyCollection(corners, facecolors="none", edgecolors="0.85", linewidths=0.3))
    ax.add_collection(PolyCollection(corners + scale * disp, facecolors="tab:blue", edgecolors="tab:blue",
                                     linewidths=0.2, alpha=0.6))
    for pts in sol.crack_mesh.polylines:
        ax.plot(pts[:, 0], pts[:, 1], "--", color="0.5", lw=0.8)
    for f in crack_faces(sol, corners, disp):
        for side in ("plus", "minus"):
            moved = f["points"] + scale * f[side]
            ax.plot(moved[:, 0], moved[:, 1], "r-", lw=1.2)
    ax.set_title(f"deformed body, displacement x {scale:.3g}\nred: the crack faces; dashed: the undeformed crack",
                 fontsize=10)
    for a in axes:
        a.set_aspect("equal")
        a.autoscale_view()
    return _finish(fig, path)


def robust_limits(values, low: float = 1.0, high: float = 99.0, weights=None) -> tuple[float, float]:
    """Colour limits from the `low`-th and `high`-th percentiles of `values` (weighted by
    `weights`, an area, if given), symmetric about zero where the values change sign: a
    crack tip's singular peak is clipped, it does not set the scale."""
    v = np.asarray(values, float)
    w = np.ones_like(v) if weights is None else np.asarray(weights, float)
    ok = np.isfinite(v) & (w > 0)
    if not np.any(ok):
        return -1.0, 1.0
    order = np.argsort(v[ok])
    vs, cum = v[ok][order], np.cumsum(w[ok][order])

    def pct(q):
        return float(vs[min(int(np.searchsorted(cum, q / 100.0 * cum[-1])), len(vs) - 1)])

    lo, hi = pct(low), pct(high)
    if lo < 0 < hi:
        m = max(-lo, hi)
        return -m, m
    if hi <= lo:
        return lo - 1.0, hi + 1.0
    return lo, hi


# ------------------------------------------------------------------- study figures
#: one colour and marker per element family, stable across figures
ELEMENT_STYLE = {
    "peers": ("tab:blue", "o"), "bdm": ("tab:orange", "s"), "tdnns": ("tab:green", "^"),
    "h1p1": ("tab:red", "v"), "h1p2": ("tab:purple", "D"),
}
#: how the study labels an element's adaptive runs ("bdm (adaptive)"): drawn dashed in the element's colour
ADAPTIVE_SUFFIX = " (adaptive)"
#: line style per quantity when several share an axis
QUANTITY_LINESTYLE = {"u1": "-", "u2": "--", "sigma_t1": "-", "sigma_nu": "--", "opening": ":"}


def _element_style(element: str, k: int = 0):
    import matplotlib

    if element in ELEMENT_STYLE:
        return ELEMENT_STYLE[element]
    base = element.removesuffix(ADAPTIVE_SUFFIX)
    if base in ELEMENT_STYLE:  # an element's adaptive runs: its colour, a plus marker
        return ELEMENT_STYLE[base][0], "P"
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    return colors[(5 + k) % len(colors)], "P"


def new_figure(path=None, **kw):
    """(figure, axes) as pyplot.subplots(**kw) gives them. To be shown (`path` None): a pyplot
    figure, drawn by the notebook's backend. To be saved (`path` given): a
    matplotlib.figure.Figure with its own Agg canvas, so that writing a file never touches
    pyplot's figures or backend (a notebook's later figures still show)."""
    if path is None:
        import matplotlib.pyplot as plt

        return plt.subplots(**kw)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig_kw = {k: kw.pop(k) for k in ("figsize", "dpi", "layout") if k in kw}
    if kw.pop("constrained_layout", False):
        fig_kw["layout"] = "constrained"
    fig = Figure(**fig_kw)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(**kw)


_figure = new_figure


def _finish(fig, path, dpi: int = 150):
    """Save `fig` to `path` if given; the figure either way."""
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig


def plain_log_ticks(ax) -> None:
    """Plain tick labels on log axes (0.2, 5000, 1e+05); minor labels at 2 and 5 on short ranges."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    def plain(v, _pos=None):
        return f"{v:g}" if 1e-3 <= abs(v) < 1e5 else f"{v:.0e}".replace("e+0", "e").replace("e-0", "e-")

    def minor(v, _pos=None):
        lead = round(v / 10 ** np.floor(np.log10(v)), 6)
        return plain(v) if lead in (2.0, 5.0) else ""

    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if axis.get_scale() != "log" or lo <= 0:
            continue
        axis.set_major_formatter(FuncFormatter(plain))
        axis.set_minor_formatter(FuncFormatter(minor) if np.log10(hi / lo) < 1.6 else NullFormatter())


def _by_element(df):
    """(element, rows) in a stable order: the known families first, in ELEMENT_STYLE order."""
    known = list(ELEMENT_STYLE)
    names = sorted(dict.fromkeys(df["element"]), key=lambda e: (known.index(e) if e in known else len(known), e))
    return [(e, df[df["element"] == e]) for e in names]


def _rows_with_error(df, quantity: str):
    col = f"err_{quantity}"
    g = df[np.isfinite(df[col].to_numpy(float)) & (df[col].to_numpy(float) > 0)]
    return g.sort_values("ndof_total")


def _draw_guides(ax, guides: dict, points, xmin: float, xmax: float, clearance: float = 1.3) -> None:
    """Guide lines e ~ x^-r over the right half (in log) of the abscissa's range (at least its
    last decade), from one
    point there, fanning out to the right: they meet only at that start (so never cross
    each other) and lie above every drawn line by `clearance` (the steepest sets the common
    start); each is labelled at its right end."""
    x0 = max(xmin, min(float(np.sqrt(xmin * xmax)), xmax / 10.0))  # the right half, or the last decade
    need = []
    for x, y in points:
        x, y = np.asarray(x, float), np.asarray(y, float)
        if not len(x):
            continue
        o = np.argsort(x)
        lx, ly = np.log(x[o]), np.log(y[o])
        keep = x[o] >= x0
        xs_, ys_ = list(x[o][keep]), list(y[o][keep])
        if lx[0] <= np.log(x0) <= lx[-1]:  # where the line passes the guides' start
            xs_.append(x0)
            ys_.append(float(np.exp(np.interp(np.log(x0), lx, ly))))
        need += [(xi, yi) for xi, yi in zip(xs_, ys_)]
    order = sorted(guides.items(), key=lambda kv: kv[1])  # shallowest first: it ends highest
    y0 = max((yi * (xi / x0) ** r for _, r in order for xi, yi in need), default=1.0) * clearance
    xs = np.array([x0, xmax])
    for j, (label, r) in enumerate(order):
        ys = y0 * (xs / x0) ** (-r)
        ax.loglog(xs, ys, color="0.55", lw=0.9, ls=(0, (5, 2 + 2 * j)), zorder=1)
        ax.annotate(label, (xs[1], ys[1]), textcoords="offset points", xytext=(-3, 4), fontsize=8, color="0.25",
                    ha="right", va="bottom", bbox={"fc": "white", "ec": "none", "alpha": 0.85, "pad": 0.6})


def _h_axis(ax, triangles, h) -> None:
    """A top axis in h, the largest edge, from the rows' meshes: h = c T^(-1/2), c fitted."""
    ok = np.isfinite(triangles) & np.isfinite(h) & (triangles > 0) & (h > 0)
    if not np.any(ok):
        return
    c = float(np.exp(np.mean(np.log(h[ok]) + 0.5 * np.log(triangles[ok]))))

    def to_h(t):
        return c / np.sqrt(np.clip(t, 1e-100, None))

    def to_t(hh):
        return (c / np.clip(hh, 1e-100, None)) ** 2

    from matplotlib.ticker import FuncFormatter, LogLocator

    top = ax.secondary_xaxis("top", functions=(to_h, to_t))
    top.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    top.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos=None: f"{v:g}"))
    top.xaxis.set_minor_formatter(FuncFormatter(lambda v, _pos=None: ""))
    top.set_xlabel(rf"$h$, the largest edge ($\approx {c:.2g}\,T^{{-1/2}}$ on these meshes)", fontsize=8)
    top.tick_params(labelsize=8)


def plot_convergence(df, quantities, path=None, title: str | None = None, paper_points: dict | None = None,
                     guides: dict | None = None, ax=None, x: str = "ndof_total", coarse_points: dict | None = None):
    """Log-log relative L2 error against the number of unknowns (the paper's Figures 3-6).

    One colour per element, one line style per quantity; the legend gives the fitted
    rate in dof (e ~ dof^-r) and in h (e ~ h^r). `paper_points`: {quantity: (abscissa, err)}
    drawn as grey markers, in the units of `x`; `guides`: {label: exponent in dof} drawn as
    thin grey lines. x: the abscissa column, "ndof_total" (unknowns) or "n_elements"
    (triangles, a footing shared with other counts of unknowns). `coarse_points`:
    {quantity: {element: (abscissa, err)}}, the element's errors on further (coarser) meshes,
    drawn thin in its colour, so that its line reaches the paper's points.
    """
    from ..studies.sweeps import QUANTITY_LABELS, fitted_rates

    fig = None
    if ax is None:
        fig, ax = _figure(path, figsize=(11, 5.4), constrained_layout=True)
    rates = fitted_rates(df, quantities)
    ymin, ymax, xmin, xmax = np.inf, 0.0, np.inf, 0.0
    points: list = []  # every (x, error) drawn: the guides keep clear of them
    for k, (element, g) in enumerate(_by_element(df)):
        color, marker = _element_style(element, k)
        for q in quantities:
            r = _rows_with_error(g, q)
            if r.empty:
                continue
            xs_, y = r[x].to_numpy(float), r[f"err_{q}"].to_numpy(float)
            fit = rates[(rates.element == element) & (rates.quantity == q)]
            label = f"{element}, {QUANTITY_LABELS[q]}"
            if len(fit):
                label += f": rate {fit.rate_dof.iloc[0]:.2f} in dof ({fit.rate_h.iloc[0]:.2f} in h)"
            ax.loglog(xs_, y, QUANTITY_LINESTYLE.get(q, "-"), color=color, marker=marker, ms=5,
                      mfc="white" if QUANTITY_LINESTYLE.get(q) == "--" else color, label=label)
            ymin, ymax, xmin, xmax = min(ymin, y.min()), max(ymax, y.max()), min(xmin, xs_.min()), max(xmax, xs_.max())
            points.append((xs_, y))
    for q, per_element in (coarse_points or {}).items():
        for k, (element, (cx, cy)) in enumerate(per_element.items()):
            ok = np.isfinite(cy) & (cy > 0)
            cx, cy = np.asarray(cx, float)[ok], np.asarray(cy, float)[ok]
            if not len(cx):
                continue
            order = np.argsort(cx)
            color, marker = _element_style(element, k)
            ax.loglog(cx[order], cy[order], QUANTITY_LINESTYLE.get(q, "-"), color=color, marker=marker, ms=3.5, lw=0.8,
                      alpha=0.6, mfc="white" if QUANTITY_LINESTYLE.get(q) == "--" else color)
            ymin, ymax, xmin, xmax = min(ymin, cy.min()), max(ymax, cy.max()), min(xmin, cx.min()), max(xmax, cx.max())
            points.append((cx, cy))
    if points and coarse_points:  # one legend line for all of them
        ax.loglog([], [], "-", color="0.5", marker="o", ms=3.5, lw=0.8, alpha=0.6,
                  label="thin, same styles: coarser meshes (the comparison's, its own reference)")
    for j, (q, (px, py)) in enumerate((paper_points or {}).items()):
        ax.loglog(px, py, ":" if j % 2 == 0 else "-.", color="0.45", marker="x+"[j % 2], ms=6,
                  label=f"paper (Table {1 + list(QUANTITY_LABELS).index(q)}), {QUANTITY_LABELS[q]}"
                        + (", dof converted to triangles" if x == "n_elements" else ""))
        ymin, ymax, xmin, xmax = min(ymin, min(py)), max(ymax, max(py)), min(xmin, min(px)), max(xmax, max(px))
        points.append((np.asarray(px, float), np.asarray(py, float)))
    if guides and np.isfinite(ymin) and xmax > xmin:
        _draw_guides(ax, guides, points, xmin, xmax)
    ax.set_xlabel(r"triangles $T$ (in 2D $T \sim h^{-2}$)" if x == "n_elements" else "unknowns (dof, total)")
    if x == "n_elements" and {"h", "n_elements"} <= set(df.columns) and len(df):
        _h_axis(ax, df["n_elements"].to_numpy(float), df["h"].to_numpy(float))
    ax.set_ylabel(r"relative $L^2(\Omega)$ error")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)  # beside: off the data
    plain_log_ticks(ax)
    if title:
        ax.set_title(title)
    return _finish(fig, path) if fig is not None else ax.figure


#: the abscissa's words per time column of a sweep's rows
TIME_LABELS = {"time_cpu": "CPU time of the solve [s] (process CPU seconds)",
               "time_total": "run time of the solve [s] (wall clock)"}


def plot_error_vs_time(df, quantity: str, path=None, title: str | None = None, time_column: str | None = None):
    """Log-log error of one quantity against the solve's time: one panel per scene, one line per element.

    time_column: "time_cpu" (CPU seconds of the process: what the solve costs, whatever else
    the machine runs) by default where every row has it, else "time_total" (wall clock)."""
    from ..studies.sweeps import QUANTITY_LABELS

    if time_column is None:
        has_cpu = "time_cpu" in df.columns and np.all(np.isfinite(df["time_cpu"].to_numpy(float)))
        time_column = "time_cpu" if has_cpu else "time_total"

    scenes = list(dict.fromkeys(df["scene"]))
    fig, axes = _figure(path, nrows=1, ncols=len(scenes), figsize=(5.4 * len(scenes), 5.0), squeeze=False,
                        constrained_layout=True)
    for ax, scene in zip(axes[0], scenes):
        sub = df[df["scene"] == scene]
        for k, (element, g) in enumerate(_by_element(sub)):
            r = _rows_with_error(g, quantity).sort_values(time_column)
            if r.empty:
                continue
            color, marker = _element_style(element, k)
            ax.loglog(r[time_column], r[f"err_{quantity}"], "--" if element.endswith(ADAPTIVE_SUFFIX) else "-",
                      color=color, marker=marker, label=element)
            last = None
            for _, row in r.iterrows():
                if row.ndof_total == last:  # an adaptive run that stopped at its budget: labelled once
                    continue
                last = row.ndof_total
                ax.annotate(f"{int(row.ndof_total):,}".replace(",", " "), (row[time_column], row[f"err_{quantity}"]),
                            textcoords="offset points", xytext=(4, 3 if k % 2 == 0 else -3), fontsize=6.5,
                            color=color, va="bottom" if k % 2 == 0 else "top")  # alternate sides: ends that meet
        nu = sub["nu"].iloc[0] if len(sub) else float("nan")
        ax.set_title(f"{scene} (Poisson ratio {nu:g})")
        ax.margins(x=0.1)  # room for the dof labels of the last point
        ax.set_xlabel(TIME_LABELS.get(time_column, f"{time_column} [s]"))
        ax.set_ylabel(f"relative $L^2$ error of {QUANTITY_LABELS[quantity]}")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
        plain_log_ticks(ax)
    handles = {}
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncols=min(len(handles), 6),
               fontsize=8, title="element (point labels: dof; dashed: adaptive runs)", title_fontsize=8)
    what = "CPU time" if time_column == "time_cpu" else "run time"
    fig.suptitle(title or f"error against {what}: {QUANTITY_LABELS[quantity]}")
    return _finish(fig, path)


def plot_sigma_nu_isolines(solutions, path=None, levels: int = 24, title: str | None = None):
    """Isolines of sigma_nu (the paper's Figures 7-8): one panel per solution, a shared colour scale.

    sigma_nu = (sigma n).n with n the first crack's normal, averaged at the vertices;
    the crack is drawn in black.
    """
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.tri import Triangulation

    solutions = list(solutions)
    data = [sigma_nu_field(s) for s in solutions]
    poly = np.asarray(solutions[0].scene.polygon)
    aspect = np.ptp(poly[:, 1]) / max(np.ptp(poly[:, 0]), 1e-300)
    fig, axes = _figure(path, nrows=len(solutions), ncols=1, squeeze=False, constrained_layout=True,
                        figsize=(10, 0.5 + len(solutions) * (8.2 * aspect + 0.75)))
    # the colour scale covers the 1st to 99th percentiles: the clamped corners' singular
    # stresses saturate (shown in the extension colours) instead of washing out the rest
    lo = min(float(np.percentile(d[2], 1.0)) for d in data)
    hi = max(float(np.percentile(d[2], 99.0)) for d in data)
    lo, hi = min(lo, -1e-12), max(hi, 1e-12)
    bounds = np.linspace(lo, hi, levels + 1)
    norm = TwoSlopeNorm(vmin=lo, vcenter=0.0, vmax=hi)
    cf = None
    for ax, sol, (verts, tris, snn, _nu) in zip(axes[:, 0], solutions, data):
        tri = Triangulation(verts[:, 0], verts[:, 1], tris)
        cf = ax.tricontourf(tri, snn, levels=bounds, cmap="RdBu_r", norm=norm, extend="both")
        ax.tricontour(tri, snn, levels=bounds, colors="k", linewidths=0.25)
        for pts in sol.crack_mesh.polylines:
            ax.plot(pts[:, 0], pts[:, 1], "-", color="k", lw=2.0)
        ax.set_aspect("equal")
        ax.set_title(f"{sol.element}: {sol.ndof['total']:,} dof, maxh {sol.maxh:g}".replace(",", " "), fontsize=10)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
    from matplotlib.ticker import MaxNLocator

    cb = fig.colorbar(cf, ax=axes[:, 0].tolist(), label=r"$\sigma_\nu = (\sigma\nu)\cdot\nu$ (unit of E)",
                      shrink=0.95)
    ticks = MaxNLocator(9).tick_values(lo, hi)
    cb.set_ticks(ticks[(ticks >= lo) & (ticks <= hi)])
    sc = solutions[0].scene
    nu = data[0][3]
    fig.suptitle(title or rf"isolines of $\sigma_\nu$, $\nu$ = ({nu[0] + 0.0:.0f}, {nu[1] + 0.0:.0f}): {sc.name}, "
                 rf"Poisson ratio {sc.material.nu:g}")
    return _finish(fig, path)


def plot_paper_comparison(df, paper_points: dict, path=None, title: str | None = None):
    """The paper's Tables 1-4 and ngcrack on a common footing: one panel per quantity.

    df: `study.comparison_errors` rows (several elements). Abscissa: triangles. Per
    element: the true L2 error against a fine reference (solid, filled markers) and the
    error measured the paper's way, element means against the next finer mesh (dashed,
    open markers); rows the element warned about are circled in red. paper_points:
    {quantity: (triangles, err)}, the paper's tables converted (grey crosses).
    """
    from ..studies.sweeps import QUANTITIES, QUANTITY_LABELS

    fig, axes = _figure(path, nrows=2, ncols=2, figsize=(11, 8.5), constrained_layout=True)
    for ax, q in zip(axes.ravel(), QUANTITIES):
        for k, (element, g) in enumerate(_by_element(df)):
            color, marker = _element_style(element, k)
            g = g.sort_values("triangles")
            for kind, ls, mfc, what in (("true", "-", color, "true L2 error vs fine reference"),
                                        ("next", "--", "white", "the paper's way: means vs next finer mesh")):
                y = g[f"{kind}_{q}"].to_numpy(float)
                ok = np.isfinite(y) & (y > 0)
                ax.loglog(g["triangles"].to_numpy(float)[ok], y[ok], ls, color=color, marker=marker, mfc=mfc, ms=5,
                          label=f"{element}: {what}")
            warned = g[g["coarse"].astype(bool)]
            if len(warned):
                ax.loglog(warned["triangles"], warned[f"true_{q}"], "o", ms=11, mfc="none", mec="tab:red", mew=0.8,
                          label=f"{element}: mesh too coarse for it (warned)" if q == QUANTITIES[0] else None)
        px, py = paper_points[q]
        ax.loglog(px, py, ":", color="0.3", marker="x", ms=7, label="paper, Tables 1-4 (dof converted to triangles)")
        ax.set_title(f"{QUANTITY_LABELS[q]} (Table {1 + QUANTITIES.index(q)})")
        ax.set_xlabel(r"triangles $T$")
        ax.set_ylabel(r"relative $L^2(\Omega)$ error")
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
        plain_log_ticks(ax)
        if {"triangles", "h"} <= set(df.columns):
            _h_axis(ax, df["triangles"].to_numpy(float), df["h"].to_numpy(float))
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=7.5)
    fig.suptitle(title or "paper-1 (Poisson ratio 0.29): the paper's tables beside ngcrack, on triangles; "
                          "errors measured both ways")
    return _finish(fig, path)
