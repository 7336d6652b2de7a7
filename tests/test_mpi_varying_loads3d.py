"""Loads varying in space under `mpiexec -n 2`: the distributed 3D solve against the serial one.

The bent penny of the distributed 3D tests (a clamped beam, a penny across it) with the end's
shear traction varying linearly over the end face (a table) and a crack-face pressure
p = 0.4 (y^2 + z^2) (a Python callable, built alike on every rank): the distributed solve
builds the same CoefficientFunctions as the serial one (`solid.loads.coefficients`), so K_I,
K_II, K_III along the front, the normal jumps and the error estimate equal the serial ones to
the Krylov tolerance (measured: K 1.1e-12, the estimate 1.1e-13), with a mixed active set.
"""

from __future__ import annotations

import json
import textwrap

import numpy as np
from test_mpi import _run, pytestmark  # noqa: F401  (the mpi4py skip)

COMPARE = textwrap.dedent('''
    import json, sys
    import numpy as np
    import ngcrack as nc
    from ngcrack.scenes.coarse3d import bent_penny
    from ngcrack.solid.scene import SolidScene
    from ngcrack.solid.solve import solve_solid
    d = bent_penny()
    d["boundary"]["xmax"]["value"] = {"axis": [0, 0, 1], "table": [[-2, 0, 0, -0.5], [2, 0, 0, -1.5]]}
    d["crack"][0]["pressure"] = lambda x, y, z: 0.4 * (y * y + z * z)
    d["mesh"] = {"maxh": 4.0, "crack_h": 0.7, "front_h": 0.5}
    scene = SolidScene.from_dict(d)
    sol = nc.solve(scene, order=1, estimate=True)  # under mpiexec: the distributed 3D solve (None on ranks > 0)
    if sol is not None:
        ser = solve_solid(scene, order=1, estimate=True)
        K = lambda s: np.array([[f.K_I, f.K_II, f.K_III] for f in s.fronts]).tolist()
        est = lambda s: {k: s.error_estimate[k] for k in ("total", "contact", "data")}
        out = dict(K=K(sol), K_serial=K(ser), jumps=sol.normal_jumps().tolist(), jumps_serial=ser.normal_jumps().tolist(),
                   active=sol.contact.active.tolist(), estimate=est(sol), estimate_serial=est(ser),
                   ranks=sol.distributed["ranks"], record=sol.to_json_dict())
        json.dump(out, open(sys.argv[1], "w"), allow_nan=False)
''')


def test_varying_traction_and_pressure_distributed_equal_serial(tmp_path):
    (tmp_path / "compare.py").write_text(COMPARE)
    proc = _run([str(tmp_path / "compare.py"), str(tmp_path / "out.json")], n=2)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads((tmp_path / "out.json").read_text())
    assert r["ranks"] == 2
    K, Ks = np.array(r["K"]), np.array(r["K_serial"])
    assert np.max(np.abs(K - Ks)) <= 1e-8 * np.max(np.abs(Ks))  # measured 1.1e-12
    w, ws = np.array(r["jumps"]), np.array(r["jumps_serial"])
    assert np.max(np.abs(w - ws)) <= 1e-8 * np.max(np.abs(ws))
    assert 0.2 < np.mean(r["active"]) < 0.8  # the bent beam closes part of the pressurized crack
    e, es = r["estimate"], r["estimate_serial"]
    assert abs(e["total"] - es["total"]) <= 1e-8 * es["total"]
    assert abs(e["data"] - es["data"]) <= 1e-8 * es["total"] and abs(e["contact"] - es["contact"]) <= 1e-8 * es["total"] ** 2
    assert r["record"]["cracks"][0]["pressure_force"] > 0
