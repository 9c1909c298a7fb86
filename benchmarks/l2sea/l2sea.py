"""Run CNR-INM's L2-Sea (its WARP linear potential-flow solver) on hullopt hulls.

L2-Sea is built by ``benchmarks/l2sea/build.sh`` into ``$HULLOPT_L2SEA_DIR`` (default
``${HULLOPT_CACHE:-~/.cache/hullopt}/l2sea``); see ``benchmarks/l2sea/README.md``.

* :func:`sections_to_grid` / :func:`write_grid`: a hullopt :class:`~hullopt.geometry.Sections` as L2-Sea's
  hull grid — a PLOT3D surface (``1``, ``ni nj 1``, then all x, all y, all z, i fastest), half hull (y ≥ 0,
  port), full scale, metres, in hullopt's own axes (x forward from the AP, z up from the baseline: the axes of
  L2-Sea's own ``5415_90_25_fs.x``). Node ``i = 0`` is the stem profile (on the centreline), ``i = ni − 1`` the
  aft-most immersed station (the transom edge); ``j = 0`` is the top of each line, ``j = nj − 1`` its keel
  point (on the centreline).
* :func:`run_warp`: run L2-Sea on such a grid in a temporary folder (its KLE morphing switched to identity by
  zero eigenvectors, so the grid is run as given) and return its coefficients: pressure-integral ``cw``
  (``Cw_pi``), wave-cut ``cw_wavecut``, ``cf`` (ITTC 1957 at model scale), ``ct``, the resistances [N] at model
  scale, the sinkage and trim its pressure predicts (not applied: the runs are at even keel, as the
  benchmark's), the wetted surface and the wall time.

Coefficients are L2-Sea's: made non-dimensional by ½ρU²S with S the wetted surface of the grid at rest.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

DTMB5415_LPP = 142.0  # full-scale Lpp of L2-Sea's DTMB 5415 [m]
DTMB5415_DRAFT = 6.16  # its draft [m]
MODEL_LPP = 5.72  # model length L2-Sea uses for the viscous part (INSEAN model 2340) [m]
SCALE = DTMB5415_LPP / MODEL_LPP  # 24.825
NODES = {1: (180, 50), 2: (151, 42), 3: (127, 35), 4: (107, 30), 5: (90, 25), 6: (76, 21), 7: (64, 18)}  # regrid


def l2sea_dir() -> Path:
    """Where build.sh puts L2-Sea: ``$HULLOPT_L2SEA_DIR``, else ``${HULLOPT_CACHE:-~/.cache/hullopt}/l2sea``."""
    if os.environ.get("HULLOPT_L2SEA_DIR"):
        return Path(os.environ["HULLOPT_L2SEA_DIR"])
    return Path(os.environ.get("HULLOPT_CACHE", Path.home() / ".cache" / "hullopt")) / "l2sea"


def binary() -> Path | None:
    """The built L2-Sea binary, or None when build.sh has not been run."""
    b = l2sea_dir() / "bin" / "L2-Sea"
    return b if b.is_file() and os.access(b, os.X_OK) else None


def parent_grid() -> Path:
    """L2-Sea's own DTMB 5415 grid (``5415_90_25_fs.x``, full scale)."""
    return l2sea_dir() / "examples" / "DTMB-5415" / "5415_90_25_fs.x"


# ---------------------------------------------------------------------------------------------------------
# PLOT3D grid I/O


