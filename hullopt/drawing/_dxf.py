"""The lines plan as DXF (ezdxf): model space at full scale in metres (``$INSUNITS`` = 6, metres; ``$MEASUREMENT``
= 1, metric), the views arranged as on the sheet — the sheer plan at the origin (x from the AP, z above the
baseline), the half-breadth plan under it, the body plan under that at the left — one layer per kind of line
(``STATION``, ``WATERLINE``, ``DWL``, ``BUTTOCK``, ``DIAGONAL``, ``OUTLINE``, ``GRID``), the labels on ``TEXT`` and
the title block's fields on ``TITLE``: a yard's CAD takes it at 1:1."""

from __future__ import annotations

import datetime
import io
import os
from pathlib import Path

import numpy as np

from ..geometry import atomic_write_bytes
from ._lines import KINDS, LinesPlan, arrange, legible_labels, plan_labels, thin_labels, view_bounds

#: AutoCAD colour index of each layer.
COLOURS = {"grid": 8, "station": 5, "waterline": 3, "buttock": 1, "diagonal": 30, "dwl": 6, "outline": 7}
_ALIGN = {("left", "center"): "MIDDLE_LEFT", ("right", "center"): "MIDDLE_RIGHT", ("center", "top"): "TOP_CENTER",
          ("center", "bottom"): "BOTTOM_CENTER", ("right", "bottom"): "BOTTOM_RIGHT",
          ("left", "bottom"): "BOTTOM_LEFT", ("center", "center"): "MIDDLE_CENTER"}


def write_lines_dxf(plan: LinesPlan, path: str | os.PathLike, fields: list[tuple[str, str]] | None = None) -> Path:
    """Write the three views to a DXF at full scale in metres (see the module docstring), written atomically.

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`~._lines.lines_plan`).
    path : str or os.PathLike
        The DXF file to write.
    fields : list of (str, str) or None
        The title block's fields (:func:`~._sheet.title_block`), written under the views; None: the name and the
        particulars.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import ezdxf
    from ezdxf.enums import TextEntityAlignment

    x0, x1 = view_bounds(plan.sheer)[:2]
    gap = 0.06 * (x1 - x0)
    height = 0.004 * (x1 - x0)  # text height [m]: 1.8 mm on a sheet that spans 450 mm
    doc = ezdxf.new("R2010", units=ezdxf.units.M)
    doc.header["$MEASUREMENT"] = 1
    for kind in KINDS:
        doc.layers.add(kind.upper(), color=COLOURS[kind])
    doc.layers.add("TEXT", color=7)
    doc.layers.add("TITLE", color=7)
    msp = doc.modelspace()
    shift = arrange(plan, gap)
    for view in shift:
        d = np.asarray(shift[view])
        for kind, _, pts in getattr(plan, view):
            msp.add_lwpolyline([tuple(map(float, q)) for q in pts + d], dxfattribs={"layer": kind.upper()})
    labels = plan_labels(plan)
    labels = [lab for view in shift for lab in thin_labels([b for b in labels if b.view == view], plan, 1.0, height)]
    # the body plan's station numbers and the buttocks' names where each clears those kept before it
    kept = legible_labels(labels, lambda lab: np.asarray(lab.at) + np.asarray(shift[lab.view])
                          + np.asarray(lab.offset) * height, height)
    for lab, at in kept:
        text = msp.add_text(lab.text, height=height, dxfattribs={"layer": "TEXT"})
        align = TextEntityAlignment[_ALIGN.get((lab.ha, lab.va), "MIDDLE_CENTER")]
        text.set_placement(tuple(map(float, at)), align=align)
    if fields is None:
        fields = [("Lines plan", plan.name or "—"), ("Lpp", f"{plan.lpp:.3f} m"), ("B", f"{plan.beam:.3f} m"),
                  ("T", "—" if plan.draft is None else f"{plan.draft:.3f} m"),
                  ("Date", datetime.date.today().isoformat()), ("Units", "m, full scale")]
    lowest = min(view_bounds(getattr(plan, v))[2] + shift[v][1] for v in shift)
    for i, (name, value) in enumerate(fields):
        msp.add_text(f"{name}: {value}", height=1.5 * height, dxfattribs={"layer": "TITLE"}).set_placement(
            (x0, lowest - gap - 2.5 * height * i))
    buf = io.StringIO()
    doc.write(buf)
    atomic_write_bytes(path, buf.getvalue().encode())
    return Path(path)
