"""The sparse active set against the number of constrained unknowns (no mesh, no dense Schur complement).

`ngcrack.core.sparse_contact.solve_contact` sees a sparse SPD matrix, a load and the indices
of the constrained unknowns. Here: the 7-point Laplacian of an N x N x NZ grid (a
stand-in for a condensed 3D system; n = N^2 NZ unknowns), the constrained unknowns its
middle plane (m = N^2) held at x >= 0 under a load that pushes half of the plane down
(a checkerboard of smooth bumps), so that about half the points close. Per size: n, m,
active-set steps, CPU seconds of the contact solve, peak resident memory, the KKT
residuals, and the memory a dense m x m Schur complement would take (8 m^2 bytes), which
the method never forms. Each size runs in its own process (its own peak memory).

    python benchmarks/sparse_contact.py                  # N = 32, 64, 128, NZ = 16
    python benchmarks/sparse_contact.py --n 32 64 128 224
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time


def run(N: int, NZ: int) -> dict:
    import numpy as np
    import scipy.sparse as sp

    from ngcrack.core.sparse_contact import solve_contact

    def lap(k):
        return sp.diags([-np.ones(k - 1), 2.0 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1])

    I, Iz = sp.identity(N), sp.identity(NZ)
    K = (sp.kron(sp.kron(lap(N), I), Iz) + sp.kron(sp.kron(I, lap(N)), Iz) + sp.kron(sp.kron(I, I), lap(NZ))
         + 1e-3 * sp.identity(N * N * NZ)).tocsr()
    x, y = np.meshgrid(np.linspace(0, 1, N), np.linspace(0, 1, N), indexing="ij")
    plane = (np.arange(N)[:, None] * N + np.arange(N)[None, :]) * NZ + NZ // 2
    F = np.zeros(K.shape[0])
    F[plane.ravel()] = (np.sin(3 * np.pi * x) * np.sin(3 * np.pi * y)).ravel() / N
    t = time.process_time()
    res = solve_contact(K, F, plane.ravel())
    cpu = time.process_time() - t
    m = plane.size
    return {"N": N, "NZ": NZ, "n": K.shape[0], "m": m, "steps": res.iterations, "closed": int(res.active.sum()),
            "cpu_s": cpu, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "dense_schur_mb": 8.0 * m * m / 2**20, "kkt": res.kkt}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", nargs="+", type=int, default=[32, 64, 128])
    p.add_argument("--nz", type=int, default=16)
    p.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.one:
        print(json.dumps(run(args.one, args.nz)))
        return 0
    print(f"machine: {os.cpu_count()} cores; load {os.getloadavg()}; OMP_NUM_THREADS=1")
    print(f"{'n':>9} {'m':>7} {'steps':>5} {'closed':>7} {'CPU s':>7} {'peak MB':>8} {'dense S MB':>10} {'KKT max':>8}")
    for N in args.n:
        env = dict(os.environ, OMP_NUM_THREADS="1")
        out = subprocess.run([sys.executable, __file__, "--one", str(N), "--nz", str(args.nz)], capture_output=True,
                             text=True, env=env, check=False)
        if out.returncode:
            print(f"N = {N}: failed: {out.stderr.strip().splitlines()[-1:]}")
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{r['n']:>9} {r['m']:>7} {r['steps']:>5} {r['closed']:>7} {r['cpu_s']:>7.1f} {r['peak_mb']:>8.0f} "
              f"{r['dense_schur_mb']:>10.0f} {max(r['kkt'].values()):>8.1e}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
