"""Fairing: the curvature of the Coons-patch hull surface (seed 001, Katsui & Norisada 2005, §2; the surface
itself is the kernel's :class:`~hullopt.geometry.CoonsSurface`), and unfairness functionals that are
hullopt's own (the seed's text stops before it defines its functionals). Automatic fairing, a design problem
over these functionals, is :func:`hullopt.optimise.fair_offsets`."""

from ._curvature import curve_curvature as curve_curvature
from ._curvature import graph_curvatures as graph_curvatures
from ._curvature import polyline_curvature as polyline_curvature
from ._curvature import section_curvature as section_curvature
from ._curvature import surface_curvatures as surface_curvatures
from ._unfairness import RESIDUALS as RESIDUALS
from ._inflections import FLOOR_FRACTION as FLOOR_FRACTION
from ._inflections import count_inflections as count_inflections
from ._inflections import floors as floors
from ._inflections import hull_knots as hull_knots
from ._inflections import inflection_counts as inflection_counts
from ._inflections import knot_weights as knot_weights
from ._inflections import line_curvatures as line_curvatures
from ._inflections import mixed_curvature as mixed_curvature
from ._inflections import sign_variation as sign_variation
from ._unfairness import jump_residuals as jump_residuals
from ._unfairness import knot_residuals as knot_residuals
from ._unfairness import line_residuals as line_residuals
from ._unfairness import mean_residuals as mean_residuals
from ._unfairness import measure as measure
from ._unfairness import unfairness as unfairness
from ._shape import KNUCKLE_FLOOR as KNUCKLE_FLOOR
from ._shape import MERGE as MERGE
from ._shape import SHAPE_MEASURES as SHAPE_MEASURES
from ._shape import sac_roughness as sac_roughness
from ._shape import section_knuckle as section_knuckle
from ._shape import section_roughness as section_roughness
from ._shape import station_knuckles as station_knuckles
from ._shape import SHAPE_UNITS as SHAPE_UNITS
from ._shape import SAC_REGIONS as SAC_REGIONS
from ._shape import WATERLINE_FRACTIONS as WATERLINE_FRACTIONS
from ._shape import WATERLINES_ABOVE as WATERLINES_ABOVE
from ._shape import entrance_angle as entrance_angle
from ._shape import run_angle as run_angle
from ._shape import sac_regions as sac_regions
from ._shape import waterline_angles as waterline_angles
from ._shape import waterlines as waterlines
from ._shape import DWL_BAND as DWL_BAND
from ._shape import INFLECTION_FLOOR as INFLECTION_FLOOR
from ._shape import dwl_turns as dwl_turns
from ._shape import section_inflections as section_inflections
from ._shape import ARRAY_MEASURES as ARRAY_MEASURES
