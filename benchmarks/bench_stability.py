"""Stability benchmark (issue [7/8]): the DTC's GZ curve, hullopt vs NavalToolbox on the same mesh.

Full-scale DTC (model mesh × 59.407, Lpp 355 m), design volume 173,467 m³, KG 20 m, free trim, heels 0–90°
by 5°. Where the two differ (past 65°), the closed mesh is cut by hullopt's equilibrium waterplane with
manifold3d (exact) as a third opinion. Also: compile and warm times of the GZ curve and of the curve with
the IS Code criteria.

Run: ``.venv/bin/python benchmarks/bench_stability.py``; results in results/stability.json.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import manifold3d  # noqa: E402
import numpy as np  # noqa: E402
from _common import HULLS, save, timeit  # noqa: E402

from hullopt.hydro import gz_curve, stability  # noqa: E402
from hullopt.models import MeshTransform, read_mesh, slice_mesh  # noqa: E402

DTC = HULLS / "DTC-scaled.stl.gz"
VOLUME, KG = 173467.0, 20.0
HEELS = np.arange(0.0, 91.0, 5.0)


def mesh_gz(mesh, heel, level, trim, lpp):
    """GZ of the closed mesh cut below the waterplane z' = level + trim (x − Lpp/2) in the heeled frame."""
    c, s = np.cos(heel), np.sin(heel)
    v = np.asarray(mesh.vertices, np.float64) @ np.array([[1, 0, 0], [0, c, s], [0, -s, c]])
    whole = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=v, tri_verts=np.asarray(mesh.faces, np.uint64)))
    n = np.array([trim, 0.0, -1.0])  # keep n·p ≥ n·o: below the plane
    part = whole.trim_by_plane(tuple(n), float(n @ [lpp / 2, 0.0, level]))
    m = part.to_mesh64()
    import trimesh

    cut = trimesh.Trimesh(np.asarray(m.vert_properties)[:, :3], np.asarray(m.tri_verts, np.int64), process=False)
    return cut.volume, -KG * s - cut.center_mass[1]


def main() -> None:
    mesh = read_mesh(DTC, MeshTransform(scale=59.407))
    sections = slice_mesh(mesh, 355.0)
    heels = jnp.deg2rad(jnp.asarray(HEELS))
    f = eqx.filter_jit(gz_curve)
    t0 = time.perf_counter()
    ours = jax.block_until_ready(f(sections, jnp.asarray(VOLUME), jnp.asarray(KG), heels))
    t_first = time.perf_counter() - t0
    t_warm = timeit(lambda: jax.block_until_ready(f(sections, jnp.asarray(VOLUME), jnp.asarray(KG), heels)), 5)
    g = eqx.filter_jit(stability)
    t0 = time.perf_counter()
    res = jax.block_until_ready(g(sections, jnp.asarray(VOLUME), jnp.asarray(KG), heels))
    t_crit_first = time.perf_counter() - t0
    t_crit = timeit(lambda: jax.block_until_ready(g(sections, jnp.asarray(VOLUME), jnp.asarray(KG), heels)), 3)

    import navaltoolbox as ntb

    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "dtc.stl"
        mesh.export(stl)
        vessel = ntb.Vessel(ntb.Hull(str(stl)))
        vessel.ap, vessel.fp = 0.0, 355.0
        t0 = time.perf_counter()
        theirs = ntb.StabilityCalculator(vessel, 1025.0).gz_curve(
            1025.0 * VOLUME, (float(ours.lcg), 0.0, KG), [float(h) for h in HEELS])
        t_ntb = time.perf_counter() - t0
    pts = theirs.points()
    their_gz = np.array([p[3] for p in pts])
    their_trim = np.array([p[2] for p in pts])
    cut = [mesh_gz(mesh, float(h), float(lv), float(tr), 355.0) for h, lv, tr in zip(heels, ours.level, ours.trim)]
    print(f"DTC {sections.n}×{sections.m}, ∇ {VOLUME:,.0f} m³, KG {KG} m, LCG {float(ours.lcg):.3f} m, "
          f"GM0 {float(ours.gm0):.3f} m")
    print(f"{'heel':>5} {'GZ hullopt':>11} {'GZ NTB':>9} {'GZ mesh cut':>12} {'∇ cut/∇':>8} {'trim ours':>10} {'trim NTB':>9}")
    for i, h in enumerate(HEELS):
        print(f"{h:5.0f} {float(ours.gz[i]):11.4f} {their_gz[i]:9.4f} {cut[i][1]:12.4f} {cut[i][0] / VOLUME:8.5f} "
              f"{np.rad2deg(np.arctan(float(ours.trim[i]))):10.4f} {their_trim[i]:9.4f}")
    print(f"hullopt GZ curve (19 heels): first call {t_first:.1f} s, warm {t_warm * 1e3:.1f} ms; "
          f"with criteria: first {t_crit_first:.1f} s, warm {t_crit * 1e3:.1f} ms; NavalToolbox {t_ntb:.2f} s")
    for r in res.criteria.to_list():
        print(f"  {r['criterion']:<32} {r['value']:10.4f} {r['unit']:<6} ≥ {r['required']:<6g} {'pass' if r['pass'] else 'FAIL'}")
    save("stability", {
        "dtc_sections": [sections.n, sections.m], "volume": VOLUME, "kg": KG, "lcg": float(ours.lcg),
        "gm0": float(ours.gm0), "heel_deg": HEELS.tolist(), "gz_hullopt": np.asarray(ours.gz).tolist(),
        "gz_navaltoolbox": their_gz.tolist(), "gz_mesh_cut": [c[1] for c in cut],
        "mesh_cut_volume_ratio": [c[0] / VOLUME for c in cut],
        "trim_deg_hullopt": np.rad2deg(np.arctan(np.asarray(ours.trim))).tolist(), "trim_deg_navaltoolbox": their_trim.tolist(),
        "seconds": {"gz_first": t_first, "gz_warm": t_warm, "criteria_first": t_crit_first, "criteria_warm": t_crit,
                    "navaltoolbox": t_ntb},
        "criteria": res.criteria.to_list(),
    })


if __name__ == "__main__":
    main()
