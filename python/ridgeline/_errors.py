"""The exceptions ridgeline raises, each carrying the library's message.

Every one derives from :class:`RidgelineError`; those about a bad value also derive from
:class:`ValueError`. A file that cannot be read raises the built-in :class:`OSError` subclass for
its errno (:class:`FileNotFoundError`, :class:`PermissionError`, ...), with ``filename`` set, and an
argument of the wrong type a :class:`TypeError`. The attributes survive pickling, so an error
raised in a Dask, Ray or Spark worker process arrives whole.
"""

from __future__ import annotations

from typing import Optional

__all__ = [
    "RidgelineError",
    "ParameterError",
    "LimitError",
    "DecodeError",
    "PointListError",
]


class RidgelineError(Exception):
    """Base class of the errors of the ridgeline library."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message

    def __reduce__(self):
        return (type(self), (self.message,))


class ParameterError(RidgelineError, ValueError):
    """A parameter is out of its documented range, of the wrong kind, or not a known key.

    ``field`` names it as a path from the keywords (``"linearity"``, ``"threshold.window"``,
    ``"limits.max_side"``); it is ``""`` when no one field is to blame.
    """

    def __init__(self, message: str, field: str = "") -> None:
        super().__init__(message)
        self.field = field

    def __reduce__(self):
        return (type(self), (self.message, self.field))


class LimitError(RidgelineError, ValueError):
    """The input is larger than ``limits`` allow (checked before anything of that size is
    allocated).

    ``what`` is what was measured (``"image pixels"``, ``"points"``, ...), ``actual`` and ``limit``
    the measured size and the limit, and ``field`` the keyword that raises it
    (``"limits.max_pixels"``: ``trace(image, limits={"max_pixels": ...})``).
    """

    def __init__(
        self,
        message: str,
        what: str = "",
        actual: Optional[int] = None,
        limit: Optional[int] = None,
        field: str = "",
    ) -> None:
        super().__init__(message)
        self.what = what
        self.actual = actual
        self.limit = limit
        self.field = field

    def __reduce__(self):
        return (type(self), (self.message, self.what, self.actual, self.limit, self.field))


class DecodeError(RidgelineError, ValueError):
    """The bytes are not an image ridgeline can decode (PNG, JPEG, TIFF, BMP, PNM, GIF, WebP), or
    the image is damaged."""


class PointListError(RidgelineError, ValueError):
    """A line of a point-list file is not two numbers; ``line`` is its 1-based number."""

    def __init__(self, message: str, line: int = 0) -> None:
        super().__init__(message)
        self.line = line

    def __reduce__(self):
        return (type(self), (self.message, self.line))