def read_grid(path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a one-block PLOT3D surface grid as written by L2-Sea: arrays X, Y, Z of shape (nj, ni)."""
    tok = Path(path).read_text().split()
    ni, nj = int(tok[1]), int(tok[2])
    n = ni * nj
    v = np.array(tok[4 : 4 + 3 * n], dtype=float)
    return v[:n].reshape(nj, ni), v[n : 2 * n].reshape(nj, ni), v[2 * n :].reshape(nj, ni)


def write_plot3d(path, X: np.ndarray, Y: np.ndarray, Z: np.ndarray) -> Path:
    """Write arrays (nj, ni) as L2-Sea's PLOT3D surface grid (i fastest; 5 numbers a line)."""
    nj, ni = X.shape
    path = Path(path)
    vals = np.concatenate([X.ravel(), Y.ravel(), Z.ravel()])
    lines = [f"{1:14d}", f"{ni:12d}{nj:12d}{1:12d}"]
    for k in range(0, len(vals), 5):
        lines.append("".join(f"{v:16.8e}" for v in vals[k : k + 5]))
    path.write_text("\n".join(lines) + "\n")
    return path


def grid_to_sections(X: np.ndarray, Y: np.ndarray, Z: np.ndarray, lpp: float, n: int = 201):
    """An L2-Sea hull grid (arrays (nj, ni), its axes: x from the AP, z from the baseline) as a hullopt
    :class:`~hullopt.geometry.Sections`: ``n`` stations (hullopt's spacing, half even, half cosine), each cut
    across the grid's rows (j) by linear interpolation along them, from the keel up; where rows do not reach
    the station (the stem, the transom) the section runs on the centreline. Points are padded at the keel to
    a common count. Used to check :func:`write_grid` on L2-Sea's own grid (a round trip)."""
    import jax.numpy as jnp

    from hullopt.geometry import Sections
    from hullopt.models import station_positions

    nj = X.shape[0]
    xs = station_positions(float(X.min()), float(X.max()), n)
    secs = []
    for xq in xs:
        pts: list[tuple[float, float]] = []
        present = False
        for j in range(nj - 1, -1, -1):  # keel row first
            rx = X[j]
            if rx.min() <= xq <= rx.max():
                o = np.argsort(rx)
                y = float(np.interp(xq, rx[o], Y[j][o]))
                z = float(np.interp(xq, rx[o], Z[j][o]))
                if not present:
                    pts.append((0.0, z))
                pts.append((max(y, 0.0), z))
                present = True
            elif present:
                pts.append((0.0, pts[-1][1]))
                present = False
        if not pts:
            pts = [(0.0, float(Z.max()))]
        secs.append(np.array(pts))
    m = max(len(p) for p in secs)
    yz = np.stack([np.vstack([np.repeat(p[:1], m - len(p), axis=0), p]) for p in secs])
    return Sections(x=jnp.asarray(xs), yz=jnp.asarray(yz), lpp=jnp.asarray(float(lpp)))


# ---------------------------------------------------------------------------------------------------------
# hullopt Sections -> L2-Sea grid


def _outer_curve(yz: np.ndarray, eps: float):
    """The part of a half-section (keel → deck, (m, 2)) from its keel point on the centreline up to its deck
    edge (a tail running inboard near the top — the deck — is dropped); None when it has no breadth. Also
    returns the number of separate pieces: 1 when every point after the keel point is off the centreline."""
    y = yz[:, 0]
    off = y > eps
    if not off.any():
        return None, 0
    c = yz[max(int(np.argmax(off)) - 1, 0) :]
    c = c[np.r_[True, np.any(np.diff(c, axis=0) != 0, axis=1)]]  # drop repeated points
    tol = 0.02 * (c[:, 1].max() - c[:, 1].min())
    k = len(c) - 1
    while k > 1 and c[k - 1, 0] >= c[k, 0] and c[k - 1, 1] >= c[-1, 1] - tol:
        k -= 1
    c = c[: k + 1]
    on = c[:, 0] > eps
    on[0] = True  # the keel point
    pieces = 1 + int(np.sum(on[1:] & ~on[:-1])) + int(not on[-1])  # back on the centreline counts as a break
    return c, pieces


def _line(c: np.ndarray, level: float, n_above: int, n_below: int, f: float = 0.25) -> np.ndarray | None:
    """``n_above + n_below`` points along a curve that runs from a keel point (first) up past ``level`` (the
    waterline), from the top down, **evenly spaced by arc length** with ``n_below`` of them at or below the
    waterline, the last at the keel, and the waterline half-way between the two that straddle it. The line
    ends above the waterline where that spacing puts its top, continued straight past the curve's end if
    needed (only the immersed part matters to WARP). None when the curve does not cross ``level``.

    Why: L2-Sea re-splines every grid line to even spacing (its regrid step, at every level), then PANCA cuts
    each line at the waterline (and merges a sliver panel). Where the waterline falls between two nodes moves
    its C_W by up to ±20 % at level 5 (DTMB 5415, Fr 0.28: f = 0.1, 0.25, 0.75, 0.9 gave 0.88–0.91e-3, f = 0.5
    gave 0.72e-3; L2-Sea's own grid, the waterline anywhere, 1.13e-3). A grid already evenly spaced, with the
    waterline at the same fraction f of a spacing on every line, keeps that cut the same on every line and
    on every hull written this way: then changing the node count by 2 or the bow breadth by 1 % moves C_W by
    0.3 % (with the waterline left where the nodes fall it moved by ±8 %)."""
    z = c[:, 1]
    k = np.flatnonzero((z[:-1] < level) & (z[1:] >= level))
    if len(k) == 0:
        return None
    k = int(k[-1])  # last upward crossing: the waterline of a flared or tumblehome side
    s = (level - z[k]) / (z[k + 1] - z[k])
    w = c[k] + s * (c[k + 1] - c[k])

    def arc(p):
        p = p[np.r_[True, np.any(np.diff(p, axis=0) != 0, axis=1)]]
        return p, np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]

    pb, sb = arc(np.vstack([w, c[: k + 1][::-1]]))  # waterline → keel
    pa, sa = arc(np.vstack([w, c[k + 1 :]]))  # waterline → top
    h = sb[-1] / (n_below - 1 + f)
    db = (np.arange(n_below) + f) * h  # from the waterline down; the last at the keel
    da = (np.arange(n_above)[::-1] + 1 - f) * h  # from the top down to (1 − f) spacing above the waterline
    up = np.stack([np.interp(da, sa, pa[:, d]) for d in range(2)], axis=1)
    if len(pa) >= 2 and da[0] > sa[-1]:  # continue straight past the end of the curve
        t = pa[-1] - pa[-2]
        t = t / np.linalg.norm(t)
        far = da > sa[-1]
        up[far] = pa[-1] + (da[far] - sa[-1])[:, None] * t
    dn = np.stack([np.interp(db, sb, pb[:, d]) for d in range(2)], axis=1)
    return np.vstack([up, dn])


