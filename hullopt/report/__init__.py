"""What a run looks like to its reader: numbers with their units (:func:`fmt`, :func:`label`), the plots (PNG,
matplotlib) and ``report.html`` (one self-contained page: plotly figures, tables, warnings), built from a run
folder or a study's results. Below the app: the CLI prints and writes through here, and so can a script."""

import lazy_loader

# Names load from their modules on first use: the CLI's commands other than ``run`` need only the units, and
# the page and plots import the whole study (together 0.6–0.9 s of a warm ``hullopt stability``).
__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "_html": [
        "MAX_SWEEP_HULLS", "FRONTS_NAME", "OVERLAY_NAME", "REPORT_NAME", "Hulls", "read_run", "run_hulls",
        "sweep_picks", "write_report",
    ],
    "_plots": [
        "plot_body_plans", "plot_overlay", "plot_convergence", "plot_pareto", "plot_rescored_fronts",
        "plot_resistance", "plot_wave_pattern",
    ],
    "_units": [
        "JSON_UNITS", "NOISE", "OBJECTIVE_UNITS", "PARTICULARS", "SIG", "TARGET_UNITS", "UNIT_PLACES", "change",
        "decimals", "displayed", "fmt", "is_number", "label", "quantity", "scalar", "to_builtin", "unit_places",
        "unit_scale", "units_of", "write_json",
    ],
})
