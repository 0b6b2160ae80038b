"""Closed-form small-deflection formulas (paper Sections II-III) as NumPy ufuncs."""
