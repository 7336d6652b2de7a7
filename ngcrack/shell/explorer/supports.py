"""The supports and loads of the explorer's figure: load arrows on the loaded edges, hatching on
clamped edges, circles on rollers, placed where the drawn (deformed, magnified) body has its
edges (`mover`: the drawn displacement at the nearest triangle corner)."""

from __future__ import annotations

import numpy as np


def mover(corners: np.ndarray, shift: np.ndarray):
    """point(s) (n, 2) -> the drawn displacement `shift` at the nearest triangle corner: where
    a boundary marker goes on the drawn body."""
    pts, moved = corners.reshape(-1, 2), shift.reshape(-1, 2)

    def move(p):
        p = np.asarray(p, float).reshape(-1, 2)
        if not len(pts):
            return np.zeros_like(p)
        nearest = [int(np.argmin(np.sum((pts - q) ** 2, axis=1))) for q in p]
        return moved[nearest]

    return move


def draw_boundary(ax, scene, poly: np.ndarray, diam: float, load_ref: float, move=None,
                  fontsize: float = 9.5) -> tuple[list, list]:
    """Load arrows on the loaded edges, hatching on clamped edges, circles on rollers, each where
    the drawn body has its edge (`move`: point -> the drawn displacement there). Returns (the
    artists drawn, the points the panel must show: the arrows' ends)."""
    move = move or (lambda p: np.zeros_like(np.asarray(p, float)))
    drawn: list = []
    extent: list = []
    n = len(poly)
    labels = scene.labels or tuple(str(i) for i in range(n))
    arrow = 0.08 * diam
    centroid = poly.mean(axis=0)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        d = b - a
        L = float(np.hypot(*d))
        if L == 0:
            continue
        t = d / L
        out = np.array([t[1], -t[0]])
        if np.dot(out, 0.5 * (a + b) - centroid) < 0:
            out = -out
        bc = scene.boundary.get(labels[i]) if i < len(labels) else None
        if bc is None:
            continue
        if bc.type == "clamped":
            ends = np.vstack([a, b])
            drawn += ax.plot(*(ends + move(ends)).T, color="k", lw=2.2, zorder=5, solid_capstyle="butt")
            k = max(3, int(L / (0.04 * diam)))
            for s in np.linspace(0.0, 1.0, k):
                p = a + s * d
                p = p + move(p[None])[0]
                q = p + 0.025 * diam * (out + 0.7 * t)
                drawn += ax.plot([p[0], q[0]], [p[1], q[1]], color="k", lw=0.8, zorder=5)
        elif bc.type == "roller":
            k = max(3, int(L / (0.06 * diam)))
            s = np.linspace(0.5 / k, 1 - 0.5 / k, k)
            on = a[None] + s[:, None] * d[None]
            pts = on + move(on) + 0.015 * diam * out[None]
            drawn += ax.plot(pts[:, 0], pts[:, 1], "o", ms=3.5, mfc="white", mec="k", mew=0.8, zorder=5, ls="none")
        elif bc.type in ("traction", "displacement"):
            v = np.asarray(bc.value, float)
            mag = float(np.hypot(*v))
            if mag == 0 or not load_ref:
                continue
            length = min(2.0, mag / load_ref) * arrow
            e = v / mag
            color = "#b91c1c" if bc.type == "traction" else "#6d28d9"
            k = max(3, int(L / (0.12 * diam)))
            for s in np.linspace(0.5 / k, 1 - 0.5 / k, k):
                p = a + s * d
                p = p + move(p[None])[0]
                tail, head = (p - length * e, p) if np.dot(e, out) <= 0 else (p, p + length * e)
                extent += [tail, head]
                drawn.append(ax.annotate("", xy=head, xytext=tail, annotation_clip=False, zorder=6,
                                         arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1.2}))
    f = getattr(scene, "body_force", None)
    if f is not None and np.hypot(*f) > 0 and load_ref:
        f = np.asarray(f, float)
        e = f / np.hypot(*f)
        length = min(2.0, float(np.hypot(*f)) / load_ref) * arrow
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        at = lo + np.array([0.1, 0.75]) * (hi - lo)  # (the upper left, away from a central crack)
        drawn.append(ax.annotate("", xy=at + 0.5 * length * e, xytext=at - 0.5 * length * e, zorder=6,
                                 arrowprops={"arrowstyle": "-|>", "color": "0.2", "lw": 1.6}))
        drawn.append(ax.text(*(at - 0.5 * length * e), "f ", color="0.2", fontsize=fontsize,
                             ha="right", va="bottom", zorder=6))
    return drawn, extent
