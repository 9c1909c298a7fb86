"""The wetted surface S, the waterline length Lwl and the immersed transom area A_T against independent references:

* three real closed meshes (DTC, KCS, DTMB 5415) read into Sections at the default slicing, against trimesh's
  exact immersed area of the same mesh (cut at the draft, no waterplane cap) and its waterline's extent; a finer
  slicing is no further away;
* the Wigley hull against the surface integral of its closed form (scipy), and Lwl = L;
* a box with a raked stem, whose waterline ends at L + T·tan θ (by hand), and a box's transom, A_T = B·T;
* the DTC at a draft that immerses its vertical transom, against the area of the mesh's transom faces;
* A_T = B·T of a box with a raked or a curved transom, and the DTMB 5415's raked transom against the
  projection of its mesh's aft faces;
* the gradient of S in every offset against central differences.
"""

import gzip
import io

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate
import trimesh
from conftest import HULLS, MESH_HULLS
from helpers import check_grad

from hullopt.geometry import Sections, longitudinal_integrals, wetted_surface
from hullopt.hydro import hydrostatics
from hullopt.models import box, load_hull, wigley


def _mesh(name: str) -> tuple[trimesh.Trimesh, float]:
    """The hull's mesh at full scale (m) and its design draft."""
    file, params, draft = MESH_HULLS[name]
    mesh = trimesh.load(io.BytesIO(gzip.decompress((HULLS / file).read_bytes())), file_type="stl", force="mesh")
    scale = dict(p.split("=") for p in params.split("&")).get("scale")
    if scale:
        mesh.apply_scale(float(scale))
    return mesh, draft


def _exact(mesh: trimesh.Trimesh, draft: float) -> tuple[float, float]:
    """The mesh's immersed area below z = draft (the hull's own faces, clipped exactly; no waterplane cap) and the
    length of its waterline (the x extent of its cut at the draft)."""
    wet = trimesh.intersections.slice_mesh_plane(mesh, plane_normal=[0, 0, -1], plane_origin=[0, 0, draft], cap=False)
    cut = trimesh.intersections.mesh_plane(mesh, [0, 0, 1], [0, 0, draft])
    return float(wet.area), float(np.ptp(cut[..., 0]))


@pytest.fixture(scope="module", params=sorted(MESH_HULLS))
def mesh_hull(request):
    name = request.param
    file, params, _ = MESH_HULLS[name]
    mesh, draft = _mesh(name)
    return name, f"{HULLS / file}?{params}", draft, *_exact(mesh, draft)


@pytest.mark.slow
def test_wetted_surface_and_lwl_of_real_meshes_at_the_default_slicing(mesh_hull):
    """S within 0.1 % of the exact immersed mesh area (measured −0.056 % DTC, −0.065 % KCS, −0.079 % DTMB 5415;
    the triangles joining point j of one station to point j of the next gave +0.42 %, +0.69 %, +1.41 %), and a
    finer slicing no further away (−0.033 %, −0.058 %, −0.071 % at 301 × 144); Lwl within 0.03 % of the mesh's
    waterline (measured +0.018 %, 0.000 %, 0.000 %; station spacing gave +0.31 %, +0.22 %, +0.17 %)."""
    name, spec, draft, s_exact, lwl_exact = mesh_hull
    errors = []
    for resolution in ("", "&n=301&m=144"):
        sections = load_hull(spec + resolution).sections
        h = jax.jit(hydrostatics)(sections, draft)
        errors.append(float(h.wetted_surface) / s_exact - 1.0)
        if not resolution:
            assert abs(errors[0]) < 1e-3, (name, errors)
            assert float(h.lwl) == pytest.approx(lwl_exact, rel=3e-4), name
    assert abs(errors[1]) <= abs(errors[0]), (name, errors)


