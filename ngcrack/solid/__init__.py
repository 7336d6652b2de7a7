"""Three-dimensional bodies with planar cracks in unilateral contact.

A scene is 3D when its ``[domain]`` is a box or a cylinder; ``nc.solve`` and
``ngcrack solve`` send it here. The stages, each a module of this package, run one way:

``scene``     SolidScene: the body, its planar cracks (disc, ellipse, polygon), material,
              supports and mesh sizes, validated field by field before any meshing
``geometry``  the OCC mesh: each crack a glued set of interior faces with a tetrahedron
              on each side, its front an edge region, curved to second order
``element``   hybridized TDNNS of order 1-3 with the crack's normal jump (the contact
              unknown) and tangential jump (the front excluded)
``contact``   the sparse primal-dual active set on the condensed system (dimension-free:
              a sparse matrix, a load, the constrained unknowns), certified by the
              system's residual
``front``     K_I, K_II, K_III and G at points along every front (a domain interaction
              integral with a q-function per front point)
``output``    SolidSolution: fields, crack summaries, the JSON record, VTK files
``solve``     solve_solid: the stages in one call

The condensed system is the 2D code's (``ngcrack.core.hybrid.condense``), which sees only the
element's spaces and forms.
"""
