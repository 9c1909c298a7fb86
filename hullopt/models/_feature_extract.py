"""Extraction of contour lines and feature curves from a parent hull (seed 000 §0011–§0016; numpy, run once).

For each station's half-section (a polyline keel → deck edge, from an offset table or a sliced mesh):

1. **Contour points.** The keel point; the flat of bottom (the run of points from the keel within
   ``flat_tol`` of the keel height) ends at ``F_b``; the flat of side (the run down from the deck edge within
   ``flat_tol`` of the deck-edge half-breadth) starts at ``F_s``; the deck edge. Each flat is then cut back
   until the area between it and its chord keel → ``F_b`` (``F_s`` → deck edge) is below ``cut_tol``,
   because the frame is rebuilt with a straight flat. Without that, the run within ``flat_tol`` reaches
   into the bilge and its chord cuts a sliver off every midship frame (the DTC lost 0.09 % of ∇ so), and
   at a station that cuts the bulb alone (deck edge on the centreline) the whole frame passed for flat of
   side. The area is signed (ripples of a faceted flat about its chord cancel), so a rippled flat stays
   whole and no ripple becomes a segment of its own at one station. Along the length these give the
   profile (keel line), flat-of-bottom, flat-of-side and deck side lines; the aftmost frame is the transom
   end line.
2. **Smoothing.** The curved part ``F_b → F_s`` is cut into *parts* where it runs along the centreline (a
   bulb below the forefoot joined to the hull above, or a station forward of the stem that cuts the bulb
   alone); each part is fitted with a smoothing spline in arc length (raw curvature of a faceted mesh is
   noise), whose curvature sign changes are the candidate inflection points.
3. **Weak lobes.** A lobe between sign changes whose sagitta (largest distance from its chord) is below
   ``lobe_tol`` is noise or a flat: it is merged with its neighbours (an interior lobe loses both its
   inflection points, an end lobe its one).
4. **Segments.** Between adjacent segment ends (``F_b``, inflection points, ends of centreline runs,
   ``F_s``): the apex (farthest from the chord) and the two auxiliary apexes (farthest from the chords
   inflection–apex), stored in the chord frame of :mod:`._feature_frame`. A run along the centreline is a
   straight segment (apex on its chord).
5. **Fixed topology.** Every station gets the same number of segments ``S`` (the most any station has).
   A station with fewer gets *degenerate* segments of zero length at ``F_b`` (the keel end), so the
   uppermost segment is always the main convex one that ends at the flat of side or deck edge (the bilge in
   the parallel midbody, the shoulder and flare in the entrance, the bilge of the run); its apex line runs
   the whole length. Lines of lower segments exist only where the frames have them (bulb, neck, skeg).
"""

from __future__ import annotations

import numpy as np

from .._types import Offsets, Stations
from ..errors import HullError
from ..geometry import SAME_POINT, TINY_LENGTH

#: Chord-frame values of a segment with no shape (degenerate or straight): apex at mid-chord on the chord,
#: auxiliary apexes where a parabola has them (equally spaced in u, v = η(1 − (1 − ρ)²)).
DEFAULT_APEX = (0.5, 0.0)


def default_aux(level: int) -> np.ndarray:
    """``(2, J, 2)`` auxiliary-apex ratios ``(ρ, σ)`` of a parabolic segment, ``J = 2**level − 1``."""
    rho = np.arange(1, 2**level) / 2**level
    half = np.stack([rho, 1.0 - (1.0 - rho) ** 2], -1)
    return np.stack([half, half])


def _chord_uv(a, b, p):
    c = b - a
    cc = float(c @ c)
    rc = np.array([-c[1], c[0]])
    d = p - a
    return d @ c / cc, d @ rc / cc


def _farthest(curve: np.ndarray, i: int, j: int) -> int:
    """Index strictly between ``i`` and ``j`` (either order) farthest from the chord ``curve[i] → curve[j]``."""
    lo, hi = min(i, j), max(i, j)
    if hi - lo < 2:
        return lo
    a, b = curve[lo], curve[hi]
    c = b - a
    if np.hypot(*c) == 0:
        return lo
    d = np.abs((curve[lo + 1 : hi] - a) @ np.array([-c[1], c[0]]))
    return lo + 1 + int(np.argmax(d))


