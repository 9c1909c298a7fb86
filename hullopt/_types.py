"""Type aliases of hullopt's arguments: what a value is, its shape and its unit, written once.

Every alias is a jaxtyping type, so it is checked while the tests run (``tests/conftest.py`` installs
jaxtyping's import hook with beartype over the whole package). ``ArrayLike`` takes a Python float or int, a
NumPy scalar or array, a JAX array, and a traced value under ``jit``/``vmap``/``grad``; an argument that
takes several values also takes a (nested) list of numbers, as ``jnp.asarray`` does. ``""`` is a scalar
(0-d), ``"..."`` any shape (an argument that broadcasts), ``"_"`` one dimension of any size. A named dimension
must agree across the arguments of one call. Units are SI (README "Conventions"): lengths in m, ``z`` above
the baseline, ``x`` from the AP, angles in rad, wave headings 0 = head seas.
"""

from collections.abc import Sequence
from typing import Any

from jaxtyping import ArrayLike, Bool, Float, Inexact, Real

_List = Sequence[Any]  # a (nested) list or tuple of numbers, for the arguments that take several values

# Numbers of any unit (the unit is the argument's, as its docstring says)
Scalar = Float[ArrayLike, ""]  # a real number: dimensionless, or in the unit the argument's docstring gives
Values = Float[ArrayLike, "..."] | _List  # real numbers of any shape, broadcast together
Reals = Real[ArrayLike, "..."]  # real numbers of any shape, integers included (generic kernels: safe_div…)
Complexes = Inexact[ArrayLike, "..."] | _List  # real or complex numbers of any shape
Mask = Bool[ArrayLike, "..."]  # where a condition holds, any shape

# Lengths, volumes, speeds, angles, frequencies
Draft = Float[ArrayLike, ""]  # m above the baseline: the even-keel waterline height T
Drafts = Float[ArrayLike, " k"] | _List  # m above the baseline: several waterline heights
Length = Float[ArrayLike, ""]  # m: a length, a height (KG) or a distance
Lengths = Float[ArrayLike, "..."] | _List  # m, any shape (broadcast)
Volume = Float[ArrayLike, ""]  # m³: a displaced volume ∇
Volumes = Float[ArrayLike, " v"] | _List  # m³: several displaced volumes
Speed = Float[ArrayLike, ""]  # m/s: ship speed U through the water, ahead positive
Speeds = Float[ArrayLike, "..."] | _List  # m/s, any shape (a speed sweep; wind speeds)
Angle = Float[ArrayLike, ""]  # rad: a heel, a heading, a flooding angle
Angles = Float[ArrayLike, "..."] | _List  # rad, any shape (wave headings, heels, wind angles)
Frequencies = Float[ArrayLike, "..."] | _List  # rad/s: circular wave frequencies ω, any shape
Period = Float[ArrayLike, ""]  # s: a wave period (T_p, T_1)
Density = Float[ArrayLike, ""]  # kg/m³: water or air density ρ
Gravity = Float[ArrayLike, ""]  # m/s²: acceleration of gravity g

# Hull geometry
Stations = Float[ArrayLike, " n"]  # m from the AP: station positions x, increasing
Waterlines = Float[ArrayLike, " w"] | _List  # m above the baseline: waterline heights z
Offsets = Float[ArrayLike, "n m 2"]  # m: half-section polylines (y, z) at each station, keel to deck edge
Polygon = Float[ArrayLike, "_ 2"] | _List  # m: a closed polygon's vertices (u, z), one row each
Vectors = Float[ArrayLike, "... 3"]  # 3-vectors along the last axis (x, y, z)
Image = Real[ArrayLike, "_ _ *_"]  # pixels (rows, cols[, 3|4]): grey, RGB or RGBA, uint8 or floats in 0–1
