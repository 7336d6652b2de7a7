"""Planar checks of a scene's polylines: simple, inside the body, apart from each other.

A polygon must be simple, a crack must not touch itself, lie inside the body (its end
points may lie on the boundary) and keep clear of every other crack; no part of the body
may be thinner than the mesher can resolve. Each check refuses with a :class:`SceneError`
naming the field, the segments and the points involved. The distances are GEOS's
formulas on numpy (`measures`: shapely's numbers bit for bit). A small scene (up to
BRUTE_FORCE_PAIRS pairs of segments or points) compares every pair on numpy and does
not import shapely; a larger one searches through shapely's
spatial index (an STRtree), so the checks cost about O(n log n) in the number of
vertices, not O(n^2).

Tolerances: ``tol`` (``GEOMETRY_RTOL * diameter``) decides "the same point", "on the
boundary", "touches"; the gap check uses the coarser ``MIN_GAP_RTOL * diameter``.
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Sequence

import numpy as np

from ...core.fields import SceneError, fmt, fmt_pt
from .measures import Point, dist, in_region, point_segment_distance, point_segment_distances, segment_distances

#: Narrowest gap of the body, relative to its diameter, that is accepted: two boundary
#: or crack pieces closer than ``MIN_GAP_RTOL * diameter`` (a needle spike, a crack
#: hugging an edge, two cracks nearly touching) are refused. Measured with netgen on
#: the default mesh sizes: a spike 5e-4 wide meshes, one 2e-4 wide fails and one 1e-5
#: wide hangs; a crack 1e-5 above an edge fails, 1e-6 hangs; two collinear cracks 1e-4
#: apart fail, 1e-7 apart are merged into one (two tips vanish).
MIN_GAP_RTOL = 1e-3
#: A gap counts as thin only where the way round along the walls between its two sides
#: is longer than ``GAP_PATH_FACTOR`` times its width: so a short edge, or a corner
#: sharper than ``asin(1 / GAP_PATH_FACTOR)`` (5.7 degrees) only near its vertex, is not one.
GAP_PATH_FACTOR = 10.0
#: up to this many pairs (of segments, or of points and segments) a search compares every
#: pair on numpy; above, it goes through shapely's STRtree
BRUTE_FORCE_PAIRS = 20_000
#: rows of a pairwise comparison at a time
_ROWS = 256


def _segments(pts: Sequence[Point], closed: bool) -> tuple[np.ndarray, np.ndarray]:
    P = np.asarray(pts, dtype=float).reshape(-1, 2)
    m = len(P) if closed else len(P) - 1
    return P[:m], P[(np.arange(m) + 1) % len(P)]


def _lines(A: np.ndarray, B: np.ndarray):
    import shapely

    return shapely.linestrings(np.stack([A, B], axis=1))


def _sorted_pairs(hits: np.ndarray) -> np.ndarray:
    if hits.size == 0:
        return np.zeros((0, 2), dtype=int)
    return hits[np.lexsort((hits[:, 1], hits[:, 0]))]


def pairs_within(first, A: np.ndarray, B: np.ndarray, distance: float) -> np.ndarray:
    """(k, 2) index pairs (i, j), sorted, of the items of `first` within ``distance`` of the
    segments A[j]-B[j]: `first` is a pair (C, D) of segment ends or an array of points."""
    segments = isinstance(first, tuple)
    n = len(first[0]) if segments else len(first)
    if n * len(A) > BRUTE_FORCE_PAIRS:  # shapely's spatial index
        import shapely

        geoms = _lines(*first) if segments else shapely.points(np.asarray(first, dtype=float).reshape(-1, 2))
        return _sorted_pairs(shapely.STRtree(_lines(A, B)).query(geoms, predicate="dwithin", distance=distance).T)
    out = []
    for i in range(0, n, _ROWS):
        if segments:
            d = segment_distances(first[0][i:i + _ROWS, None], first[1][i:i + _ROWS, None], A[None], B[None])
        else:
            d = point_segment_distances(np.asarray(first, dtype=float)[i:i + _ROWS, None], A[None], B[None])
        r, c = np.nonzero(d <= distance)
        out.append(np.stack([r + i, c], axis=1))
    return _sorted_pairs(np.concatenate(out) if out else np.zeros((0, 2), dtype=int))


def check_polyline_simple(pts: Sequence[Point], fld: str, tol: float, closed: bool,
                          what: str) -> None:
    """Refuse zero-length segments, back-tracking adjacent segments and any contact
    between non-adjacent segments."""
    n = len(pts)
    A, B = _segments(pts, closed)
    m = len(A)
    lengths = np.hypot(*(B - A).T)
    short = np.flatnonzero(lengths <= tol)
    if short.size:
        i = int(short[0])
        j = (i + 1) % n
        raise SceneError(
            f"{fld}: {what} {i} from point {i} {fmt_pt(pts[i])} to point {j} {fmt_pt(pts[j])} "
            f"has zero length; consecutive points must differ"
            + ("; do not repeat the first vertex at the end (the polygon closes "
               "itself)" if closed and j == 0 else ""))
    for i, j in pairs_within((A, B), A, B, tol):
        if j <= i:
            continue
        adjacent = j == i + 1 or (closed and i == 0 and j == m - 1)
        if adjacent:
            # shared point: p2 == q1 (or q2 == p1 when closing the loop); the two
            # segments may only meet there, so neither far end may touch the other
            far_a, far_b = (A[i], B[j]) if j == i + 1 else (B[i], A[j])
            bad = (point_segment_distance(far_a, A[j], B[j]) <= tol
                   or point_segment_distance(far_b, A[i], B[i]) <= tol)
        else:
            bad = True
        if bad:
            rule = ("the polygon must be simple" if closed
                    else "a crack must not cross or touch itself")
            raise SceneError(
                f"{fld}: {what}s {i} {fmt_pt(A[i])}-{fmt_pt(B[i])} and {j} "
                f"{fmt_pt(A[j])}-{fmt_pt(B[j])} cross, touch or overlap; {rule}")


class Walls:
    """The body's boundary loops, indexed: the outer polygon and any holes.

    ``loops`` is a list of ``(points, labels, field)``, the first the outer polygon
    (counter-clockwise), the others holes; ``field`` names the loop in messages
    (``domain.polygon``, ``hole[0]``). Holds every edge in an STRtree and the region
    (the outer polygon minus the holes) prepared for point-in-region tests.
    """

    def __init__(self, loops: Sequence[tuple[Sequence[Point], Sequence[str], str]]) -> None:
        self.loops = [(tuple(map(tuple, p)), tuple(lab), f) for p, lab, f in loops]
        A, B, owner = [], [], []
        for li, (pts, _, _) in enumerate(self.loops):
            a, b = _segments(pts, closed=True)
            A.append(a)
            B.append(b)
            owner += [(li, e) for e in range(len(a))]
        self.A, self.B = np.concatenate(A), np.concatenate(B)
        self.owner = owner
        self._tree = None

    def _small(self, k: int) -> bool:
        return k * len(self.A) <= BRUTE_FORCE_PAIRS

    @property
    def tree(self):
        """shapely's STRtree of the edges (made on first use: large scenes only)."""
        if self._tree is None:
            import shapely

            self._tree = shapely.STRtree(_lines(self.A, self.B))
        return self._tree

    def edge_name(self, k: int) -> str:
        li, e = self.owner[k]
        _, labels, fld = self.loops[li]
        return f"edge {e} {labels[e]!r} of {fld}"

    def _distances(self, P: np.ndarray) -> np.ndarray:
        return point_segment_distances(P[:, None], self.A[None], self.B[None])

    def distance(self, P: np.ndarray) -> np.ndarray:
        """Distance of each point (k, 2) to the nearest boundary edge."""
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        if self._small(len(P)):
            return self._distances(P).min(axis=1)
        import shapely

        _, d = self.tree.query_nearest(shapely.points(P), return_distance=True, all_matches=False)
        return d

    def nearest_edge(self, P: np.ndarray) -> np.ndarray:
        """Index (into the edges) of the boundary edge nearest to each point."""
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        if self._small(len(P)):
            return self._distances(P).argmin(axis=1)
        import shapely

        return self.tree.query_nearest(shapely.points(P), all_matches=False)[1]

    def inside(self, P: np.ndarray) -> np.ndarray:
        """True where a point lies strictly inside the region (not on its boundary)."""
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        if self._small(len(P)):
            return in_region(P, [pts for pts, _, _ in self.loops])
        import shapely

        outer, *holes = [pts for pts, _, _ in self.loops]
        return shapely.contains_xy(shapely.Polygon(outer, holes), P[:, 0], P[:, 1])


