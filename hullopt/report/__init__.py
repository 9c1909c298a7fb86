"""What a run looks like to its reader: numbers with their units (:func:`fmt`, :func:`label`), the plots (PNG,
matplotlib) and ``report.html`` (one self-contained page: plotly figures, tables, warnings), built from a run
folder or a study's results. Below the app: the CLI prints and writes through here, and so can a script."""

from ._html import MAX_SWEEP_HULLS as MAX_SWEEP_HULLS
from ._html import FRONTS_NAME as FRONTS_NAME
from ._html import OVERLAY_NAME as OVERLAY_NAME
from ._html import REPORT_NAME as REPORT_NAME
from ._html import Hulls as Hulls
from ._html import read_run as read_run
from ._html import run_hulls as run_hulls
from ._html import sweep_picks as sweep_picks
from ._html import write_report as write_report
from ._plots import plot_body_plans as plot_body_plans
from ._plots import plot_overlay as plot_overlay
from ._plots import plot_convergence as plot_convergence
from ._plots import plot_pareto as plot_pareto
from ._plots import plot_rescored_fronts as plot_rescored_fronts
from ._plots import plot_resistance as plot_resistance
from ._plots import plot_wave_pattern as plot_wave_pattern
from ._units import JSON_UNITS as JSON_UNITS
from ._units import NOISE as NOISE
from ._units import OBJECTIVE_UNITS as OBJECTIVE_UNITS
from ._units import PARTICULARS as PARTICULARS
from ._units import SIG as SIG
from ._units import TARGET_UNITS as TARGET_UNITS
from ._units import UNIT_PLACES as UNIT_PLACES
from ._units import change as change
from ._units import decimals as decimals
from ._units import displayed as displayed
from ._units import fmt as fmt
from ._units import is_number as is_number
from ._units import label as label
from ._units import quantity as quantity
from ._units import scalar as scalar
from ._units import to_builtin as to_builtin
from ._units import unit_places as unit_places
from ._units import unit_scale as unit_scale
from ._units import units_of as units_of
from ._units import write_json as write_json
