"""The dimension-free core: what every solve runs through, whatever the body.

The options (`options`), the staged pipeline and its one-shot use (`pipeline`, `solve`), the
condensed system and its Schur complement on the crack unknowns (`hybrid`, `schur`, `csr`), the
crack problem in those unknowns and its solvers (`contact`, `friction`, `constraints`: Signorini and
Coulomb, KKT residuals), the element family's protocol (`discretization`) and the answer
(`solution`). The bodies (`ngcrack.planar`, `ngcrack.solid`) supply the geometry, the meshes, the
element forms and the fracture parameters.
"""
