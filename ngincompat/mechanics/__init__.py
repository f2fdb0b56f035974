"""The paper's continuum mechanics: kinematics F = Fe Fg, growth tensors and laws, materials,
direction fields."""
