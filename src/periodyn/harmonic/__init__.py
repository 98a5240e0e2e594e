"""The harmonic layer: block pattern and real basis (:mod:`.pattern`), and the Hill/HB
operator as polynomials in omega (:mod:`.operator`), which every harmonic-balance solve and
Hill eigen-solve of periodyn goes through."""

from .operator import (FORMS, AliasingWarning, HarmonicOperator, HillOperator, check_form, check_harmonics,
                       first_order_matrix)
from .pattern import BlockPattern, block_pattern, from_real_basis, real_form, to_real_basis

__all__ = ["AliasingWarning", "BlockPattern", "FORMS", "HarmonicOperator", "HillOperator", "block_pattern",
           "check_form", "check_harmonics", "first_order_matrix", "from_real_basis", "real_form", "to_real_basis"]
