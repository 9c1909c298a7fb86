"""Models: parameters or files → :class:`~hullopt.geometry.Sections`."""

from ._builtins import BUILTINS as BUILTINS
from ._builtins import box as box
from ._builtins import wigley as wigley
from ._offsets import OffsetSurface as OffsetSurface
from ._offsets import OffsetTable as OffsetTable
from ._offsets import offset_surface as offset_surface
from ._offsets import offsets_to_sections as offsets_to_sections
from ._offsets import parse_station as parse_station
from ._offsets import read_offsets as read_offsets
from ._meshes import MeshTransform as MeshTransform
from ._meshes import read_mesh as read_mesh
from ._meshes import slice_mesh as slice_mesh
from ._meshes import station_positions as station_positions
