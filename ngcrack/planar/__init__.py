"""The planar (2D) body: its scene, netgen meshes with cracks as interior edge chains, the element
families (PEERS, BDM, TDNNS and the displacement baselines), hp meshes at the tips, the crack
profiles, the fracture parameters at the tips (K_I, K_II, G, T), the error estimate, the size guard,
figures and ParaView files.
"""
