"""Hull specs every command takes (library parents by name, run folders) and drafts up to the deck."""

import json
import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.errors import HullError
from hullopt.geometry import Sections, level_widths, section_integrals
from hullopt.hydro import hydrostatics
from hullopt.models import load_hull, load_parent


@pytest.mark.parametrize("name", ["dtc", "tanker", "wigley", "seed003"])
def test_library_parent_is_a_hull_for_every_command(name):
    h = load_hull(f"parent:{name}")
    fh = load_parent(name)
    assert h.design_draft == fh.design_draft
    assert np.array_equal(np.asarray(h.sections.yz), np.asarray(fh.sections().yz))
    assert load_hull(f"parent:{name}?q=4").sections.m > h.sections.m


def test_parent_specs_from_the_console(cli, tmp_path):
    code, out, err = cli("hydro", "parent:wigley", "--json")
    assert code == 0, err
    assert json.loads(out)["cb"] == pytest.approx(4 / 9, rel=2e-3)  # the library's Wigley at its design draft
    code, _, err = cli("features", "parent:wigley", "--out", tmp_path / "f" / "new")  # creates its folder
    assert code == 0, err
    assert (tmp_path / "f" / "new" / "features.json").stat().st_size > 0
    code, out, err = cli("hydro", f"parent:{tmp_path / 'f' / 'new' / 'features.json'}", "--json")
    assert code == 0 and json.loads(out)["cb"] == pytest.approx(4 / 9, rel=2e-3)
    code, _, err = cli("export", "parent:wigley", tmp_path / "e" / "w.stl")  # creates its folder
    assert code == 0 and (tmp_path / "e" / "w.stl").stat().st_size > 0
    for spec, message in (("parent:nope", "unknown parent 'nope'"), ("dtc", "the library parent is parent:dtc"),
                          ("parent:wigley?n=3", "unknown parameter 'n'"), (str(tmp_path), "not a run folder")):
        code, _, err = cli("hydro", spec)
        assert code == 2 and message in err and err.count("\n") == 1, err


def test_the_library_reads_every_spec_but_run_folders(tmp_path):
    """hullopt.models.load_hull needs no app: the same errors as the CLI's; a folder is the CLI's to read."""
    with pytest.raises(HullError, match="run folders are read by hullopt.study.load_hull"):
        load_hull(str(tmp_path))
    for spec, message in (("builtin:wigley?L=100&B=10&T=6.25", "missing parameter D"),
                          ("builtin:box?L=100&B=20&D=x", "parameter D='x' is not a valid float"),
                          ("builtin:box?L=1&L=2&B=2&D=1", "parameter L given twice"),
                          (str(tmp_path / "none.stl"), "no such file or run folder")):
        with pytest.raises(HullError, match=re.escape(f"hull {spec!r}: {message}")):
            load_hull(spec)


def test_widths_at_a_vertex_are_the_limit_from_below():
    """A level through a vertex counts it once: on a rising chain, at a local top (the deck edge: the deck
    closes the section) and at a local bottom the width is the limit from below."""
    poly = jnp.array([[0.0, 0.0], [2.0, 1.0], [3.0, 2.0], [1.0, 3.0], [4.0, 4.0], [0.0, 4.0]])  # closed polygon
    levels = jnp.array([1.0, 2.0, 3.0, 4.0])
    below = np.asarray(level_widths(poly, levels - 1e-9))
    assert np.asarray(level_widths(poly, levels)) == pytest.approx(below, abs=1e-8)
    sec = Sections(x=jnp.array([0.0, 1.0]), yz=jnp.stack([poly[:-1], poly[:-1]]), lpp=jnp.asarray(1.0))
    assert np.asarray(section_integrals(sec, 4.0).width) == pytest.approx([4.0, 4.0])


def test_hydrostatics_at_the_deck_are_exact():
    """Box and Wigley (vertical sides above the waterline) at T = D: Cb ≤ 1 by definition, closed forms."""
    hydro = jax.jit(hydrostatics)  # compiled: the same integrals as op by op, a few times faster here
    box = load_hull("builtin:box?L=100&B=20&D=10").sections
    h = hydro(box, 10.0)
    assert float(h.cb) == pytest.approx(1.0, abs=1e-12) and float(h.bwl) == pytest.approx(20.0)
    assert float(h.bmt) == pytest.approx(20.0**2 / (12 * 10.0), rel=1e-12)
    w = load_hull("builtin:wigley?L=100&B=10&T=6.25&D=10").sections
    h = hydro(w, 10.0)
    volume = 4 / 9 * 100 * 10 * 6.25 + 2 / 3 * 100 * 10 * 3.75  # below the DWL + the wall-sided part above
    assert float(h.volume) == pytest.approx(volume, rel=1e-4) and float(h.bwl) == pytest.approx(10.0)
    assert float(h.cb) == pytest.approx(volume / (100 * 10 * 10), rel=1e-4) and float(h.cm) <= 1.0


def test_drafts_above_the_deck_are_refused_and_curves_stop_below_it(cli, tmp_path, monkeypatch):
    code, _, err = cli("hydro", "builtin:box?L=100&B=20&D=10", "--draft", "10.5")
    assert code == 2 and "above the deck" in err and "scale" not in err
    code, _, err = cli("hydro", "builtin:box?L=1&B=0.2&D=0.1", "--draft", "6")  # a model read as a ship
    assert code == 2 and "a model-scale file? give the spec its scale, FILE?scale=S" in " ".join(err.split())
    code, out, err = cli("hydro", "builtin:box?L=100&B=20&D=10", "--draft", "10", "--json")
    assert code == 0 and json.loads(out)["cb"] == pytest.approx(1.0)
    import hullopt.drawing

    seen, block = [], []
    monkeypatch.setattr(hullopt.drawing, "plot_hydrostatic_curves", lambda t, path, name="", **kw: seen.append(t.draft))
    real_plan = hullopt.drawing.lines_plan
    monkeypatch.setattr(hullopt.drawing, "lines_plan", lambda *a, **kw: block.append(kw) or real_plan(*a, **kw))
    code, _, err = cli("lines", "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=21", "--out", tmp_path / "l.png",
                       "--curves", tmp_path / "c.png")
    assert code == 0, err
    assert len(seen) == 1 and len(seen[0]) == 20 and float(np.max(seen[0])) < 10.0
    # the title block's particulars are the DWL's (one table with the curves' drafts): the Wigley's closed form
    assert block[0]["displacement"] == pytest.approx(1.025 * 4 / 9 * 100 * 10 * 6.25, rel=2e-3)
    assert block[0]["cb"] == pytest.approx(4 / 9, rel=2e-3)
