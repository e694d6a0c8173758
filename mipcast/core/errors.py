"""mipcast's own exception and warning classes (importable from :mod:`mipcast`).

Examples
--------
>>> issubclass(InputError, ValueError)
True
"""
from __future__ import annotations


class InputError(ValueError):
    """Input mipcast cannot draw; the message names the problem and the fix.

    A subclass of ``ValueError``, so ``except ValueError`` keeps working.
    Raised by the pyvista accessors, the command line and
    :func:`mipcast.core.validation.check_image` before anything renders; in a
    VTK pipeline a mapper reports the same message as a VTK error event and
    through ``GetLastProblem()``.

    Examples
    --------
    >>> try:
    ...     raise InputError("the volume is empty")
    ... except ValueError as error:
    ...     print(error)
    the volume is empty
    """


class InputWarning(UserWarning):
    """Input mipcast draws, with a caveat (e.g. +-Inf values drawn as missing); once per volume."""