def check_crack_in_domain(walls: Walls, pts: Sequence[Point], fld: str, tol: float) -> None:
    """Refuse a crack that leaves the body, runs along or crosses an edge, or touches
    the boundary anywhere but at its first or last point."""
    P = np.asarray(pts, dtype=float)
    last = len(P) - 1
    d = walls.distance(P)
    on = d <= tol
    ins = walls.inside(P)
    where_body = walls.loops[0][2] if len(walls.loops) == 1 else "the body"
    body = "the polygon" if len(walls.loops) == 1 else "the body (outside every hole)"
    for k in np.flatnonzero((~on & ~ins) | (on & (np.arange(len(P)) > 0) & (np.arange(len(P)) < last))):
        p = pts[k]
        if not on[k]:
            raise SceneError(
                f"{fld}.points[{k}] = {fmt_pt(p)} lies outside {where_body}; every "
                f"crack point must lie inside {body} (end points may lie on its "
                f"boundary)")
        raise SceneError(
            f"{fld}.points[{k}] = {fmt_pt(p)} lies on the boundary of {where_body}; "
            f"only a crack's first and last points may lie on the boundary, interior "
            f"points must lie strictly inside")
    ends_on = [P[k] for k in (0, last) if on[k]]
    A, B = _segments(pts, closed=False)
    M = 0.5 * (A + B)
    bad_mid = (walls.distance(M) <= tol) | ~walls.inside(M)
    pairs = pairs_within((A, B), walls.A, walls.B, tol)
    rule = (f"a crack must lie inside {body} and may touch its boundary only at its "
            "first or last point")
    for s in sorted(set(pairs[:, 0].tolist()) | set(np.flatnonzero(bad_mid).tolist())):
        a, b = A[s], B[s]
        where = f"{fld}.points: segment {s} from {fmt_pt(a)} to {fmt_pt(b)}"
        for e in pairs[pairs[:, 0] == s, 1]:
            c, dd = walls.A[e], walls.B[e]
            edge = walls.edge_name(e)
            contacts = [x for x in (a, b) if point_segment_distance(x, c, dd) <= tol]
            contacts += [x for x in (c, dd) if point_segment_distance(x, a, b) <= tol]
            if not contacts:
                raise SceneError(f"{where} crosses {edge}; {rule}")
            if max(dist(x, y) for x in contacts for y in contacts) > tol:
                raise SceneError(f"{where} runs along {edge}; {rule}")
            x = contacts[0]
            if not any(dist(x, y) <= tol for y in ends_on):
                raise SceneError(f"{where} touches {edge} at {fmt_pt(x)}; {rule}")
        if bad_mid[s]:
            raise SceneError(f"{where} leaves the domain (its midpoint "
                             f"{fmt_pt(M[s])} is not inside {where_body}); {rule}")


