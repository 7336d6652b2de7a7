"""Three-dimensional bodies with planar cracks in unilateral contact.

scene (SolidScene, TOML) -> geometry (OCC mesh, the crack a glued interior face set)
-> element (hybridized TDNNS with the crack's jumps) -> the condensed system
(ngcrack.hybrid) -> contact (a sparse primal-dual active set, dimension-free) ->
front (K_I, K_II, K_III and G along every front) -> output (JSON, VTK).
"""
