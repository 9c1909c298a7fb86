"""Kept sections of mesh hulls (``hullopt.models.load_hull(spec, cache=…)``, the CLI's ``$HULLOPT_CACHE/sections``):
a second load reads them back without reading or slicing the mesh, and gives the very same sections; a changed
file or spec is sliced again."""

import numpy as np
import pytest

from hullopt.errors import HullError
from hullopt.geometry import to_trimesh
from hullopt.models import _specs, load_hull, wigley

SPEC = "?lpp=100&n=21&m=24"  # a coarse slicing keeps the test fast


def _write_wigley(path, beam: float = 10.0) -> None:
    """A closed Wigley mesh (a small STL) written independently of the reader under test."""
    to_trimesh(wigley(100.0, beam, 6.25, 10.0, n=21, m=16)).export(path)


@pytest.fixture
def mesh(tmp_path):
    path = tmp_path / "wigley.stl"
    _write_wigley(path)
    return path


def _same(a, b) -> None:
    for f in ("x", "yz", "lpp"):
        np.testing.assert_array_equal(np.asarray(getattr(a.sections, f)), np.asarray(getattr(b.sections, f)))
    assert (a.name, a.design_draft) == (b.name, b.design_draft)


def _no_slicing(monkeypatch) -> None:
    monkeypatch.setattr(_specs, "read_mesh", lambda *a, **k: pytest.fail("the mesh was read again"))
    monkeypatch.setattr(_specs, "slice_mesh", lambda *a, **k: pytest.fail("the mesh was sliced again"))


def test_a_second_load_reads_the_kept_sections(mesh, tmp_path, monkeypatch):
    cache = tmp_path / "cache" / "sections"
    plain = load_hull(f"{mesh}{SPEC}")  # no cache: nothing kept
    assert not cache.exists()
    first = load_hull(f"{mesh}{SPEC}", cache=cache)
    assert len(list(cache.glob("*.npz"))) == 1
    _same(plain, first)
    _no_slicing(monkeypatch)
    again = load_hull(f"{mesh}{SPEC}", cache=cache)
    _same(first, again)
    # the key is the content, not the path: a copy under another name hits and keeps its own name
    copy = tmp_path / "copy.stl"
    copy.write_bytes(mesh.read_bytes())
    other = load_hull(f"{copy}{SPEC}", cache=cache)
    assert other.name == "copy.stl"
    np.testing.assert_array_equal(np.asarray(other.sections.yz), np.asarray(first.sections.yz))


def test_a_changed_file_or_spec_is_sliced_again(mesh, tmp_path):
    cache = tmp_path / "sections"
    first = load_hull(f"{mesh}{SPEC}", cache=cache)
    _write_wigley(mesh, beam=12.0)  # same name, new content
    wider = load_hull(f"{mesh}{SPEC}", cache=cache)
    assert float(np.max(np.asarray(wider.sections.yz)[..., 0])) == pytest.approx(6.0, rel=1e-3)
    assert float(np.max(np.asarray(first.sections.yz)[..., 0])) == pytest.approx(5.0, rel=1e-3)
    finer = load_hull(f"{mesh}?lpp=100&n=23&m=24", cache=cache)
    assert finer.sections.n == 23
    scaled = load_hull(f"{mesh}{SPEC}&scale=2", cache=cache)
    assert float(np.max(np.asarray(scaled.sections.yz)[..., 0])) == pytest.approx(12.0, rel=1e-3)
    assert len(list(cache.glob("*.npz"))) == 4


def test_a_corrupt_or_foreign_file_is_sliced_again_and_rewritten(mesh, tmp_path):
    cache = tmp_path / "sections"
    first = load_hull(f"{mesh}{SPEC}", cache=cache)
    (kept,) = cache.glob("*.npz")
    kept.write_bytes(b"not sections")
    _same(first, load_hull(f"{mesh}{SPEC}", cache=cache))
    assert kept.read_bytes() != b"not sections"
    # another key's sections under this file name (a truncated digest's collision): not trusted
    other = tmp_path / "other.stl"
    _write_wigley(other, beam=12.0)
    load_hull(f"{other}{SPEC}", cache=cache)
    (theirs,) = set(cache.glob("*.npz")) - {kept}
    kept.write_bytes(theirs.read_bytes())
    _same(first, load_hull(f"{mesh}{SPEC}", cache=cache))


def test_errors_are_not_kept(mesh, tmp_path):
    cache = tmp_path / "sections"
    with pytest.raises(HullError, match="unknown parameter"):
        load_hull(f"{mesh}?lpp=100&bogus=1", cache=cache)
    with pytest.raises(HullError, match="too few"):
        load_hull(f"{mesh}?lpp=100&n=21&m=2", cache=cache)
    assert not list(cache.glob("*.npz")) if cache.exists() else True


def test_the_cli_keeps_sections_in_its_cache(mesh, tmp_path, monkeypatch, cli):
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path / "hc"))
    code, out, _ = cli("hydro", f"{mesh}{SPEC}", "--draft", "5", "--json")
    assert code == 0 and len(list((tmp_path / "hc" / "sections").glob("*.npz"))) == 1
    _no_slicing(monkeypatch)
    assert cli("hydro", f"{mesh}{SPEC}", "--draft", "5", "--json")[1] == out
