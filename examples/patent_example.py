"""The kind of change seed 000's worked example makes (JP2006-79247 §0027: move the bow and stern apex lines so
that LCB moves forward by ≈ 0.3 % Lpp with Cb held), made here on the DTC parent. It reproduces the patent's
LCB *shift*, not the patent's hull or its numbers: the patent's ship (Cb 0.591, LCB −1.47 → −1.18 % Lpp from
midship) is not available, and its apex moves are not given in a form that could be replayed. On the DTC at
T = 14.5 m the hand-set parameters of configs/deform_example.toml give Cb 0.6605 → 0.6604 (−0.00005) and LCB
−0.970 → −0.673 % Lpp (+0.297). Writes body plans and sectional-area curves before/after (PNG) to the folder
given (default: the current one; created if missing).

    .venv/bin/python examples/patent_example.py [OUT_DIR]
"""

import sys
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hullopt.app.commands.features import read_design  # noqa: E402
from hullopt.hydro import hydrostatics, sectional_areas  # noqa: E402
from hullopt.models import check_design  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)
model, params, _ = read_design(Path(__file__).parents[1] / "configs" / "deform_example.toml")
T = model.hull.design_draft
before, after = model.hull.sections(), check_design(model, params)
h0, h1 = hydrostatics(before, T), hydrostatics(after, T)
print(f"Cb  {float(h0.cb):.4f} -> {float(h1.cb):.4f}  (change {float(h1.cb - h0.cb):+.5f})")
print(f"LCB {float(h0.lcb_pct):+.3f} -> {float(h1.lcb_pct):+.3f} % Lpp from midship, forward positive")

fig, ax = plt.subplots(figsize=(10, 6))
x = np.asarray(before.x)
for sec, style in ((before, "0.6"), (after, "tab:red")):
    yz = np.asarray(sec.yz)
    for i in range(0, len(x), 2):
        s = 1.0 if x[i] >= float(before.lpp) / 2 else -1.0
        ax.plot(s * yz[i, :, 0], yz[i, :, 1], color=style, lw=0.6)
ax.axhline(T, color="tab:blue", lw=0.5)
ax.set_aspect("equal")
ax.set_title("Body plan: parent (grey), apex lines moved (red)")
fig.savefig(out / "patent_body_plan.png", dpi=120)

fig, ax = plt.subplots(figsize=(10, 4))
ax.plot(x, np.asarray(sectional_areas(before, T)), color="0.5", label=f"parent, LCB {float(h0.lcb_pct):+.2f} %")
ax.plot(x, np.asarray(sectional_areas(after, T)), color="tab:red", label=f"deformed, LCB {float(h1.lcb_pct):+.2f} %")
ax.set_xlabel("x from AP [m]")
ax.set_ylabel("A(x) [m²]")
ax.legend()
ax.set_title(f"Sectional-area curve at T = {T} m (Cb {float(h0.cb):.4f} → {float(h1.cb):.4f})")
fig.savefig(out / "patent_sac.png", dpi=120)
print("wrote", out / "patent_body_plan.png", out / "patent_sac.png")