def test_wigley_against_its_closed_form_surface_integral():
    """S = 2 ∫∫ √(1 + y_x² + y_z²) dx dz of y = (B/2)(1 − ξ²)(1 − ζ²) (Gauss–Legendre, checked by scipy's
    dblquad): −0.008 % with 21 × 21 points, −0.0003 % with 81 × 101 (the joined-triangle grid gave −0.11 %,
    −0.006 %); Lwl = L exactly."""
    L, B, T, D = 100.0, 10.0, 6.25, 10.0

    def integrand(z, x):
        xi, zeta = 2 * (x - L / 2) / L, (T - z) / T
        y_x = (B / 2) * (-4 * xi / L) * (1 - zeta**2)
        y_z = (B / 2) * (1 - xi**2) * (2 * zeta / T)
        return np.sqrt(1 + y_x**2 + y_z**2)

    u, w = np.polynomial.legendre.leggauss(200)  # a smooth integrand: Gauss–Legendre to ~1e-12
    xq, zq = np.meshgrid(L / 2 * (u + 1), T / 2 * (u + 1), indexing="ij")
    exact = 2 * (L / 2) * (T / 2) * float(w @ integrand(zq, xq) @ w)
    assert exact == pytest.approx(scipy.integrate.dblquad(integrand, 0, L, 0, T, epsrel=1e-8)[0] * 2, rel=1e-8)
    ws = jax.jit(wetted_surface)
    coarse = float(ws(wigley(L, B, T, D, n=21, m=21), T))
    fine = float(ws(wigley(L, B, T, D, n=81, m=101), T))
    assert coarse == pytest.approx(exact, rel=2e-4)
    assert fine == pytest.approx(exact, rel=1e-5)
    assert abs(fine - exact) < abs(coarse - exact)
    li = jax.jit(longitudinal_integrals)(wigley(L, B, T, D, n=21, m=21), T)
    assert float(li.lwl) == pytest.approx(L, rel=1e-12) and float(li.a_transom) == 0.0


def _raked_box(L: float, B: float, D: float, rake: float, n: int) -> Sections:
    """A box with a straight stem raked forward by ``rake`` [rad] from the vertical: forward of x = L each section
    starts at the stem's height (x − L)/tan(rake) (its bottom edge off the centre plane)."""
    x = np.linspace(0.0, L + D * np.tan(rake), n)
    z0 = np.clip((x - L) / np.tan(rake), 0.0, D)
    yz = np.stack([np.stack([np.zeros(n), z0], 1), np.stack([np.full(n, B / 2), z0], 1),
                   np.stack([np.full(n, B / 2), np.full(n, D)], 1)], axis=1)
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(L))


@pytest.mark.parametrize("n", [23, 40])
def test_lwl_of_a_raked_stem_by_hand_and_a_box_transom(n):
    """The waterline of a box with a stem raked 30° ends at L + T·tan 30° (the stations need not hit it); its
    transom (the aft end, wet) has A_T = B·T; so has a plain box's."""
    L, B, D, T, rake = 50.0, 8.0, 6.0, 3.7, np.radians(30.0)
    li = jax.jit(longitudinal_integrals)(_raked_box(L, B, D, rake, n), T)
    assert float(li.x_aft) == 0.0
    assert float(li.x_fwd) == pytest.approx(L + T * np.tan(rake), rel=1e-12)
    assert float(li.lwl) == pytest.approx(L + T * np.tan(rake), rel=1e-12)
    assert float(li.a_transom) == pytest.approx(B * T, rel=1e-12)
    assert float(jax.jit(hydrostatics)(box(80.0, 16.0, 9.0), 4.2).a_transom) == pytest.approx(16.0 * 4.2, rel=1e-13)


