"""A 3D scene's mesh over the ranks: rank 0's SolidMesh distributed, each subdomain's cracks
found again, the constraint map's blocks placed, the solution gathered back.

- `crack_layout` (rank 0): per crack, each crack face's centroid, its vertices in the
  mesh's vertex order, its block of the constraint map G (`solid.element.constraint_map`,
  computed on the serial mesh, where the crack's surface elements are) and the mid points
  of the crack's interior edges (the front's excluded);
- `distribute`: netgen's `Distribute` / `Receive`; every rank then sets the scene's OCC
  geometry on its subdomain and curves it (`Mesh.Curve`) as the serial mesh is curved (a
  received subdomain has no geometry: uncurved, the crack's area is 0.7% short);
- `local_solid_mesh`: the subdomain's crack faces, their tetrahedra on each side, and the
  interior crack edges, matched by coordinates. Netgen's partition kept each crack face's
  two tetrahedra on one rank on every mesh measured (2-6 ranks); a face split over two
  ranks is counted and refused by `distributed.solid`. Netgen keeps the vertices' order on
  every rank, so a face's unknowns come in the same order as on the serial mesh; checked
  per crack face (its vertices in order), refused otherwise;
- `gather_to_rank0` / `scatter_into`: the condensed unknowns, per mesh edge and face, sent
  with the node's position and matched to the serial mesh with a k-d tree on rank 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .mesh import MATCH_RTOL

#: the fewest tetrahedra per worker rank a distributed 3D solve accepts
MIN_TETS_PER_RANK = 500


class TooFewTetrahedra(ValueError):
    """The scene's 3D mesh has fewer tetrahedra than the ranks that should share it."""


def check_ranks(ne: int, size: int) -> None:
    """Refuse a mesh of `ne` tetrahedra for `size` ranks (rank 0 holds none) with one line."""
    if ne < MIN_TETS_PER_RANK * (size - 1):
        raise TooFewTetrahedra(
            f"mpiexec -n {size}: the 3D mesh has {ne} tetrahedra, fewer than {MIN_TETS_PER_RANK} per worker rank "
            f"({size - 1} workers); use fewer ranks or a finer mesh (maxh, crack_h, front_h)")


@dataclass
class CrackLayout:
    """One crack of the serial mesh, as every rank needs it (module docstring)."""

    centroids: np.ndarray  # (faces, 3)
    vertices: np.ndarray  # (faces, 3, 3): each face's vertices in the mesh's vertex order
    blocks: np.ndarray  # (faces, p, p): rows the face's constraint points, columns its jn unknowns
    edge_mids: np.ndarray  # (interior edges, 3)


def _face_vertices(mesh: ngs.Mesh, f: int) -> list[int]:
    return sorted(v.nr for v in mesh[ngs.NodeId(ngs.FACE, int(f))].vertices)


def crack_layout(smesh, order: int) -> list[CrackLayout]:
    """Rank 0: the layout of every crack of the serial SolidMesh `smesh` for the element of `order`."""
    from ..solid.element import _compress, constraint_map, lagrange_points

    mesh, pts = smesh.mesh, smesh.points
    facet = ngs.FacetFESpace(mesh, order=order)
    jn_space = _compress(facet, [ngs.NodeId(ngs.FACE, int(f)) for c in smesh.cracks for f in c.faces])
    G, _, _ = constraint_map(smesh, jn_space, facet, order)
    G = G.tocsr()
    per = len(lagrange_points(order))
    out, row = [], 0
    for c in smesh.cracks:
        cents, verts, blocks = [], [], []
        for f in c.faces:
            vs = _face_vertices(mesh, f)
            dofs = list(jn_space.GetDofNrs(ngs.NodeId(ngs.FACE, int(f))))
            blocks.append(G[row:row + per][:, dofs].toarray())
            row += per
            verts.append(pts[vs])
            cents.append(pts[vs].mean(axis=0))
        mids = [pts[[v.nr for v in mesh[ngs.NodeId(ngs.EDGE, int(e))].vertices]].mean(axis=0)
                for e in c.interior_edges]
        out.append(CrackLayout(np.array(cents), np.array(verts), np.array(blocks), np.array(mids).reshape(-1, 3)))
    return out


def distribute(smesh, scene, comm, sizes: dict, curve: int):
    """This rank's subdomain of rank 0's `smesh` (None on the others), curved; an ngs.Mesh on every rank."""
    import netgen.meshing as nm

    from ..solid.geometry import occ_geometry

    if comm.rank == 0:
        ngmesh = smesh.mesh.ngmesh.Copy().Distribute(comm)
    else:
        ngmesh = nm.Mesh.Receive(comm)
    ngmesh.SetGeometry(occ_geometry(scene, sizes))
    mesh = ngs.Mesh(ngmesh)
    if curve:
        mesh.Curve(curve)
    return mesh


def _points(mesh: ngs.Mesh) -> np.ndarray:
    return np.array([v.point for v in mesh.vertices], dtype=float).reshape(-1, 3)


