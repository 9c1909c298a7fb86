"""Drawings and tables: the lines plan on a sheet (PNG/SVG/PDF) and in DXF, hydrostatic, GZ and cross curves,
offset tables."""

from ._curves import plot_cross_curves as plot_cross_curves
from ._curves import plot_gz as plot_gz
from ._curves import plot_hydrostatic_curves as plot_hydrostatic_curves
from ._dxf import write_lines_dxf as write_lines_dxf
from ._grid import round_step as round_step
from ._grid import waterline_spacing as waterline_spacing
from ._lines import LinesPlan as LinesPlan
from ._lines import lines_plan as lines_plan
from ._lines import plan_labels as plan_labels
from ._lines import station_sections as station_sections
from ._offsets import half_breadths as half_breadths
from ._offsets import offset_table as offset_table
from ._offsets import write_offset_grid as write_offset_grid
from ._offsets import write_offsets_stations as write_offsets_stations
from ._offsets import write_offsets_wide as write_offsets_wide
from ._save import save_figure as save_figure
from ._sheet import LINES_FORMATS as LINES_FORMATS
from ._sheet import SCALES as SCALES
from ._sheet import SHEETS as SHEETS
from ._sheet import layout_sheet as layout_sheet
from ._sheet import plot_lines as plot_lines
from ._sheet import save_lines as save_lines
from ._sheet import title_block as title_block