def check_cracks_disjoint(cracks: Sequence[Sequence[Point]], tol: float) -> None:
    """Refuse two cracks that cross or touch (the later one is named)."""
    if len(cracks) < 2:
        return
    segs = [_segments(c, closed=False) for c in cracks]
    owner = np.concatenate([np.full(len(a), i) for i, (a, _) in enumerate(segs)])
    local = np.concatenate([np.arange(len(a)) for a, _ in segs])
    A = np.concatenate([a for a, _ in segs])
    B = np.concatenate([b for _, b in segs])
    pairs = pairs_within((A, B), A, B, tol)
    pairs = pairs[owner[pairs[:, 0]] > owner[pairs[:, 1]]]
    if not len(pairs):
        return
    key = np.lexsort((local[pairs[:, 1]], local[pairs[:, 0]], owner[pairs[:, 1]], owner[pairs[:, 0]]))
    u, v = pairs[key[0]]
    i, s, j, r = owner[u], local[u], owner[v], local[v]
    raise SceneError(
        f"crack[{i}].points: segment {s} {fmt_pt(A[u])}-{fmt_pt(B[u])} crosses or touches "
        f"crack[{j}] (segment {r}); cracks must be disjoint (join them into one polyline "
        f"or move them apart)")


# --------------------------------------------------------------------------------------
# gaps thinner than the mesher resolves
# --------------------------------------------------------------------------------------