def local_solid_mesh(mesh: ngs.Mesh, scene, layout: list[CrackLayout], sizes: dict):
    """(SolidMesh of this subdomain, per crack (local face numbers, their blocks of G))."""
    from scipy.spatial import cKDTree

    from ..solid.geometry import CrackFaces, SolidMesh

    pts = _points(mesh)
    tol = MATCH_RTOL * scene.size
    face_verts = np.array([sorted(v.nr for v in f.vertices) for f in mesh.faces], dtype=int).reshape(-1, 3)
    edge_verts = np.array([[v.nr for v in e.vertices] for e in mesh.edges], dtype=int).reshape(-1, 2)
    face_tree = cKDTree(pts[face_verts].mean(axis=1)) if len(face_verts) else None
    edge_tree = cKDTree(pts[edge_verts].mean(axis=1)) if len(edge_verts) else None
    cracks, placed = [], []
    for i, (crack, lay) in enumerate(zip(scene.cracks, layout)):
        faces, blocks, plus, minus, edges = np.zeros(0, int), np.zeros((0,) + lay.blocks.shape[1:]), [], [], []
        if face_tree is not None and len(lay.centroids):
            dist, idx = face_tree.query(lay.centroids)
            here = dist <= tol
            faces, blocks = idx[here], lay.blocks[here]
            if not np.allclose(pts[face_verts[faces]], lay.vertices[here], rtol=0.0, atol=tol):
                raise RuntimeError(f"crack[{i}]: a crack face's vertices come in another order on a subdomain than "
                                   "on the mesh (its unknowns would not match)")
            for f in faces:
                for el in mesh[ngs.NodeId(ngs.FACE, int(f))].elements:
                    opp = [v.nr for v in mesh[el].vertices if v.nr not in face_verts[f]]
                    side = np.dot(pts[opp[0]] - crack.center, crack.normal)
                    (plus if side > 0 else minus).append(el.nr)
        if edge_tree is not None and len(lay.edge_mids):
            dist, idx = edge_tree.query(lay.edge_mids)
            edges = np.sort(idx[dist <= tol])
        cracks.append(CrackFaces(i, crack, f"crack{i}", f"front{i}", np.zeros(0, int), np.asarray(faces, int),
                                 np.array(plus, int), np.array(minus, int), np.zeros(0, int), np.zeros(0, int),
                                 np.asarray(edges, int), 0.0))
        placed.append((np.asarray(faces, int), blocks))
    return SolidMesh(mesh, scene, cracks, sizes), placed


@dataclass
class Gathered:
    """Per node kind ("edge", "face"): positions (n, 3), dof counts (n), values and active flags (concatenated)."""

    nodes: dict


_KINDS = (("edge", ngs.EDGE), ("face", ngs.FACE))


def _node_items(mesh: ngs.Mesh, fes: ngs.FESpace, ntype):
    pts = _points(mesh)
    items = mesh.edges if ntype == ngs.EDGE else mesh.faces
    for item in items:
        dofs = [d for d in fes.GetDofNrs(ngs.NodeId(ntype, item.nr)) if d >= 0]
        if dofs:
            yield pts[[v.nr for v in item.vertices]].mean(axis=0), dofs


def gather_to_rank0(comm, mesh: ngs.Mesh, fes: ngs.FESpace, values: np.ndarray, flags: np.ndarray):
    """Gathered on rank 0 (None on the others): `values` (cumulated) and `flags` per dof of this rank."""
    local = {}
    for kind, ntype in _KINDS:
        pos, counts, vals, act = [], [], [], []
        for p, dofs in _node_items(mesh, fes, ntype):
            pos.append(p)
            counts.append(len(dofs))
            vals.extend(values[dofs])
            act.extend(flags[dofs])
        local[kind] = (np.asarray(pos, float).reshape(-1, 3), np.asarray(counts, int), np.asarray(vals, float),
                       np.asarray(act, bool))
    parts = comm.gather(local, root=0)
    if comm.rank != 0:
        return None
    return Gathered({kind: tuple(np.concatenate([p[kind][i] for p in parts]) for i in range(4)) for kind, _ in _KINDS})


def scatter_into(gathered: Gathered, mesh: ngs.Mesh, fes: ngs.FESpace, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The serial vector (zero where nothing was sent) and the active flags per serial dof."""
    from scipy.spatial import cKDTree

    full = np.zeros(fes.ndof)
    flags = np.zeros(fes.ndof, dtype=bool)
    for kind, ntype in _KINDS:
        pos, counts, vals, act = gathered.nodes[kind]
        if not len(pos):
            continue
        serial = list(_node_items(mesh, fes, ntype))
        dist, idx = cKDTree(np.array([p for p, _ in serial])).query(pos)
        if np.any(dist > tol):
            raise RuntimeError(f"gather: {int(np.sum(dist > tol))} {kind}s of the subdomains match no {kind} of the mesh")
        starts = np.concatenate([[0], np.cumsum(counts)])
        for k, i in enumerate(idx):
            dofs = serial[i][1]
            if len(dofs) != counts[k]:
                raise RuntimeError(f"gather: a {kind} has {counts[k]} unknowns on its subdomain, {len(dofs)} in the mesh")
            full[dofs] = vals[starts[k]:starts[k + 1]]
            flags[dofs] |= act[starts[k]:starts[k + 1]]
    return full, flags