def _stem_profile(x: np.ndarray, yz: np.ndarray, zs: np.ndarray, eps: float) -> np.ndarray:
    """Forward-most x of the hull at each height ``zs``: the last station with breadth at that height, moved
    forward to where its half-breadth, extrapolated from the station behind, would vanish (not past the next
    station)."""
    p0, p1 = yz[:, :-1, :], yz[:, 1:, :]  # (n, m-1, 2) segments
    out = np.full(len(zs), np.nan)
    for q, zl in enumerate(zs):
        z0, z1 = p0[..., 1], p1[..., 1]
        cross = (np.minimum(z0, z1) <= zl) & (zl <= np.maximum(z0, z1)) & (z1 != z0)
        s = np.where(cross, (zl - z0) / np.where(z1 != z0, z1 - z0, 1.0), 0.0)
        yc = np.where(cross, p0[..., 0] + s * (p1[..., 0] - p0[..., 0]), 0.0)
        half = yc.max(axis=1)  # outermost half-breadth at the level, per station
        has = np.flatnonzero(half > eps)
        if len(has) == 0:
            continue
        k = int(has[-1])
        xs = x[k]
        if 0 < k and half[k - 1] > half[k]:
            xs = x[k] + half[k] * (x[k] - x[k - 1]) / (half[k - 1] - half[k])
        if k + 1 < len(x):
            xs = min(xs, x[k + 1])
        out[q] = xs
    return out


