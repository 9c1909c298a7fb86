"""Calm-water resistance."""

from ._holtrop import HoltropHull as HoltropHull
from ._holtrop import HoltropResult as HoltropResult
from ._holtrop import holtrop_hull as holtrop_hull
from ._holtrop import holtrop_mennen as holtrop_mennen
from ._michell import michell_integrand as michell_integrand
from ._michell import michell_wave_resistance as michell_wave_resistance
from ._michell import wave_resistance_coefficient as wave_resistance_coefficient
from ._panel import Panels as Panels
from ._panel import PanelResult as PanelResult
from ._panel import double_body_flow as double_body_flow
from ._panel import hull_panels as hull_panels
from ._panel import kelvin_spectrum as kelvin_spectrum
from ._panel import panel_wave_resistance as panel_wave_resistance
from ._panel import source_velocity as source_velocity
from ._calm import METHODS as METHODS
from ._calm import CalmWater as CalmWater
from ._calm import calm_water as calm_water
from ._calm import check_method as check_method
from ._calm import outside_validity as outside_validity
from ._calm import DISAGREE as DISAGREE
from ._panel import wave_pattern as wave_pattern
