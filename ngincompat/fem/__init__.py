"""Discretisation and solution: problems as energies, Newton solvers, stages, buckling, contact,
transport, measures of a solution."""