def test_immersed_transom_of_the_dtc_against_its_transom_faces():
    """At T = 18.85 m the DTC's vertical transom (x = −6.74 m) is immersed: A_T against the area of the mesh's
    aft-facing faces there (trimesh; 128.5 m²), measured −0.03 %; at the design draft 14.5 m it is dry (0)."""
    mesh, _ = _mesh("dtc")
    draft = 18.85
    wet = trimesh.intersections.slice_mesh_plane(mesh, plane_normal=[0, 0, -1], plane_origin=[0, 0, draft], cap=False)
    centres, normals = wet.triangles_center, wet.face_normals
    transom = (normals[:, 0] < -0.99) & (centres[:, 0] < mesh.bounds[0, 0] + 0.01)
    expected = float(wet.area_faces[transom].sum())
    assert expected == pytest.approx(128.5, rel=1e-2)  # the reference's own size
    file, params, _ = MESH_HULLS["dtc"]
    sections = load_hull(f"{HULLS / file}?{params}&n=101&m=80").sections
    a_transom = jax.jit(lambda t: longitudinal_integrals(sections, t).a_transom)
    assert float(a_transom(draft)) == pytest.approx(expected, rel=2e-3)
    assert float(a_transom(14.5)) == 0.0


def _box_with_transom(L: float, B: float, D: float, face, n: int) -> Sections:
    """A box whose aft end is the face ``x = face(z)`` [m from the AP] for ``0 ≤ z ≤ D`` (``face(D) = 0``, the
    face leaning forward going down): aft of the face's lower edge each section starts at the face's height
    there (its bottom edge off the centre plane)."""
    zs = np.linspace(0.0, D, 2001)
    xf = face(zs)  # decreasing in z
    x = np.linspace(0.0, L, n)
    z0 = np.interp(x, xf[::-1], zs[::-1], left=D, right=0.0)
    yz = np.stack([np.stack([np.zeros(n), z0], 1), np.stack([np.full(n, B / 2), z0], 1),
                   np.stack([np.full(n, B / 2), np.full(n, D)], 1)], axis=1)
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(L))


@pytest.mark.parametrize("n", [23, 101])
@pytest.mark.parametrize("shape", ["raked", "curved"])
def test_immersed_transom_of_a_raked_and_a_curved_box_transom(shape, n):
    """A_T = B·T (the face's projection on the transverse plane) for a box whose transom is raked 20° from the
    vertical, and for one curved in profile (a circular arc, vertical at the deck, 30° from the vertical at
    the keel); the stations do not hit the face's lower edge. Measured to round-off."""
    L, B, D, T = 50.0, 8.0, 6.0, 3.7
    if shape == "raked":
        face = lambda z: (D - z) * np.tan(np.radians(20.0))  # noqa: E731
    else:
        r = D / np.sin(np.radians(30.0))
        face = lambda z: r - np.sqrt(r**2 - (D - z) ** 2)  # noqa: E731
    s = _box_with_transom(L, B, D, face, n)
    a_t = jax.jit(lambda s, t: longitudinal_integrals(s, t).a_transom)
    assert float(a_t(s, T)) == pytest.approx(B * T, rel=1e-12)
    assert float(a_t(s, 7.0)) == pytest.approx(B * D, rel=1e-12)  # above the deck: the whole face
    g = jax.jit(jax.grad(lambda yz: longitudinal_integrals(Sections(s.x, yz, s.lpp), T).a_transom))(s.yz)
    assert np.all(np.isfinite(np.asarray(g)))