def check_gaps(walls: Walls, cracks: Sequence[Sequence[Point]], diameter: float, tol: float) -> None:
    """Refuse a part of the body narrower than ``MIN_GAP_RTOL * diameter``.

    The walls are the boundary loops and the cracks, joined where a crack end lies on
    the boundary. The narrowest gap between two walls is attained at a vertex of one of
    them, so every vertex is measured against every wall segment near it (an STRtree
    query); a short distance counts as a gap when the way round along the walls from the
    vertex to the nearest point is more than ``GAP_PATH_FACTOR`` times longer.
    """
    g = MIN_GAP_RTOL * diameter
    # the graph of walls: nodes (points), edges (segments) with an owner for messages
    nodes: list[Point] = []
    names: list[str] = []
    node_field: list[str] = []
    loop_nodes: list[list[int]] = []
    for pts, _, fld in walls.loops:
        loop_nodes.append(list(range(len(nodes), len(nodes) + len(pts))))
        nodes += [tuple(map(float, p)) for p in pts]
        names += [f"vertex {k} {fmt_pt(p)} of {fld}" for k, p in enumerate(pts)]
        node_field += [fld] * len(pts)
    crack_nodes: list[list[int]] = []
    inserted: dict[int, list[tuple[float, int]]] = {}  # wall edge -> (parameter, node)
    for i, pts in enumerate(cracks):
        ids = []
        for k, p in enumerate(pts):
            p = tuple(map(float, p))
            nid = None
            if k in (0, len(pts) - 1) and walls.distance(np.array([p]))[0] <= tol:
                e = int(walls.nearest_edge(np.array([p]))[0])
                li, ei = walls.owner[e]
                ln = loop_nodes[li]
                for q in (ln[ei], ln[(ei + 1) % len(ln)]):
                    if dist(p, nodes[q]) <= tol:
                        nid = q
                if nid is None:
                    nid = len(nodes)
                    a, b = walls.A[e], walls.B[e]
                    t = float(np.dot(np.subtract(p, a), b - a) / np.dot(b - a, b - a))
                    inserted.setdefault(e, []).append((t, nid))
            if nid is None:
                nid = len(nodes)
            if nid == len(nodes):
                nodes.append(p)
                names.append(f"crack[{i}].points[{k}] {fmt_pt(p)}")
                node_field.append(f"crack[{i}]")
            ids.append(nid)
        crack_nodes.append(ids)
    segs: list[tuple[int, int, str, str]] = []  # (node, node, name, field)
    chains: list[tuple[list[int], bool]] = []  # node sequences along each wall, closed or not
    seg_chain: list[int] = []
    for li in range(len(walls.loops)):
        seq: list[int] = []
        for e in (e for e, (lj, _) in enumerate(walls.owner) if lj == li):
            ei = walls.owner[e][1]
            ln = loop_nodes[li]
            chain = [ln[ei]] + [nid for _, nid in sorted(inserted.get(e, []))] + [ln[(ei + 1) % len(ln)]]
            segs += [(a, b, walls.edge_name(e), walls.loops[li][2]) for a, b in itertools.pairwise(chain)]
            seq += chain[:-1]
        seg_chain += [len(chains)] * len(seq)
        chains.append((seq, True))
    for i, ids in enumerate(crack_nodes):
        segs += [(a, b, f"segment {s} of crack[{i}]", f"crack[{i}]")
                 for s, (a, b) in enumerate(itertools.pairwise(ids))]
        seg_chain += [len(chains)] * (len(ids) - 1)
        chains.append((ids, False))
    X = np.asarray(nodes, dtype=float)
    SA, SB = np.array([s[0] for s in segs]), np.array([s[1] for s in segs])
    seg_len = np.hypot(*(X[SB] - X[SA]).T)
    # arc length of every node along each chain it belongs to, and each chain's length
    pos: dict[tuple[int, int], float] = {}
    seg_s0 = np.zeros(len(segs))
    perimeter = []
    k = 0
    for c, (seq, closed) in enumerate(chains):
        m = len(seq) if closed else len(seq) - 1
        s_nodes = np.concatenate([[0.0], np.cumsum(seg_len[k:k + m])])
        for j, nid in enumerate(seq):
            pos.setdefault((nid, c), float(s_nodes[j]))
        seg_s0[k:k + m] = s_nodes[:m]
        perimeter.append(float(s_nodes[-1]) if closed else np.inf)
        k += m
    adjacency: list[list[tuple[int, float]]] = [[] for _ in nodes]
    for (a, b, _, _), L in zip(segs, seg_len):
        adjacency[a].append((b, float(L)))
        adjacency[b].append((a, float(L)))
    hits = pairs_within(X, X[SA], X[SB], g)
    hits = hits[(SA[hits[:, 1]] != hits[:, 0]) & (SB[hits[:, 1]] != hits[:, 0])]
    if not len(hits):
        return
    d = point_segment_distances(X[hits[:, 0]], X[SA[hits[:, 1]]], X[SB[hits[:, 1]]])
    loc = _locate(X[hits[:, 0]], X[SA[hits[:, 1]]], X[SB[hits[:, 1]]])
    # the way round along the one wall both sides belong to, where they do: short enough
    # there, the pair is a corner or a short edge, not a gap
    near = np.zeros(len(hits), dtype=bool)
    for k, (v, s) in enumerate(hits):
        c = seg_chain[s]
        sv = pos.get((int(v), c))
        if sv is not None:
            delta = abs(sv - (seg_s0[s] + loc[k]))
            delta = min(delta, perimeter[c] - delta)
            near[k] = delta <= GAP_PATH_FACTOR * max(d[k], tol)
    hits, d = hits[~near], d[~near]
    worst = None
    for k in np.argsort(d, kind="stable"):
        v, s = (int(x) for x in hits[k])
        width = float(d[k])
        if width >= g:
            break
        a, b = X[SA[s]], X[SB[s]]
        f = float(_locate(X[v], a, b)) / seg_len[s] if seg_len[s] > 0 else 0.0
        xp = (float(a[0] + f * (b[0] - a[0])), float(a[1] + f * (b[1] - a[1])))
        limit = GAP_PATH_FACTOR * max(width, tol)
        around = _path_length(adjacency, nodes, v, int(SA[s]), int(SB[s]), xp, limit)
        if around > limit:
            worst = (width, v, s, xp)
            break
    if worst is None:
        return
    width, v, s, xp = worst
    where = fmt_pt(((nodes[v][0] + xp[0]) / 2, (nodes[v][1] + xp[1]) / 2))
    f_node, f_seg = node_field[v], segs[s][3]
    cracks_only = f_node.startswith("crack[") and f_seg.startswith("crack[") and f_node != f_seg
    fld = f_node if f_node.startswith("crack[") else f_seg
    advice = ("the mesher would merge them (the tips between them would vanish); join them into "
              f"one polyline or move them at least {fmt(g)} apart" if cracks_only
              else f"netgen cannot mesh it (measured); widen it to at least {fmt(g)} or remove it")
    raise SceneError(
        f"{fld}: the body is only {fmt(width)} wide at {where}, between {names[v]} and {segs[s][2]}; "
        f"parts narrower than {MIN_GAP_RTOL:g} of the body's diameter ({fmt(g)}) are refused: {advice}")


