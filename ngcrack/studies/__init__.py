"""Studies and loops over solves: sweeps over sizes and materials, the paper's study, the stability
study, adaptivity, volume control, crack growth and hydraulic fracture, and the converged reference
answers of the built-in scenes.
"""
