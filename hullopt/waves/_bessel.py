"""Modified Bessel functions of the second kind K0, K1 in JAX, and the NMRI draft factor α_T.

``jax.scipy.special`` has I0, I1 (and the scaled i0e, i1e) but no K0, K1. These use the Chebyshev series of
the Cephes library (S. L. Moshier, Cephes Math Library 2.8, ``k0.c``/``k1.c``; the same coefficients scipy uses),
accurate to ~1e-15 relative in float64, with exact derivatives through ``custom_jvp``:
K0' = −K1, K1' = −K0 − K1/x. All functions are elementwise, for x > 0.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.special import i0, i1, i1e

from .._types import Values

# K0(x) + log(x/2) I0(x) on [0, 2], in y = x² − 2 (Cephes k0.c, A).
_K0_A = (
    1.37446543561352307156e-16, 4.25981614279661018399e-14, 1.03496952576338420167e-11,
    1.90451637722020886025e-9, 2.53479107902614945675e-7, 2.28621210311945178607e-5,
    1.26461541144692592338e-3, 3.59799365153615016266e-2, 3.44289899924628486886e-1,
    -5.35327393233902768720e-1,
)
# exp(x) sqrt(x) K0(x) on [2, ∞), in y = 8/x − 2 (Cephes k0.c, B).
_K0_B = (
    5.30043377268626276149e-18, -1.64758043015242134646e-17, 5.21039150503902756861e-17,
    -1.67823109680541210385e-16, 5.51205597852431940784e-16, -1.84859337734377901440e-15,
    6.34007647740507060557e-15, -2.22751332699166985548e-14, 8.03289077536357521100e-14,
    -2.98009692317273043925e-13, 1.14034058820847496303e-12, -4.51459788337394416547e-12,
    1.85594911495471785253e-11, -7.95748924447710747776e-11, 3.57739728140030116597e-10,
    -1.69753450938905987466e-9, 8.57403401741422608519e-9, -4.66048989768794782956e-8,
    2.76681363944501510342e-7, -1.83175552271911948767e-6, 1.39498137188764993662e-5,
    -1.28495495816278026384e-4, 1.56988388573005337491e-3, -3.14481013119645005427e-2,
    2.44030308206595545468e0,
)
# x (K1(x) − log(x/2) I1(x)) on [0, 2], in y = x² − 2 (Cephes k1.c, A).
_K1_A = (
    -7.02386347938628759343e-18, -2.42744985051936593393e-15, -6.66690169419932900609e-13,
    -1.41148839263352776110e-10, -2.21338763073472585583e-8, -2.43340614156596823496e-6,
    -1.73028895751305206302e-4, -6.97572385963986435018e-3, -1.22611180822657148235e-1,
    -3.53155960776544875667e-1, 1.52530022733894777053e0,
)
# exp(x) sqrt(x) K1(x) on [2, ∞), in y = 8/x − 2 (Cephes k1.c, B).
_K1_B = (
    -5.75674448366501715755e-18, 1.79405087314755922667e-17, -5.68946255844285935196e-17,
    1.83809354436663880070e-16, -6.05704724837331885336e-16, 2.03870316562433424052e-15,
    -7.01983709041831346144e-15, 2.47715442448130437068e-14, -8.97670518232499435011e-14,
    3.34841966607842919884e-13, -1.28917396095102890680e-12, 5.13963967348173025100e-12,
    -2.12996783842756842877e-11, 9.21831518760500529508e-11, -4.19035475934189648750e-10,
    2.01504975519703286596e-9, -1.03457624656780970260e-8, 5.74108412545004946722e-8,
    -3.50196060308781257119e-7, 2.40648494783721712015e-6, -1.93619797416608296024e-5,
    1.95215518471351631108e-4, -2.85781685962277938680e-3, 1.03923736576817238437e-1,
    2.72062619048444266945e0,
)


def _chbevl(y, coef):
    """Clenshaw sum of a Chebyshev series in Cephes' convention (½ the first term; highest first)."""
    b0, b1, b2 = jnp.full_like(y, coef[0]), jnp.zeros_like(y), jnp.zeros_like(y)
    for c in coef[1:]:  # a fixed, short unrolled loop over coefficients, not over data
        b2, b1 = b1, b0
        b0 = y * b1 - b2 + c
    return 0.5 * (b0 - b2)