def _refine(curve: np.ndarray, start: int, apex: int, level: int) -> list[int] | None:
    """Auxiliary apexes from ``start`` (an inflection) to ``apex``: each level inserts, in every interval,
    the point farthest from the interval's chord (level 1 is the patent's auxiliary apex)."""
    idx = [start, apex]
    for _ in range(level):
        new = [idx[0]]
        for p, r in zip(idx[:-1], idx[1:]):
            k = _farthest(curve, p, r)
            if k in (p, r) or k == min(p, r):
                return None
            new += [k, r]
        idx = new
    return idx[1:-1]


def _segment(curve: np.ndarray, i: int, j: int, level: int, straight: bool = False) -> tuple:
    """Chord-frame description of the segment ``curve[i..j]``: ``(a, b, (β, η), aux (2, J, 2))``."""
    a, b = curve[i].copy(), curve[j].copy()
    default = (a, b, DEFAULT_APEX, default_aux(level))
    if straight or np.hypot(*(b - a)) == 0 or j - i < 2 ** (level + 2):
        return default
    k = _farthest(curve, i, j)
    beta, eta = _chord_uv(a, b, curve[k])
    lo, hi = _refine(curve, i, k, level), _refine(curve, j, k, level)
    if abs(eta) < 1e-9 or lo is None or hi is None:
        return default
    aux = np.zeros((2, 2**level - 1, 2))
    for t, idx in enumerate((lo, hi)):
        for m, c in enumerate(idx):
            u, v = _chord_uv(a, b, curve[c])
            aux[t, m] = (u / beta if t == 0 else (1 - u) / (1 - beta), v / eta)
    return a, b, (beta, eta), aux


def _smooth(part: np.ndarray, dense: int, smoothing: float) -> np.ndarray:
    """Smoothing spline through a polyline in arc length, sampled at ``dense`` points (ends kept)."""
    from scipy.interpolate import make_smoothing_spline

    seg = np.hypot(*np.diff(part, axis=0).T)
    keep = np.concatenate([[True], seg > 1e-12])
    part = part[keep]
    if len(part) < 5:
        t = np.linspace(0, 1, dense)
        return part[0] + t[:, None] * (part[-1] - part[0]) if len(part) == 2 else np.array(
            [np.interp(t, np.linspace(0, 1, len(part)), part[:, k]) for k in range(2)]).T
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(part, axis=0).T))])
    lam = smoothing * s[-1] ** 3 if smoothing > 0 else None
    spl = make_smoothing_spline(s, part, lam=lam, axis=0)
    t = np.linspace(0.0, s[-1], dense)
    out = spl(t)
    out[0], out[-1] = part[0], part[-1]  # the ends are segment ends: keep them exactly
    return out


