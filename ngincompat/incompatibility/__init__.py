"""Geometric incompatibility of a growth field: Curl Fg, G, Burgers vectors and the curvature of
Cg."""
