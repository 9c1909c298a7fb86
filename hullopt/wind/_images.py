"""Wind variables from drawings (seed 004 claims 1–5): side and front views as images with a scale.

Pixel convention: pixel ``(r, c)`` has its centre at ``(r, c)`` (as ``skimage.draw.polygon``). A view has a
scale ``ppm`` [pixels per metre] and a ``waterline_row``: the waterline runs along the top edge of that row,
so a pixel centre in row r stands ``(waterline_row − 0.5 − r)/ppm`` metres above water. In the side view
the bow points to the right (``bow="right"``) or left; column ``origin_col − 0.5`` is x = 0 (any origin
gives the same variables, which are measured from mid-length). Everything below the waterline is ignored.

Parts are picked by colour (RGB within a tolerance) or by a polygon in pixel coordinates ``[[col, row], …]``;
the ship is every pixel darker than ``threshold`` (grey level 0–1) or of a part colour.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import jax.numpy as jnp
import numpy as np

from .._types import Image, Polygon
from ..errors import HullError
from ._variables import WindVariables

# skimage (0.15 s to import) is imported in the functions that use it: most runs read no drawing.


@dataclass(frozen=True)
class ViewScale:
    """Scale of one view: ``ppm`` pixels per metre, ``waterline_row`` (see the module docstring), the
    column of x = 0 and the side the bow points to (side view only)."""

    ppm: float
    waterline_row: float
    origin_col: float = 0.0
    bow: str = "right"

    def __post_init__(self):
        if not (np.isfinite(self.ppm) and self.ppm > 0):
            raise HullError(f"pixels_per_metre {self.ppm!r}: must be a positive number (the drawing's scale)")
        if not np.isfinite(self.waterline_row):
            raise HullError(f"waterline_row {self.waterline_row!r}: must be a row number")
        if self.bow not in ("right", "left"):
            raise HullError(f"bow {self.bow!r}: expected 'right' or 'left'")

    def to_pixels(self, u, h) -> tuple[np.ndarray, np.ndarray]:
        """Metres (u along the view, h above water) → (row, col) pixel coordinates."""
        s = 1.0 if self.bow == "right" else -1.0
        return self.waterline_row - 0.5 - np.asarray(h) * self.ppm, self.origin_col - 0.5 + s * np.asarray(u) * self.ppm

    def to_metres(self, rows, cols) -> tuple[np.ndarray, np.ndarray]:
        """Pixel centres → (u, h) in metres."""
        s = 1.0 if self.bow == "right" else -1.0
        return s * (np.asarray(cols) + 0.5 - self.origin_col) / self.ppm, (self.waterline_row - 0.5 - np.asarray(rows)) / self.ppm


@dataclass(frozen=True)
class PartSpec:
    """A part in a drawing: a name, a kind (``hull``, ``superstructure``, ``cargo``, ``mast``), a mast group,
    and either an RGB ``colour`` or a pixel ``polygon`` ``[[col, row], …]`` of the side view."""

    name: str
    kind: str
    colour: tuple[int, int, int] | None = None
    polygon: list[list[float]] | None = None
    group: str = ""
    tolerance: float = field(default=8.0)


def render(polygons: Sequence[Polygon], colours: Sequence[tuple[int, int, int]], scale: ViewScale,
           shape: tuple[int, int]) -> np.ndarray:
    """Draw filled polygons ``(k, 2)`` in metres (u, h) into a white RGB ``uint8`` image of ``shape``.

    Parameters
    ----------
    polygons : sequence of (k, 2) float
        Polygons in metres (u along the view, h above water), one per part.
    colours : sequence of (3,) int
        RGB colour (0–255) of each polygon.
    scale : ViewScale
        The view's scale and origin.
    shape : (int, int)
        Image (rows, columns) in pixels.

    Returns
    -------
    numpy.ndarray
        (rows, columns, 3) uint8 RGB image, later polygons drawn over earlier ones.
    """
    from skimage import draw

    img = np.full((*shape, 3), 255, dtype=np.uint8)
    for poly, col in zip(polygons, colours):
        poly = np.asarray(poly, dtype=float)
        r, c = scale.to_pixels(poly[:, 0], poly[:, 1])
        rr, cc = draw.polygon(r, c, shape=shape)
        img[rr, cc] = col
    return img


def _rgb(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim == 2:
        image = np.stack([image] * 3, axis=-1)
    if image.ndim != 3 or image.shape[-1] not in (3, 4):
        raise HullError(f"image of shape {image.shape}: expected a grey, RGB or RGBA image")
    image = image[..., :3]
    if image.dtype != np.uint8:
        image = np.clip(np.round(255 * image if image.max() <= 1.0 else image), 0, 255).astype(np.uint8)
    return image


def ship_mask(image: Image, scale: ViewScale, threshold: float = 0.5) -> np.ndarray:
    """Binary mask of the ship above the waterline: grey level below ``threshold``.

    Parameters
    ----------
    image : array_like
        Grey (rows, cols), RGB or RGBA (rows, cols, 3|4) image, uint8 or floats in 0–1.
    scale : ViewScale
        The view's scale (its ``waterline_row`` cuts the mask).
    threshold : float
        Grey level (0–1) below which a pixel is the ship.

    Returns
    -------
    numpy.ndarray
        (rows, cols) bool mask.
    """
    from skimage import color

    rgb = _rgb(image)
    mask = color.rgb2gray(rgb) < threshold
    rows = np.arange(rgb.shape[0])[:, None]
    mask &= rows < scale.waterline_row - 0.5  # pixel centres above the waterline
    return mask


def part_mask(image: Image, part: PartSpec, scale: ViewScale, ship: np.ndarray) -> np.ndarray:
    """Mask of one part above the waterline: its colour (within ``tolerance`` per channel, any lightness),
    or the ship's pixels inside its polygon.

    Parameters
    ----------
    image : array_like
        The side view, grey, RGB or RGBA (rows, cols[, 3|4]).
    part : PartSpec
        The part, with a ``colour`` or a pixel ``polygon``.
    scale : ViewScale
        The view's scale (its ``waterline_row`` cuts the mask).
    ship : numpy.ndarray
        (rows, cols) bool ship mask (:func:`ship_mask`).

    Returns
    -------
    numpy.ndarray
        (rows, cols) bool mask of the part.

    Raises
    ------
    HullError
        If the part has neither colour nor polygon, a bad polygon, or an empty mask.
    """
    from skimage import draw

    if part.colour is not None:
        diff = np.abs(_rgb(image).astype(float) - np.asarray(part.colour, dtype=float))
        above = np.arange(ship.shape[0])[:, None] < scale.waterline_row - 0.5
        mask = np.all(diff <= part.tolerance, axis=-1) & above
    elif part.polygon is not None:
        poly = np.asarray(part.polygon, dtype=float)
        if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3:
            raise HullError(f"part {part.name!r}: polygon must be at least 3 [col, row] points")
        mask = draw.polygon2mask(ship.shape, poly[:, ::-1]) & ship
    else:
        raise HullError(f"part {part.name!r}: give a colour or a polygon")
    if not mask.any():
        raise HullError(f"part {part.name!r}: empty mask (no pixel of its colour/polygon above the waterline)")
    return mask


def box_counting_dimension(outline: np.ndarray) -> float:
    """Box-counting (Minkowski) dimension of a set of pixels: the slope of log N(s) against log(1/s) over
    box sizes s = 1, 2, 4, … up to a quarter of the smaller image side.

    Parameters
    ----------
    outline : numpy.ndarray
        (rows, cols) bool pixel set (e.g. :func:`outline` of a mask).

    Returns
    -------
    float
        The dimension (dimensionless; ≈ 1 for a smooth curve).

    Raises
    ------
    HullError
        If ``outline`` is empty.
    """
    outline = np.asarray(outline, dtype=bool)
    if not outline.any():
        raise HullError("box counting: empty outline")
    sizes, counts = [], []
    s = 1
    while s <= min(outline.shape) // 4 or len(sizes) < 2:
        h, w = -(-outline.shape[0] // s) * s, -(-outline.shape[1] // s) * s
        padded = np.zeros((h, w), dtype=bool)
        padded[: outline.shape[0], : outline.shape[1]] = outline
        counts.append(padded.reshape(h // s, s, w // s, s).any(axis=(1, 3)).sum())
        sizes.append(s)
        s *= 2
    slope = np.polyfit(np.log(1.0 / np.asarray(sizes)), np.log(np.asarray(counts, dtype=float)), 1)[0]
    return float(slope)


def outline(mask: np.ndarray) -> np.ndarray:
    """The boundary pixels of a mask (the mask less its erosion).

    Parameters
    ----------
    mask : numpy.ndarray
        (rows, cols) bool mask.

    Returns
    -------
    numpy.ndarray
        (rows, cols) bool boundary pixels.
    """
    from skimage import morphology

    return mask & ~morphology.erosion(mask)


def mask_moments(mask: np.ndarray, scale: ViewScale, x_ref: float, order: int = 3) -> np.ndarray:
    """Raw moments ``Σ x^p h^q · pixel area`` [m^(2+p+q)] about (x_ref, waterline), p + q ≤ order
    (``skimage.measure.moments_coords`` on the pixel centres in metres).

    Parameters
    ----------
    mask : numpy.ndarray
        (rows, cols) bool mask.
    scale : ViewScale
        The view's scale and origin.
    x_ref : float
        Reference position along the view [m] (the origin of x).
    order : int
        Highest total order p + q.

    Returns
    -------
    numpy.ndarray
        (order + 1, order + 1) float moments [m^(2+p+q)], indexed [p, q]; 0 where p + q > order.
    """
    from skimage import measure

    rows, cols = np.nonzero(mask)
    u, h = scale.to_metres(rows, cols)
    coords = np.stack([u - x_ref, h], axis=-1)
    m = measure.moments_coords(coords, order=order) / scale.ppm**2
    p, q = np.meshgrid(np.arange(order + 1), np.arange(order + 1), indexing="ij")
    return np.where(p + q <= order, m, 0.0)


@dataclass(frozen=True)
class DrawingResult:
    """Variables read from drawings, plus the outline's box-counting dimension and the masks."""

    variables: WindVariables
    fractal_dimension: float
    side_mask: np.ndarray
    front_mask: np.ndarray