def _inflections(curve: np.ndarray, lobe_tol: float) -> list[int]:
    """Indices of the inflection points of a smooth dense curve, weak lobes merged away."""
    d1 = np.gradient(curve, axis=0)
    d2 = np.gradient(d1, axis=0)
    kappa = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    sign = np.sign(kappa)
    # Ignore a few points at the ends, where one-sided differences are poor.
    edge = max(2, len(curve) // 100)
    idx = [i for i in range(edge, len(curve) - edge) if sign[i] * sign[i - 1] < 0]
    bounds = [0, *idx, len(curve) - 1]
    while len(bounds) > 2:
        sag = []
        for a, b in zip(bounds[:-1], bounds[1:]):
            k = _farthest(curve, a, b)
            c = curve[b] - curve[a]
            n = np.hypot(*c)
            sag.append(0.0 if n == 0 or k == a else abs((curve[k] - curve[a]) @ np.array([-c[1], c[0]])) / n)
        w = int(np.argmin(sag))
        if sag[w] >= lobe_tol:
            break
        if w == 0:
            del bounds[1]
        elif w == len(sag) - 1:
            del bounds[-2]
        else:
            del bounds[w : w + 2]
    return bounds[1:-1]


def _cut_off(p: np.ndarray, i: int, j: int) -> float:
    """Area [m²] the chord ``p[i] → p[j]`` cuts off the hull: between the polyline ``p[i..j]`` and the chord,
    positive where the polyline runs outside it (on its right, the hull being on the left of a frame drawn
    keel → deck), negative where inside; ripples about the chord cancel."""
    q = p[i : j + 1]
    if len(q) < 3:
        return 0.0
    y, z = q[:, 0], q[:, 1]
    return 0.5 * float(np.sum(y * np.roll(z, -1) - np.roll(y, -1) * z))  # shoelace: the loop runs anticlockwise


def extract_station(p: np.ndarray, flat_tol: float, lobe_tol: float, smoothing: float, level: int = 2,
                    dense: int = 600, cut_tol: float | None = None):
    """Contour points and segments of one half-section ``p (m, 2)``.

    ``flat_tol``, ``lobe_tol`` [m] and ``cut_tol`` [m²] as in :func:`extract_features` (``cut_tol``
    defaults to ``10 flat_tol²``). Returns ``(keel, deck, segments)`` with ``segments`` a list of
    ``(a, b, apex, aux)`` from ``F_b`` up to ``F_s`` (``segments[0][0]`` is ``F_b``, ``segments[-1][1]`` is
    ``F_s``).
    """
    p = np.asarray(p, dtype=np.float64)
    cut_tol = 10.0 * flat_tol**2 if cut_tol is None else cut_tol  # = 1e-5 B² with flat_tol's default 1e-3 B
    step = np.hypot(*np.diff(p, axis=0).T)
    p = p[np.concatenate([[True], step > SAME_POINT * max(1.0, np.abs(p).max())])]
    keel, deck = p[0].copy(), p[-1].copy()
    if len(p) < 3:
        return keel, deck, [(keel, deck, DEFAULT_APEX, default_aux(level))]
    ib = 0
    while ib + 1 < len(p) - 1 and p[ib + 1, 1] <= keel[1] + flat_tol and p[ib + 1, 0] >= p[ib, 0]:
        ib += 1
    while ib > 0 and abs(_cut_off(p, 0, ib)) > cut_tol:  # the flat ends where the bilge starts to rise
        ib -= 1
    fs = len(p) - 1
    while fs - 1 > ib and p[fs - 1, 0] >= deck[0] - flat_tol and p[fs - 1, 1] <= p[fs, 1]:
        fs -= 1
    while fs < len(p) - 1 and abs(_cut_off(p, fs, len(p) - 1)) > cut_tol:
        fs += 1
    curved = p[ib : fs + 1]
    if len(curved) < 2:
        return keel, deck, [(curved[0], curved[-1], DEFAULT_APEX, default_aux(level))]
    # Parts: maximal runs off the centreline, each with its bounding centreline points.
    on = curved[:, 0] <= SAME_POINT * max(1.0, np.abs(curved).max())
    segments = []
    i = 0
    last = len(curved) - 1
    while i < last:
        if on[i] and on[i + 1]:  # along the centreline: a straight segment
            j = i + 1
            while j < last and on[j + 1]:
                j += 1
            segments.append((curved[i].copy(), curved[j].copy(), DEFAULT_APEX, default_aux(level)))
            i = j
            continue
        j = i + 1
        while j < last and not on[j]:
            j += 1
        part = curved[i : j + 1]
        if len(part) < 4:
            segments.append(_segment(part, 0, len(part) - 1, level, straight=True))
        else:
            sm = _smooth(part, dense, smoothing)
            ends = [0, *_inflections(sm, lobe_tol), len(sm) - 1]
            segments += [_segment(sm, a, b, level) for a, b in zip(ends[:-1], ends[1:])]
        i = j
    return keel, deck, segments


def extract_features(x: Stations, yz: Offsets, lpp: float, flat_tol: float | None = None, lobe_tol: float | None = None,
                     smoothing: float = 0.0, level: int = 2, dense: int = 600, cut_tol: float | None = None):
    """Feature arrays of a parent hull given as sections ``x (n,)``, ``yz (n, m, 2)`` (numpy).

    ``flat_tol`` [m] (default 0.1 % of the greatest breadth B) decides what is flat, ``cut_tol`` [m²]
    (default 1e-5 B²; ``math.inf``: the flats as the band ``flat_tol`` gives them) the most area a flat's
    chord may cut off the frame (module docstring, 1.); ``lobe_tol`` [m]
    (default 0.03 % of B) is the least sagitta of a lobe between inflection points; ``smoothing`` is the
    smoothing spline's λ per cubed arc length (0: chosen by generalised cross-validation); ``level``
    the levels of auxiliary apexes (1: the patent's frame; 2, the default: three per half, see
    :mod:`._feature_frame`).
    Returns a dict of numpy arrays: ``x``, ``keel (n, 2)``, ``deck (n, 2)``, ``ends (n, S+1, 2)``,
    ``apex (n, S, 2)``, ``aux (n, S, 2, J, 2)``, ``real (n, S)`` (segment found in the parent, not padding), ``lpp``.

    Parameters
    ----------
    x : array_like, (n,) float
        Station positions [m from the AP].
    yz : array_like, (n, m, 2) float
        Half-sections ``(y, z)`` [m], keel to deck edge.
    lpp : float
        Length between perpendiculars [m].
    flat_tol : float, optional
        Flatness band [m]; ``None``: 1e-3 B.
    lobe_tol : float, optional
        Least lobe sagitta [m]; ``None``: 3e-4 B.
    smoothing : float
        Smoothing spline's λ per cubed arc length (0, the default: by generalised cross-validation).
    level : int
        Levels of auxiliary apexes, ``J = 2**level − 1`` per half-segment (2 by default).
    dense : int
        Points at which each part's smoothing spline is sampled (600 by default).
    cut_tol : float, optional
        Largest area [m²] a flat's chord may cut off; ``None``: 1e-5 B².

    Returns
    -------
    dict of str to numpy.ndarray
        ``x (n,)``, ``keel (n, 2)``, ``deck (n, 2)``, ``ends (n, S+1, 2)`` [m]; ``apex (n, S, 2)`` and
        ``aux (n, S, 2, J, 2)`` (chord-frame ratios, dimensionless); ``real (n, S)`` bool; ``lpp`` (float, m).
    """
    x = np.asarray(x, dtype=np.float64)
    yz = np.asarray(yz, dtype=np.float64)
    if yz.ndim != 3 or yz.shape[0] != x.shape[0] or yz.shape[2] != 2:
        raise HullError(f"sections must be (n, m, 2) with n = {x.shape[0]} stations, got {yz.shape}")
    breadth = 2.0 * max(float(yz[..., 0].max()), TINY_LENGTH)
    flat_tol = 1e-3 * breadth if flat_tol is None else flat_tol
    lobe_tol = 3e-4 * breadth if lobe_tol is None else lobe_tol
    cut_tol = 1e-5 * breadth**2 if cut_tol is None else cut_tol
    stations = [extract_station(p, flat_tol, lobe_tol, smoothing, level, dense, cut_tol) for p in yz]
    s_max = max(len(st[2]) for st in stations)
    n = len(x)
    keel = np.array([st[0] for st in stations])
    deck = np.array([st[1] for st in stations])
    ends = np.zeros((n, s_max + 1, 2))
    apex = np.tile(np.array(DEFAULT_APEX), (n, s_max, 1))
    aux = np.tile(default_aux(level), (n, s_max, 1, 1, 1))
    real = np.zeros((n, s_max), bool)
    for i, (_, _, segs) in enumerate(stations):
        pad = s_max - len(segs)  # degenerate segments at the keel end (module docstring, 5.)
        ends[i, : pad + 1] = segs[0][0]
        for k, (a, b, ap, ax) in enumerate(segs):
            ends[i, pad + k + 1] = b
            apex[i, pad + k] = ap
            aux[i, pad + k] = ax
            real[i, pad + k] = True
    return dict(x=x, keel=keel, deck=deck, ends=ends, apex=apex, aux=aux, real=real, lpp=float(lpp))