def _split(x):
    """Safe arguments for the two branches (x ≤ 2 and x > 2), so neither produces NaN (double where)."""
    small = x <= 2.0
    xs = jnp.where(small, x, 1.0)
    xl = jnp.where(small, 4.0, x)
    return small, xs, xl


def _x_log_half_x(x):
    """x·log(x/2), continuous at 0 (value 0) with a finite gradient there."""
    pos = x > 0.0
    xp = jnp.where(pos, x, 1.0)
    return jnp.where(pos, xp * jnp.log(0.5 * xp), 0.0)


@jax.custom_jvp
def k0e(x: Values):
    """Exponentially scaled K0: ``exp(x) K0(x)``."""
    x = jnp.asarray(x, dtype=float)
    small, xs, xl = _split(x)
    lo = (_chbevl(xs * xs - 2.0, _K0_A) - jnp.log(0.5 * xs) * i0(xs)) * jnp.exp(xs)
    hi = _chbevl(8.0 / xl - 2.0, _K0_B) / jnp.sqrt(xl)
    return jnp.where(small, lo, hi)


@jax.custom_jvp
def k1e(x: Values):
    """Exponentially scaled K1: ``exp(x) K1(x)``."""
    x = jnp.asarray(x, dtype=float)
    small, xs, xl = _split(x)
    lo = (jnp.log(0.5 * xs) * i1(xs) + _chbevl(xs * xs - 2.0, _K1_A) / xs) * jnp.exp(xs)
    hi = _chbevl(8.0 / xl - 2.0, _K1_B) / jnp.sqrt(xl)
    return jnp.where(small, lo, hi)


@k0e.defjvp
def _k0e_jvp(primals, tangents):
    (x,), (dx,) = primals, tangents
    a, b = k0e(x), k1e(x)
    return a, (a - b) * dx  # d/dx e^x K0 = e^x (K0 − K1)


@k1e.defjvp
def _k1e_jvp(primals, tangents):
    (x,), (dx,) = primals, tangents
    a, b = k0e(x), k1e(x)
    return b, (b - a - b / x) * dx  # d/dx e^x K1 = e^x (K1 − K0 − K1/x)


def k0(x: Values):
    """Modified Bessel function of the second kind, order 0 (x > 0).

    Parameters
    ----------
    x : float or Array
        Argument x > 0 (dimensionless), any shape.

    Returns
    -------
    Array
        K0(x), shape of ``x``.
    """
    x = jnp.asarray(x, dtype=float)
    return k0e(x) * jnp.exp(-x)


def k1(x: Values):
    """Modified Bessel function of the second kind, order 1 (x > 0).

    Parameters
    ----------
    x : float or Array
        Argument x > 0 (dimensionless), any shape.

    Returns
    -------
    Array
        K1(x), shape of ``x``.
    """
    x = jnp.asarray(x, dtype=float)
    return k1e(x) * jnp.exp(-x)


def alpha_t(x: Values):
    """The NMRI draft factor α_T(x) = π²I₁²(x) / (π²I₁²(x) + K₁²(x)), x = k_e·d ≥ 0, elementwise.

    Never forms I₁, K₁ where they over/underflow: for x ≤ 2, with r = π I₁/K₁ = π·xI₁/(xK₁) and
    xK₁ = x log(x/2) I₁ + (Chebyshev series), finite at x = 0, α_T = r²/(1 + r²) → π²x⁴/4 as x → 0
    (0 at x = 0, with a finite gradient); for x > 2, with q = K₁/(πI₁) = k1e·e^(−2x)/(π·i1e),
    α_T = 1/(1 + q²) → 1. Values and gradients are finite for every x ≥ 0.

    Parameters
    ----------
    x : float or Array
        k_e·d ≥ 0 (dimensionless; encounter wavenumber [1/m] times draft [m]), any shape.

    Returns
    -------
    Array
        α_T in [0, 1] (dimensionless), shape of ``x``.
    """
    x = jnp.asarray(x, dtype=float)
    small, xs, xl = _split(x)
    xs = jnp.where(small, jnp.maximum(x, 0.0), 1.0)
    i1s = i1(xs)
    x_k1 = _x_log_half_x(xs) * i1s + _chbevl(xs * xs - 2.0, _K1_A)
    r = jnp.pi * xs * i1s / x_k1
    q = k1e(xl) * jnp.exp(-2.0 * xl) / (jnp.pi * i1e(xl))
    return jnp.where(small, r * r / (1.0 + r * r), 1.0 / (1.0 + q * q))
