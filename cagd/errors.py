"""The project's exception type."""


class CagdError(ValueError):
    """Invalid input to a cagd constructor or operation.

    The message names the offending argument and the problem, e.g.
    ``"knots: must be non-decreasing (knots[3]=0.2 < knots[2]=0.5)"``.
    """
