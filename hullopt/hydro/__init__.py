"""Hydrostatics (upright) and, later, stability."""

from ._hydrostatics import RHO_SEA as RHO_SEA
from ._hydrostatics import Hydrostatics as Hydrostatics
from ._hydrostatics import draft_for_volume as draft_for_volume
from ._hydrostatics import hydrostatic_table as hydrostatic_table
from ._hydrostatics import hydrostatics as hydrostatics
from ._hydrostatics import sectional_areas as sectional_areas
from ._hydrostatics import volume_at as volume_at
from ._hydrostatics import waterline_half_breadths as waterline_half_breadths