def drawing_variables(side_image: Image, front_image: Image, side: ViewScale, front: ViewScale, parts: list[PartSpec],
                      threshold: float = 0.5) -> DrawingResult:
    """The wind variables of :class:`~hullopt.wind.WindVariables` from a side and a front view.

    Areas are pixel counts / ppm², lengths pixel extents (edge to edge), centroids pixel-centre means,
    ``S`` the perimeter (``skimage.measure.perimeter``) of the side mask without masts less the waterline,
    ``M`` the number of connected components (``skimage.measure.label``) of the mast mask, or of the mast
    groups named in ``parts`` when they are given. ``part_*`` follow ``parts`` (a ``hull`` part, if any,
    is listed first as in the geometry); ``part_front_area`` is NaN (parts are picked in the side view).

    Parameters
    ----------
    side_image, front_image : array_like
        Side and front views, grey, RGB or RGBA (rows, cols[, 3|4]), uint8 or floats in 0–1.
    side, front : ViewScale
        The views' scales (pixels per metre, waterline row, origin; the side view's bow direction).
    parts : list of PartSpec
        Parts picked in the side view (by colour or polygon).
    threshold : float
        Grey level (0–1) below which a pixel is the ship.

    Returns
    -------
    DrawingResult
        The :class:`~hullopt.wind.WindVariables` (SI), the side outline's box-counting dimension and the side
        and front ship masks (bool).

    Raises
    ------
    HullError
        If a view's mask is empty or a part cannot be found.
    """
    from skimage import measure

    ship = ship_mask(side_image, side, threshold)
    front_ship = ship_mask(front_image, front, threshold)
    for what, m in (("side", ship), ("front", front_ship)):
        if not m.any():
            raise HullError(f"{what} view: empty mask (no pixel darker than {threshold} above the waterline row)")
    masks = {p.name: part_mask(side_image, p, side, ship) for p in parts}
    for p in parts:
        ship |= masks[p.name]
    px = 1.0 / side.ppm**2
    rows, cols = np.nonzero(ship)
    u, h = side.to_metres(rows, cols)
    half = 0.5 / side.ppm
    x_lo, x_hi = u.min() - half, u.max() + half
    length, x_mid = x_hi - x_lo, 0.5 * (x_lo + x_hi)
    a_l = ship.sum() * px

    def union(kinds):
        m = np.zeros_like(ship)
        for p in parts:
            if p.kind in kinds:
                m |= masks[p.name]
        return m

    ss, od, mast = union({"superstructure"}), union({"superstructure", "cargo", "mast"}), union({"mast"})
    solid = ship & ~mast
    wl_len = np.any(solid, axis=0).sum() / side.ppm  # the waterline edge is not part of S
    s_outline = measure.perimeter(np.pad(solid, 1)) / side.ppm - wl_len
    groups = {p.group for p in parts if p.kind == "mast" and p.group}
    n_masts = len(groups) if groups else measure.label(mast, connectivity=2).max()
    h_top = lambda m: (side.waterline_row - 0.5 - (np.nonzero(m)[0].min() - 0.5)) / side.ppm  # noqa: E731
    h_br = h_top(ss) if ss.any() else h_top(od) if od.any() else h_top(ship)
    a_ss = ss.sum() * px
    c_br = (side.to_metres(*np.nonzero(ss))[0].mean() - x_mid) if ss.any() else 0.0

    fr, fc = np.nonzero(front_ship)
    _, fh = front.to_metres(fr, fc)
    a_t = front_ship.sum() / front.ppm**2
    breadth = (fc.max() - fc.min() + 1) / front.ppm

    ordered = sorted(parts, key=lambda p: p.kind != "hull")
    mom = np.stack([mask_moments(masks[p.name], side, x_mid) for p in ordered]) if ordered else np.zeros((0, 4, 4))
    area = mom[:, 0, 0]
    props = [measure.regionprops(masks[p.name].astype(np.uint8))[0] for p in ordered]
    c = u.mean() - x_mid
    f = lambda a: jnp.asarray(np.asarray(a, dtype=float))  # noqa: E731
    v = WindVariables(
        L=f(length), B=f(breadth), A_T=f(a_t), A_L=f(a_l), A_OD=f(od.sum() * px), A_SS=f(a_ss), C=f(c),
        C_BR=f(c_br), H_BR=f(h_br), H_C=f(h.mean()), S=f(s_outline), M=f(n_masts), H_T=f(fh.mean()),
        H_L=f(a_l / length), C_bow=f(0.5 * length - c), x_mid=f(x_mid),
        part_area=f(area), part_x=f(mom[:, 1, 0] / area), part_h=f(mom[:, 0, 1] / area), part_moments=f(mom),
        part_perimeter=f([pr.perimeter / side.ppm for pr in props]), part_front_area=f(np.full(len(ordered), np.nan)),
        part_names=tuple(p.name for p in ordered), part_kinds=tuple(p.kind for p in ordered),
    )
    return DrawingResult(v, box_counting_dimension(outline(solid)), ship, front_ship)