def _locate(P, A, B) -> np.ndarray:
    """How far along each segment A-B (from A) the nearest point to P lies (GEOS's
    projection onto a segment, clamped to it)."""
    P, A, B = (np.asarray(v, dtype=float) for v in (P, A, B))
    D = B - A
    len2 = np.sum(D * D, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(len2 > 0, ((P[..., 0] - A[..., 0]) * D[..., 0] + (P[..., 1] - A[..., 1]) * D[..., 1]) / len2, 0.0)
    return np.clip(r, 0.0, 1.0) * np.sqrt(len2)


def _path_length(adjacency, nodes, start: int, a: int, b: int, x: Point, limit: float) -> float:
    """The shortest way along the walls from node ``start`` to the point ``x`` of the
    segment a-b, searched up to ``limit`` (inf beyond it)."""
    best = {start: 0.0}
    heap = [(0.0, start)]
    out = np.inf
    while heap:
        du, u = heapq.heappop(heap)
        if du > limit or du > out:
            break
        if du > best.get(u, np.inf):
            continue
        if u in (a, b):
            out = min(out, du + dist(nodes[u], x))
        for w, L in adjacency[u]:
            dw = du + L
            if dw < best.get(w, np.inf) and dw <= limit:
                best[w] = dw
                heapq.heappush(heap, (dw, w))
    return out