def sections_to_grid(sections, draft: float, ni: int = 90, nj: int = 25, *, n_below: int | None = None,
                     wl_fraction: float = 0.25):
    """A hullopt hull as L2-Sea's structured hull grid, arrays X, Y, Z of shape (nj, ni) [m, hullopt axes].

    Line ``i = 0`` is the stem profile (y = 0, the forward-most x of the hull at each height); lines
    ``i = 1 … ni−1`` are stations from the forward-most one that is a single piece and lies aft of the stem
    profile, back to the aft-most station immersed below the waterline (a transom's edge) — or, for a stern
    that closes on the centreline below the waterline, to the aft-most station forward of it, the last line
    then the stern profile — spaced half evenly, half by cosine, each interpolated node by node between the
    two hullopt stations around it. Every line runs from its top (``j = 0``) down to its keel point on the
    centreline (``j = nj − 1``), evenly spaced by arc length, ``n_below`` nodes (default 2/3 of them, about
    what L2-Sea's own grid has below the waterline at midship) below the waterline and the waterline
    ``wl_fraction`` of a spacing above the first node below it on every line (see :func:`_line`); the tops
    follow from that spacing. Write it with the node counts of the grid level it will run at (:data:`NODES`),
    so that L2-Sea's re-splining to even spacing changes little.
    """
    x = np.asarray(sections.x, dtype=float)
    yz = np.asarray(sections.yz, dtype=float)
    T = float(draft)
    n_below = int(round(2 * nj / 3)) if n_below is None else int(n_below)
    n_above = nj - n_below
    if n_above < 1 or n_below < 2:
        raise ValueError(f"n_below = {n_below} of {nj} nodes a line: need at least 1 above and 2 below")
    eps = 1e-6 * max(float(yz[..., 0].max()), 1e-9)

    curves = []
    for k in range(len(x)):
        c, pieces = _outer_curve(yz[k], eps)
        ok = c is not None and pieces == 1 and c[0, 1] < T < c[:, 1].max()
        curves.append(_line(c, T, n_above, n_below, wl_fraction) if ok else None)
    good = np.array([r is not None for r in curves])
    if not good.any():
        raise ValueError("no station crosses the waterline as a single piece")
    # the contiguous run of usable stations around the middle of the usable range
    gi = np.flatnonzero(good)
    mid = int(gi[np.argmin(np.abs(x[gi] - 0.5 * (x[gi].min() + x[gi].max())))])
    lo = mid
    while lo > 0 and good[lo - 1]:
        lo -= 1
    hi = mid
    while hi + 1 < len(x) and good[hi + 1]:
        hi += 1

    # stem profile, and the forward-most station: aft of the stem at every height it spans below the top
    z_keel_fwd = min(curves[k][-1, 1] for k in range(max(lo, hi - 20), hi + 1))
    z_hi = float(yz[max(lo, hi - 20) :, :, 1].max())
    zs = np.linspace(min(z_keel_fwd, T), z_hi, 600)
    xs = _stem_profile(x, yz, zs, eps)
    valid = np.isfinite(xs)
    zs, xs = zs[valid], xs[valid]
    while hi > lo:
        zk = curves[hi][-1, 1]
        if np.all(xs[(zs >= zk - 1e-9) & (zs <= T + 0.5 * (z_hi - T))] > x[hi] + 1e-6):
            break
        hi -= 1
    # the stern: a transom ends the grid at the aft-most immersed station; a stern that closes on the
    # centreline below the waterline (no transom: the hull goes on aft of that station, which is narrow at the
    # waterline, under a quarter of the largest breadth) gets an aft profile line, as the bow
    z_keel_aft = min(curves[k][-1, 1] for k in range(lo, min(hi, lo + 20) + 1))
    z_hi_aft = float(yz[: min(hi, lo + 20) + 1, :, 1].max())
    za = np.linspace(min(z_keel_aft, T), z_hi_aft, 600)
    xa = -_stem_profile(-x[::-1], yz[::-1], za, eps)  # aft-most x of the hull at each height
    valid = np.isfinite(xa)
    za, xa = za[valid], xa[valid]
    lpp = float(sections.lpp)
    y_wl = 0.5 * (curves[lo][n_above - 1, 0] + curves[lo][n_above, 0])  # its half-breadth at the waterline
    b_wl = max(0.5 * (c[n_above - 1, 0] + c[n_above, 0]) for c in curves[lo : hi + 1])
    closed = bool(np.any(xa[za <= T] < x[lo] - 0.005 * lpp)) and y_wl < 0.25 * b_wl
    if closed:
        while lo < hi:
            zk = curves[lo][-1, 1]
            if np.all(xa[(za >= zk - 1e-9) & (za <= T + 0.5 * (z_hi_aft - T))] < x[lo] - 1e-6):
                break
            lo += 1
    x_a, x_b = x[lo], x[hi]

    # stations: nodes interpolated between hullopt's stations along the length
    n_st = ni - 1 - int(closed)
    idx = np.arange(lo, hi + 1)
    S = np.stack([curves[k] for k in idx])  # (K, nj, 2)
    u = np.linspace(0.0, 1.0, n_st)
    t = 0.5 * u + 0.25 * (1.0 - np.cos(np.pi * u))  # half even, half cosine
    xi = x_b - t * (x_b - x_a)  # forward → aft
    X = np.empty((nj, ni))
    Y = np.empty((nj, ni))
    Z = np.empty((nj, ni))
    for q, xq in enumerate(xi):
        if len(idx) == 1:
            c = S[0]
        else:
            k = int(np.clip(np.searchsorted(x[idx], xq) - 1, 0, len(idx) - 2))
            w = (xq - x[idx[k]]) / (x[idx[k + 1]] - x[idx[k]])
            c = (1 - w) * S[k] + w * S[k + 1]
        X[:, q + 1] = xq
        Y[:, q + 1] = c[:, 0]
        Z[:, q + 1] = c[:, 1]
    Y[-1, 1:] = 0.0  # keel points on the centreline

    # stem line (and stern line): the profile from the end station's keel height up, laid out as the stations
    ends = [(0, 1, xs, zs)] + ([(ni - 1, ni - 2, xa, za)] if closed else [])
    for col, nxt, px, pz in ends:
        z_end = Z[-1, nxt]
        keep = pz >= z_end
        prof = np.vstack([[X[-1, nxt], z_end], np.stack([px[keep], pz[keep]], axis=1)])  # (x, z), bottom → top
        line = _line(prof, T, n_above, n_below, wl_fraction)
        if line is None:
            raise ValueError("the stem or stern profile does not cross the waterline")
        X[:, col] = line[:, 0]
        Y[:, col] = 0.0
        Z[:, col] = line[:, 1]
    return X, Y, Z


