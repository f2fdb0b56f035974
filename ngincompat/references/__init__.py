"""Independent solutions used as checks: the radial boundary-value problem, the bilayer
bifurcation."""
