"""The geometry kernel: the shared hull type, exact section integrals, splines, meshes."""

from ._integrate import simpson_weights as simpson_weights
from ._mesh import EXPORT_FORMATS as EXPORT_FORMATS
from ._mesh import atomic_write_bytes as atomic_write_bytes
from ._mesh import export_mesh as export_mesh
from ._mesh import grid_triangles as grid_triangles
from ._mesh import hull_mesh as hull_mesh
from ._mesh import read_stl_header as read_stl_header
from ._mesh import stl_header as stl_header
from ._mesh import surface_grid as surface_grid
from ._mesh import to_trimesh as to_trimesh
from ._mesh import wetted_surface as wetted_surface
from ._sections import EdgeIntegrals as EdgeIntegrals
from ._sections import Sections as Sections
from ._sections import clipped_edge_integrals as clipped_edge_integrals
from ._sections import closed_half_polygon as closed_half_polygon
from ._sections import level_widths as level_widths
from ._sections import polygon_integrals as polygon_integrals
from ._sections import section_integrals as section_integrals
from ._splines import CubicSpline as CubicSpline
from ._splines import natural_cubic_spline as natural_cubic_spline
from ._splines import spline_matrix as spline_matrix
from ._print import split_for_print as split_for_print
