"""Calm-water resistance."""

from ._holtrop import HoltropHull as HoltropHull
from ._holtrop import HoltropResult as HoltropResult
from ._holtrop import holtrop_hull as holtrop_hull
from ._holtrop import holtrop_mennen as holtrop_mennen
from ._michell import michell_integrand as michell_integrand
from ._michell import michell_wave_resistance as michell_wave_resistance
from ._michell import wave_resistance_coefficient as wave_resistance_coefficient
