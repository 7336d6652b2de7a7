"""The distributed solution's condensed unknowns gathered on rank 0, matched to the serial mesh.

Every rank sends, per mesh edge and per vertex of its subdomain, the node's position
(edge mid point, vertex) and the values of its unknowns (the same compound space on the
same node has the same dofs in the same order: netgen keeps the global vertex order on
every rank, so edges keep their orientation), with the active flags of the crack
unknowns. Rank 0 matches positions with a k-d tree.
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np


@dataclass
class Gathered:
    """Per node kind ("edge", "vertex"): positions (n, 2), dof counts (n), values and active flags (concatenated)."""

    nodes: dict


def _local(mesh: ngs.Mesh, fes: ngs.FESpace, x: np.ndarray, active_dof: np.ndarray) -> dict:
    out = {}
    for kind, items, ntype in (("edge", mesh.edges, ngs.EDGE), ("vertex", mesh.vertices, ngs.VERTEX)):
        pos, counts, vals, flags = [], [], [], []
        for item in items:
            dofs = [d for d in fes.GetDofNrs(ngs.NodeId(ntype, item.nr)) if d >= 0]
            if not dofs:
                continue
            if ntype == ngs.EDGE:
                p = np.mean([mesh[v].point for v in item.vertices], axis=0)
            else:
                p = np.asarray(item.point)
            pos.append(p[:2])
            counts.append(len(dofs))
            vals.extend(x[dofs])
            flags.extend(active_dof[dofs])
        out[kind] = (np.asarray(pos, float).reshape(-1, 2), np.asarray(counts, int), np.asarray(vals, float),
                     np.asarray(flags, bool))
    return out


def gather_to_rank0(comm, cmesh, fes: ngs.FESpace, x, active: np.ndarray, jn_dofs: np.ndarray):
    """Gathered on rank 0 (None on the others). `x` a cumulated vector or the values per dof (numpy); `active`
    per crack unknown of this rank."""
    active_dof = np.zeros(fes.ndof, dtype=bool)
    active_dof[jn_dofs] = active
    values = x if isinstance(x, np.ndarray) else x.FV().NumPy()
    parts = comm.gather(_local(cmesh.mesh, fes, values, active_dof), root=0)
    if comm.rank != 0:
        return None
    nodes = {}
    for kind in ("edge", "vertex"):
        chunks = [p[kind] for p in parts]
        nodes[kind] = tuple(np.concatenate([c[i] for c in chunks]) for i in range(4))
    return Gathered(nodes=nodes)


def scatter_into(gathered: Gathered, mesh: ngs.Mesh, fes: ngs.FESpace, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The serial vector (zero where nothing was sent) and active flags per serial dof."""
    from scipy.spatial import cKDTree

    full = np.zeros(fes.ndof)
    flags = np.zeros(fes.ndof, dtype=bool)
    for kind, items, ntype in (("edge", mesh.edges, ngs.EDGE), ("vertex", mesh.vertices, ngs.VERTEX)):
        pos, counts, vals, act = gathered.nodes[kind]
        if not len(pos):
            continue
        serial_pos, serial_dofs = [], []
        for item in items:
            dofs = [d for d in fes.GetDofNrs(ngs.NodeId(ntype, item.nr)) if d >= 0]
            if not dofs:
                continue
            p = np.mean([mesh[v].point for v in item.vertices], axis=0) if ntype == ngs.EDGE else np.asarray(item.point)
            serial_pos.append(p[:2])
            serial_dofs.append(dofs)
        dist, idx = cKDTree(np.asarray(serial_pos)).query(pos)
        if np.any(dist > tol):
            raise RuntimeError(f"gather: {int(np.sum(dist > tol))} {kind}s of the subdomains match no {kind} of the mesh")
        starts = np.concatenate([[0], np.cumsum(counts)])
        for k, i in enumerate(idx):
            dofs = serial_dofs[i]
            if len(dofs) != counts[k]:
                raise RuntimeError(f"gather: a {kind} has {counts[k]} unknowns on its subdomain, {len(dofs)} in the mesh")
            full[dofs] = vals[starts[k]:starts[k + 1]]
            flags[dofs] |= act[starts[k]:starts[k + 1]]
    return full, flags


def serial_node_values(mesh: ngs.Mesh, fes: ngs.FESpace, values: np.ndarray) -> Gathered:
    """Rank 0: the serial vector `values` per node (positions, dof counts, values), to be sent to every rank and read
    with `local_values`."""
    return Gathered(nodes=_local(mesh, fes, values, np.zeros(fes.ndof, dtype=bool)))


def local_values(serial: Gathered, mesh: ngs.Mesh, fes: ngs.FESpace, tol: float) -> np.ndarray:
    """This rank's vector of the serial values `serial` (`serial_node_values`), matched by node positions."""
    from scipy.spatial import cKDTree

    out = np.zeros(fes.ndof)
    for kind, (pos, counts, vals, _) in serial.nodes.items():
        mine = _local(mesh, fes, np.zeros(fes.ndof), np.zeros(fes.ndof, dtype=bool))[kind][0]
        if not len(pos) or not len(mine):
            continue
        items, ntype = (mesh.edges, ngs.EDGE) if kind == "edge" else (mesh.vertices, ngs.VERTEX)
        node_dofs = [d for d in ([d for d in fes.GetDofNrs(ngs.NodeId(ntype, item.nr)) if d >= 0] for item in items)
                     if d]
        dist, idx = cKDTree(pos).query(mine)
        if np.any(dist > tol):
            raise RuntimeError(f"scatter: {int(np.sum(dist > tol))} {kind}s of this subdomain match no {kind} of the mesh")
        starts = np.concatenate([[0], np.cumsum(counts)])
        for dofs, i in zip(node_dofs, idx):
            if len(dofs) != counts[i]:
                raise RuntimeError(f"scatter: a {kind} has {len(dofs)} unknowns on its subdomain, {counts[i]} in the mesh")
            out[dofs] = vals[starts[i]:starts[i + 1]]
    return out
