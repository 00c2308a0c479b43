"""cagd: classical computer-aided geometric design in numpy.

Curves: polynomial/Hermite/natural cubic splines, Bezier, B-spline and NURBS, each
with vectorized evaluation, derivatives of any order and an exact ``to_nurbs()``.
Invalid input raises :class:`CagdError` (a ValueError).
"""
from .errors import CagdError
from .curves.base import Curve
from .curves.bspline import BSplineCurve, OccForm
from .curves.bezier import BezierCurve

__version__ = "0.1.0"
__all__ = ["CagdError", "Curve", "BSplineCurve", "OccForm", "BezierCurve"]
