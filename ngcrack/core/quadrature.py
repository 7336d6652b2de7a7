"""The quadrature orders the fracture parameters share, one constant per purpose for both bodies.

The domain (interaction) integral around a 2D tip and along a 3D front integrates the
element's fields (polynomials of degree at most 2) against the Williams fields, which are
smooth where grad q does not vanish: degrees 4, 6 and 8 agree to 1e-7 on the 2D tips. Its
crack-face terms (a pressure or a friction traction against the auxiliary displacement) have
an integrable r^(-1/2) at the front, so they take a higher degree.
"""

#: the degree of the triangle (2D) or tetrahedron (3D) rule of the domain integral
DOMAIN_INTEGRAL_ORDER = 6
#: the degree of the triangle rule on the crack faces of the domain integral's face terms (3D)
FACE_TERM_ORDER = 8