def test_immersed_transom_of_the_dtmb5415_against_its_mesh(dtmb5415):
    """The DTMB 5415's transom is raked (~20° from the vertical) and its lower edge is curved in plan (from
    0.03 m forward of the AP on the centre plane to ~0.5 m at the sides); at T = 6.15 m its face is ~0.45 m
    deep. A_T against the projection of the mesh's aft faces steeper than 45° there (trimesh: 4.06 m²; the
    flat face alone, steeper than 64°, 3.68 m²): measured +14 % at the default 201 stations (the rounded
    knuckle at the lower edge, ~0.2 m long, is below the station spacing and taken as a sharp corner), −3 %
    at 401. The previous rule (the aft end station's immersed area) gave 0. The gradient is finite."""
    spec, draft = dtmb5415
    mesh, _ = _mesh("dtmb5415")
    wet = trimesh.intersections.slice_mesh_plane(mesh, plane_normal=[0, 0, -1], plane_origin=[0, 0, draft], cap=False)
    normals, aft = wet.face_normals, wet.triangles_center[:, 0] < mesh.bounds[0, 0] + 5.0
    steep = aft & (normals[:, 0] < -np.sqrt(0.5))
    expected = float(np.sum(wet.area_faces[steep] * -normals[steep, 0]))
    assert expected == pytest.approx(4.06, abs=0.01)
    a_t = jax.jit(lambda s: longitudinal_integrals(s, draft).a_transom)
    coarse, fine = (load_hull(spec + res).sections for res in ("", "&n=401"))
    assert float(a_t(coarse)) == pytest.approx(expected, rel=0.16)
    assert float(a_t(fine)) == pytest.approx(expected, rel=0.05)
    g = jax.jit(jax.grad(lambda yz: longitudinal_integrals(Sections(coarse.x, yz, coarse.lpp), draft).a_transom))(
        coarse.yz
    )
    assert np.all(np.isfinite(np.asarray(g)))


@pytest.mark.slow
def test_wetted_surface_gradient_in_every_offset(dtmb5415):
    """dS/d(offsets) against central differences on a coarse slicing of the DTMB 5415 (sonar dome, bulb joints,
    a transom): finite everywhere, and equal where S is smooth."""
    spec, draft = dtmb5415
    s = load_hull(spec + "&n=21&m=24").sections
    yz0 = np.asarray(s.yz)
    off = np.flatnonzero(((yz0[..., 0] > 0.05) & (yz0[..., 1] < draft))[..., None].repeat(2, -1).reshape(-1))
    pick = np.random.default_rng(0).choice(off, 12, replace=False)  # coordinates of wet points off the centre plane

    def f(v):
        yz = s.yz.reshape(-1).at[pick].set(v).reshape(s.yz.shape)
        return wetted_surface(Sections(x=s.x, yz=yz, lpp=s.lpp), draft)

    v0 = np.asarray(s.yz).reshape(-1)[pick]
    check_grad(jax.jit(f), v0, rtol=1e-5, atol=1e-7, h=1e-6)
    assert np.all(np.isfinite(np.asarray(jax.grad(lambda yz: wetted_surface(Sections(s.x, yz, s.lpp), draft))(s.yz))))


@pytest.mark.slow
def test_wetted_surface_forward_reverse_and_vmap_agree():
    """The nearest-edge derivative (one search, gathers of the feet) gives the same directional derivative in
    forward (jax.jvp) and reverse mode (jax.grad · v), and vmap of the gradient equals the gradient of each hull,
    on a Wigley whose stations are perturbed (so the nearest edges are not the same-numbered ones)."""
    s = wigley(100.0, 10.0, 6.25, 10.0, n=11, m=9)
    rng = np.random.default_rng(1)
    f = lambda yz: wetted_surface(Sections(s.x, yz, s.lpp), 6.25)  # noqa: E731
    yz = s.yz * (1.0 + 0.05 * rng.uniform(-1, 1, s.yz.shape))
    v = jnp.asarray(rng.normal(size=s.yz.shape))
    grad = jax.jit(jax.grad(f))
    _, t = jax.jit(lambda a, b: jax.jvp(f, (a,), (b,)))(yz, v)
    g = grad(yz)
    assert np.all(np.isfinite(np.asarray(g)))
    np.testing.assert_allclose(float(t), float(jnp.sum(g * v)), rtol=1e-12)
    batch = jnp.stack([yz, s.yz, yz * 0.98])
    gb = jax.jit(jax.vmap(jax.grad(f)))(batch)
    for i in range(3):
        np.testing.assert_allclose(np.asarray(gb[i]), np.asarray(grad(batch[i])), rtol=1e-12, atol=1e-12)
