"""Calm-water resistance."""

from ._holtrop import HoltropHull as HoltropHull
from ._holtrop import HoltropResult as HoltropResult
from ._holtrop import holtrop_hull as holtrop_hull
from ._holtrop import holtrop_mennen as holtrop_mennen