def write_grid(sections, draft: float, path, ni: int = 90, nj: int = 25, **kw) -> Path:
    """Write a hullopt hull (full scale, hullopt axes) as L2-Sea's hull grid (``filenamei``) at ``path``;
    see :func:`sections_to_grid` for the layout and options. Returns the path."""
    return write_plot3d(path, *sections_to_grid(sections, draft, ni, nj, **kw))


# ---------------------------------------------------------------------------------------------------------
# running WARP


def _set(text: str, block: str, key: str, value: str) -> str:
    """Set ``key = value`` inside namelist ``&block … /`` of an SBDF.nml text."""
    m = re.search(rf"&{block}\b(.*?)\n/", text, flags=re.S)
    if m is None:
        raise ValueError(f"no namelist {block}")
    body, n = re.subn(rf"(\n\s*{key}\s*=\s*)[^!\n]*", lambda mm: mm.group(1) + value + "\t", m.group(1), count=1)
    if n == 0:
        raise ValueError(f"no {key} in {block}")
    return text[: m.start(1)] + body + text[m.end(1) :]


def run_warp(grid_path, froude=0.28, grid_level: int = 5, *, lpp: float = DTMB5415_LPP,
             draft: float = DTMB5415_DRAFT, keep: str | Path | None = None,
             timeout: float = 1800.0) -> dict:
    """Run L2-Sea's WARP (double-body linearised potential flow, even keel) on the grid at ``grid_path``.

    Parameters
    ----------
    grid_path : path
        A PLOT3D hull grid in the axes of L2-Sea's own (full scale, x from the AP, z from the baseline).
    froude : float or list of float
        Froude number(s), one run of the solver for all.
    grid_level : int
        L2-Sea's fidelity level 1 (finest, 180 × 50 regridded nodes) … 7 (coarsest, 64 × 18); 5 is 90 × 25.
    lpp, draft : float
        Length between perpendiculars and draft of the grid [m] (PANCA's ``dist_pp`` and ``-ztrasla``; the
        model length for the viscous part is ``lpp / SCALE``).
    keep : path, optional
        Copy the run folder (L2-Sea's ``CPU000``) here.

    Returns
    -------
    dict
        ``froude``, ``cw`` (pressure integral), ``cw_wavecut``, ``cf``, ``cf_ittc``, ``ct`` (= cw + cf),
        ``rw_N``, ``rt_N`` (model scale), ``sinkage`` and ``trim`` predicted from the pressure (not applied;
        L2-Sea's non-dimensional sinkage, its sign as it writes it, and trim [rad]), ``wetted_surface_over_L2``,
        ``displacement_over_L3`` (each a list, one per Froude number when a list was given), ``seconds``,
        ``grid_level``, ``nodes`` (regridded ni × nj).
    """
    exe = binary()
    if exe is None:
        raise FileNotFoundError(f"L2-Sea is not built in {l2sea_dir()}: run benchmarks/l2sea/build.sh")
    frs = [float(froude)] if np.isscalar(froude) else [float(f) for f in froude]
    grid_path = Path(grid_path).resolve()
    X, _, _ = read_grid(grid_path)
    nj, ni = X.shape
    template = (l2sea_dir() / "examples" / "DTMB-5415" / "SBDF.nml").read_text()
    nml = template
    for block, key, val in [
        ("MAIN_PARAMETERS", "igrid", str(int(grid_level))),
        ("MAIN_PARAMETERS", "igeomod", "2"),
        ("GRID_PARAMETERS", "filenamei", "'hull.x'"),
        ("GRID_PARAMETERS", "inode", str(ni)),
        ("GRID_PARAMETERS", "jnode", str(nj)),
        ("PANCA_PARAMETERS", "shiplen", f"{lpp / SCALE:.6f}"),
        ("PANCA_PARAMETERS", "dist_pp", f"{lpp:.6f}"),
        ("PANCA_PARAMETERS", "xtrasla", f"{-0.5 * lpp:.6f}"),
        ("PANCA_PARAMETERS", "ztrasla", f"{-draft:.6f}"),
        ("CONSTRAINTS", "ZC_inode", f"1, {min(19, ni)}"),
        ("CONSTRAINTS", "ZC_jnode", f"{min(19, nj)}, {nj}"),
        ("NUMBER_FROUDE", "nfr", str(len(frs))),
        ("FREE_WARP", "fr", " ".join(f"{f:.4f}" for f in frs)),
        ("FREE_WARP", "fz", " ".join("0." for _ in frs)),
        ("FREE_WARP", "my", " ".join("0." for _ in frs)),
        ("FREE_WARP", "sinki", " ".join("0." for _ in frs)),
        ("FREE_WARP", "trimi", " ".join("0." for _ in frs)),
    ]:
        nml = _set(nml, block, key, val)
    with tempfile.TemporaryDirectory(prefix="l2sea-") as tmp:
        # L2-Sea runs `sh ../../../scripts/clean.sh` from its CPU000 folder at the end (deleting outputs):
        # run three levels down in a fresh folder so that no such script exists there.
        run = Path(tmp) / "a" / "b" / "run"
        run.mkdir(parents=True)
        shutil.copy(grid_path, run / "hull.x")
        (run / "SBDF.nml").write_text(nml)
        shutil.copy(l2sea_dir() / "examples" / "DTMB-5415" / "alfak.out", run / "alfak.out")
        (run / "variables.inp").write_text("0.\n" * 14)
        # zero KLE eigenvectors: L2-Sea's morphing (igeomod = 2) leaves the grid as it is
        (run / "eigenvecto.out").write_text(("0. " * 14 + "\n") * (3 * ni * nj))
        env = {**os.environ, "OMP_NUM_THREADS": "1"}  # built without OpenMP (build.sh: static locals)
        t0 = time.perf_counter()
        proc = subprocess.run(["bash", "-c", f"ulimit -s unlimited; exec '{exe}'"], cwd=run, env=env,
                              capture_output=True, text=True, timeout=timeout)
        seconds = time.perf_counter() - t0
        cpu = run / "CPU000"
        if keep is not None:
            shutil.copytree(cpu, keep, dirs_exist_ok=True)
            (Path(keep) / "stdout.log").write_text(proc.stdout + proc.stderr)
        stat = cpu / "coef-stat.out"
        if proc.returncode != 0 or not stat.is_file() or "unfeasible physic" in proc.stdout:
            raise RuntimeError(f"L2-Sea failed (rc {proc.returncode}):\n{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}")
        out = read_run(cpu, one=np.isscalar(froude))
    return out | {"seconds": seconds, "grid_level": int(grid_level),
                  "nodes": list(NODES.get(int(grid_level), (ni, nj)))}


