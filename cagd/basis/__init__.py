"""Basis functions: Bernstein polynomials and B-spline (Cox-de Boor) bases."""
from .bernstein import bernstein, bezier_matrix, elevation_matrix, power_to_bernstein, bernstein_to_power, \
    product_matrix
from .bspline import basis_functions, basis_derivatives, basis_matrix, cox_de_boor

__all__ = ["bernstein", "bezier_matrix", "elevation_matrix", "power_to_bernstein", "bernstein_to_power",
           "product_matrix", "basis_functions", "basis_derivatives", "basis_matrix", "cox_de_boor"]
