"""Models: parameters or files → :class:`~hullopt.geometry.Sections`."""

from ._builtins import BUILTINS as BUILTINS
from ._builtins import box as box
from ._builtins import wigley as wigley
