"""The scene's mesh made on rank 0 and distributed; each rank's subdomain as a CrackMesh.

Rank 0 meshes with the serial pipeline (`Pipeline.mesh`, the same mesh a serial solve
gets) and hands a copy to netgen's `Distribute`; the other ranks `Receive` their
subdomain. On every rank the crack edges are found again on the local mesh from the
crack's boundary labels (`geometry._crack_edges`), the tips by their coordinates, so
that the element builders run on a subdomain as on a whole mesh.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..planar.geometry import CrackMesh, _crack_edges

#: two vertices closer than this fraction of the body's diameter are the same point
MATCH_RTOL = 1e-9


#: the fewest triangles per worker rank a distributed solve accepts
MIN_ELEMENTS_PER_RANK = 50


class TooFewElements(ValueError):
    """The scene's mesh has fewer elements than the ranks that should share it."""


def check_ranks(ne: int, size: int) -> None:
    """Refuse a mesh of `ne` triangles for `size` ranks (rank 0 holds none) with one line."""
    if ne < MIN_ELEMENTS_PER_RANK * (size - 1):
        raise TooFewElements(f"mpiexec -n {size}: the mesh has {ne} triangles, fewer than {MIN_ELEMENTS_PER_RANK} per "
                             f"worker rank ({size - 1} workers); use fewer ranks or a finer mesh (maxh, tip_h)")


def distribute(serial: CrackMesh | None, scene, comm) -> CrackMesh:
    """The local part of `serial` (given on rank 0, None elsewhere) on every rank of `comm`."""
    import netgen.meshing as nm

    rank, size = comm.rank, comm.size
    if rank == 0:
        ne = serial.mesh.ne
        tips = np.array([serial.points[v] for v in sorted(serial.tip_vertices)]).reshape(-1, 2)
        ok = ne >= MIN_ELEMENTS_PER_RANK * (size - 1)
        meta = dict(maxh=serial.maxh, tip_h=serial.tip_h, crack_h=serial.crack_h, grading=serial.grading,
                    quality=serial.quality)
        comm.bcast((ok, ne, tips, meta), root=0)
        check_ranks(ne, size)
        ngmesh = serial.mesh.ngmesh.Copy()
        mesh = ngs.Mesh(ngmesh.Distribute(comm))
    else:
        ok, ne, tips, meta = comm.bcast(None, root=0)
        if not ok:  # rank 0 reports it
            raise SystemExit(2)
        mesh = ngs.Mesh(nm.Mesh.Receive(comm))
    return local_crack_mesh(mesh, scene, meta, tips)


def local_crack_mesh(mesh: ngs.Mesh, scene, meta: dict, tips: np.ndarray) -> CrackMesh:
    """A CrackMesh of this rank's subdomain `mesh` (empty on rank 0)."""
    points = np.array([v.point for v in mesh.vertices], dtype=float).reshape(-1, 2)
    triangles = np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.VOL)], dtype=int).reshape(-1, 3)
    cracks = tuple(_crack_edges(mesh, scene, k, points) for k in range(len(scene.cracks)))
    tol = MATCH_RTOL * scene.diameter
    tip_vertices = frozenset(int(i) for t in tips for i in np.flatnonzero(np.linalg.norm(points - t, axis=1) <= tol))
    return CrackMesh(
        mesh=mesh, points=points, triangles=triangles, cracks=cracks, tip_vertices=tip_vertices,
        polylines=tuple(np.asarray(c.points, float) for c in scene.cracks), diameter=scene.diameter, **meta)
