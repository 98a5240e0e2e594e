"""Mechanism kernels over all element families: the constraint system and its tensors,
the transfer function by Newton on the constraints, the LU they use, assembly of the
per-sample matrices, their omega-polynomial split, outputs and the non-linear equations
of motion."""