def read_run(cpu, one: bool = True) -> dict:
    """The results of an L2-Sea run from its output folder (``CPU000``, or a copy kept by :func:`run_warp`).

    Parameters
    ----------
    cpu : path
        The folder holding ``coef-stat.out``, ``force-dyn.out``, ``Ct.out`` and ``panca.aux``.
    one : bool
        One Froude number: each value a float (else a list, one per Froude number).

    Returns
    -------
    dict
        As :func:`run_warp`, without ``seconds``, ``grid_level`` and ``nodes``.
    """
    cpu = Path(cpu)

    def table(name):
        return [list(map(float, ln.split())) for ln in (cpu / name).read_text().splitlines()[1:] if ln.strip()]

    rows, dyn, ct_rows = table("coef-stat.out"), table("force-dyn.out"), table("Ct.out")
    aux = (cpu / "panca.aux").read_text().split()
    # coef-stat.out: Fr Cw_pi Cw_wc Ch Cf Cf_ittc Ct_pi Ct_wc Ct_ittc SinkG Trim WSurf_s WSurf_d
    # force-dyn.out: Fr Rw_pi Rw_wc Rh Rf Rf_ittc Rt_pi Rt_wc Rt_ittc
    # Ct.out: Fr Cw Ch Cf Cf_ittc Ct Ct_ittc Sink Trim WSurf
    pick = (lambda v: v[0]) if one else (lambda v: v)
    return {
        "froude": pick([r[0] for r in rows]),
        "cw": pick([r[1] for r in rows]),
        "cw_wavecut": pick([r[2] for r in rows]),
        "cf": pick([r[4] for r in rows]),
        "cf_ittc": pick([r[5] for r in rows]),
        "ct": pick([r[6] for r in rows]),
        "rw_N": pick([r[1] for r in dyn]),
        "rt_N": pick([r[6] for r in dyn]),
        "sinkage": pick([r[7] for r in ct_rows]),
        "trim": pick([r[8] for r in ct_rows]),
        "wetted_surface_over_L2": float(aux[3]),
        "displacement_over_L3": float(aux[1]),
    }


if __name__ == "__main__":  # python benchmarks/l2sea/l2sea.py [level]: the parent from L2-Sea's own grid
    import json
    import sys

    level = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    print(json.dumps(run_warp(parent_grid(), 0.28, level), indent=1))
