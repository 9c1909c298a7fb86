"""Drawings and tables: the lines plan (PNG/SVG/PDF/DXF), hydrostatic, GZ and cross curves, offset tables."""

from ._curves import plot_cross_curves as plot_cross_curves
from ._curves import plot_gz as plot_gz
from ._curves import plot_hydrostatic_curves as plot_hydrostatic_curves
from ._lines import LINES_FORMATS as LINES_FORMATS
from ._lines import LinesPlan as LinesPlan
from ._lines import lines_plan as lines_plan
from ._lines import plot_lines as plot_lines
from ._lines import save_lines as save_lines
from ._lines import station_sections as station_sections
from ._lines import write_lines_dxf as write_lines_dxf
from ._offsets import SEED003_STATIONS as SEED003_STATIONS
from ._offsets import half_breadths as half_breadths
from ._offsets import station_label as station_label
from ._offsets import write_offsets_stations as write_offsets_stations
from ._offsets import write_offset_grid as write_offset_grid
from ._offsets import write_offsets_wide as write_offsets_wide
from ._save import save_figure as save_figure
