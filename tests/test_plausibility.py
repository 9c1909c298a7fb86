"""Plausibility of every hull read (issue 62 item 1): a Wigley mesh written in millimetres, centimetres or inches,
lying on its side (y up), upside down (z down), standing on its stern or with its origin amidships gets one
``HullWarning`` line naming the cause and the fix (and the fix works); the ship at full scale, a 1:30 model, every
shipped example hull and every config's parent get none; the CLI prints the line as a warning and ``--strict``
refuses the hull (exit code 2). And the small bad inputs of the same issue: ``waves --speed 0`` and a
``stability --kg`` above the deck are one-line errors."""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import HULLS, MESH_HULLS, REPO

from hullopt.errors import HullError, HullWarning
from hullopt.geometry import Sections, hull_mesh
from hullopt.models import load_hull, plausibility_warnings, wigley

FAST = "n=41&m=24"  # a coarse slicing: the checks do not depend on it


@pytest.fixture(scope="module")
def meshes(tmp_path_factory) -> Path:
    """The Wigley L 100 m, B 10 m, T 6.25 m, D 10 m as a closed mesh (no hullopt header: nothing but its
    vertices tells its size), written as exported in other units and axes."""
    folder = tmp_path_factory.mktemp("meshes")
    ship = hull_mesh(wigley(L=100.0, B=10.0, T=6.25, D=10.0, n=41, m=21))
    ways = {
        "full": lambda v: v, "mm": lambda v: 1000 * v, "cm": lambda v: 100 * v, "inches": lambda v: v / 0.0254,
        "model30": lambda v: v / 30,
        "yup": lambda v: v[:, [0, 2, 1]] * [1, 1, -1],  # the file's y up, its z to starboard
        "zdown": lambda v: v * [1, -1, -1],  # the file's z down (and y to starboard)
        "standing": lambda v: v[:, [2, 1, 0]],  # the length along the file's z
        "amidships": lambda v: v - [50, 0, 6.25],  # origin amidships on the waterline
    }
    for name, f in ways.items():
        m = ship.copy()
        m.vertices = f(np.asarray(m.vertices))
        m.export(folder / f"{name}.stl")
    return folder


def _read(spec: str):
    """``load_hull(spec)`` and the HullWarnings it issued."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", HullWarning)
        hull = load_hull(spec)
    return hull, [str(w.message) for w in caught if issubclass(w.category, HullWarning)]


@pytest.mark.parametrize("name, words, fixed", [
    ("mm", ["Lpp 100000 m is longer than any ship", "a mesh in millimetres?", "?scale=0.001 (Lpp 100 m)"],
     "scale=0.001"),
    ("cm", ["Lpp 10000 m", "centimetres", "?scale=0.01 (Lpp 100 m)"], "scale=0.01"),
    ("inches", ["Lpp 3940 m", "inches", "?scale=0.0254 (Lpp 100 m)"], "scale=0.0254"),
    ("yup", ["symmetric about z = 0", "the file's y up", "?axes=x,-z,y"], "axes=x,-z,y"),
    ("zdown", ["lowest quarter of its height", "upside down", "?axes=x,-y,-z"], "axes=x,-y,-z"),
    ("standing", ["longer up (z)", "than along x, 10 m", "?axes=z,y,x"], "axes=z,y,x"),
    ("amidships", ["origin is not at the AP on the baseline", "?shift=50,0,6.25"], "shift=50,0,6.25"),
])
def test_a_misread_mesh_gets_one_line_naming_the_fix_and_the_fix_works(meshes, name, words, fixed):
    spec = f"{meshes / name}.stl?{FAST}"
    hull, issued = _read(spec)
    assert len(issued) == 1 and list(hull.warnings) == issued, issued
    line = issued[0]
    assert line.startswith(f"{name}.stl: ") and "\n" not in line
    assert all(w in line for w in words), line
    hull, issued = _read(f"{spec}&{fixed}")
    assert issued == [] and hull.warnings == ()
    assert float(hull.sections.lpp) == pytest.approx(100.0, rel=1e-3)


def test_the_ship_and_a_model_of_it_get_none(meshes):
    """The full-scale ship reads without a word; so does a 1:30 model (Lpp 3.33 m): a towing-tank model is read at
    model scale, which is right for a model (``?scale=30`` gives the ship), and a ship's draft on it is refused
    with that hint."""
    for name, lpp in (("full", 100.0), ("model30", 100 / 30)):
        hull, issued = _read(f"{meshes / name}.stl?{FAST}")
        assert issued == [] and float(hull.sections.lpp) == pytest.approx(lpp, rel=1e-3)
    with pytest.raises(HullError, match=r"model-scale file\? give the spec its scale"):
        hull.check_draft(6.25)


def test_a_builtin_states_its_dimensions_and_is_not_judged():
    hull, issued = _read("builtin:box?L=100000&B=1&D=1")
    assert issued == [] and hull.warnings == ()


def test_the_fix_is_worded_for_the_source():
    """An offsets table or a parent has no ``?scale=``: its own units are named instead."""
    s = wigley(L=100.0, B=10.0, T=6.25, D=10.0, n=21, m=11)
    mm = Sections(x=1000 * np.asarray(s.x), yz=1000 * np.asarray(s.yz), lpp=np.float64(1e5))
    [table] = plausibility_warnings(mm, None, "yard/offsets.csv")
    assert table.startswith("offsets.csv: Lpp 100000 m")
    assert "a table in millimetres? write it in metres: ×0.001 (Lpp 100 m)" in table
    [parent] = plausibility_warnings(mm, None, "parent:mine.json")
    assert "give it in metres: ×0.001 (Lpp 100 m)" in parent and "?scale" not in parent
    assert plausibility_warnings(s, 6.25, "wigley.stl") == []
    # a design draft that does not fit the hull: judged by B/T, T/Lpp, D/T and ∇/Lpp³
    found = plausibility_warnings(s, 0.05, "wigley.stl")
    assert any(w.startswith("wigley.stl: B/T 200 at the design draft 0.05 m is far outside ships' 1–10")
               for w in found), found


def _example_specs() -> list[tuple[str, tuple[float | None, ...]]]:
    """Every shipped example hull as the docs and tests read it (with the design draft the tests give it), the
    raw model-scale meshes, the library parents and every config's parent at the config's draft: each spec once,
    with the drafts to judge it at (a mesh sliced coarsely: the checks do not depend on it)."""
    specs = [(f"{HULLS / name}?{params}", draft) for name, params, draft in MESH_HULLS.values()]
    specs += [(f"{HULLS / 'kvlcc2_model_half_open_from_igs.stl.gz'}?scale=58&lpp=320", 20.8),
              (f"{HULLS / 'wigley_openfoam.stl.gz'}?scale=100&shift=50,0,6.25&lpp=100", 6.25),
              (str(HULLS / "series60_cb060_todd1963.csv"), None),
              (str(REPO / "hullopt/data/offsets/seed003_table1.csv"), None)]
    models = ("DTC-scaled.stl.gz", "kcs_model_closed_from_igs.stl.gz", "kvlcc2_model_half_open_from_igs.stl.gz")
    specs += [(str(HULLS / name), None) for name in models]  # as they are: models at 1:59.4, 1:31.6, 1:58
    specs += [(f"parent:{name}", None) for name in ("dtc", "tanker", "wigley", "seed003")]
    for path in sorted((REPO / "configs").glob("*.toml")):  # [hull] parent, a wind config's hull, deform's parent
        data = tomllib.loads(path.read_text())
        hull = data.get("hull", {})
        parent, draft = (hull.get("parent"), hull.get("draft")) if isinstance(hull, dict) else (hull, data.get("draft"))
        parent = parent or data.get("parent")
        if parent is None:
            continue
        base = parent.partition("?")[0]
        spec = f"parent:{parent}" if "/" not in base and "." not in base else str((path.parent / parent).resolve())
        specs.append((spec, draft))
    drafts: dict[str, set] = {}
    for spec, draft in specs:
        mesh = ".stl" in spec and "n=" not in spec
        drafts.setdefault(f"{spec}{'&' if '?' in spec else '?'}{FAST}" if mesh else spec, set()).add(draft)
    return [(spec, tuple(sorted(d, key=lambda t: t or 0.0))) for spec, d in drafts.items()]


@pytest.mark.parametrize("spec, drafts", _example_specs(), ids=lambda v: Path(str(v).partition("?")[0]).name
                         if isinstance(v, str) else "")
def test_every_shipped_hull_gets_no_warning(spec, drafts):
    hull, issued = _read(spec)
    assert issued == [] and hull.warnings == ()
    for draft in drafts:
        assert plausibility_warnings(hull.sections, draft or hull.design_draft, spec) == [], draft


@pytest.mark.slow
def test_the_iges_example_gets_no_warning():
    pytest.importorskip("gmsh")
    hull, issued = _read(f"{HULLS / 'kcs_ship_kcs_overture.igs'}?scale=31.6&lpp=230")
    assert issued == [] and plausibility_warnings(hull.sections, 10.8, "kcs.igs") == []


def test_a_kept_parent_warns_again(meshes, monkeypatch, tmp_path):
    """A config's parent read from a mesh in millimetres warns when its features are extracted and again when they
    are read back from the cache (the extraction itself is stubbed: any parent will do)."""
    from hullopt.models import load_parent
    from hullopt.study import _hulls, run_parent

    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path))
    monkeypatch.setattr(_hulls, "extract_faithful", lambda *a: (load_parent("wigley"), {"met": True}))
    spec = f"{meshes / 'mm.stl'}?{FAST}"
    for _ in range(2):  # extracted, then kept
        with pytest.warns(HullWarning, match=r"mm\.stl: Lpp 100000 m .*\?scale=0\.001"):
            run_parent(spec, 6250.0)
    assert len(list((tmp_path / "parents").glob("*.json"))) == 1


# ----------------------------------------------------------------------------------------------- the CLI


def test_the_cli_prints_one_warning_line_and_strict_refuses(cli, meshes, tmp_path, monkeypatch):
    spec = f"{meshes / 'mm.stl'}?{FAST}"
    code, out, err = cli("export", spec, tmp_path / "h.obj")
    assert code == 0 and "wrote" in out
    assert err.count("\n") == 1 and err.startswith("warning: mm.stl: Lpp 100000 m") and "?scale=0.001" in err
    monkeypatch.setattr("hullopt.app.commands.hydro.sections_like", lambda spec: None)  # nothing to compile
    code, out, err = cli("hydro", spec, "--draft", "6.25", "--strict")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("error: mm.stl: Lpp 100000 m") and err.rstrip().endswith("(refused by --strict)")
    code, _, err = cli("export", f"{meshes / 'full.stl'}?{FAST}", tmp_path / "f.obj", "--strict")
    assert code == 0 and err == ""
    with pytest.warns(HullWarning):  # the CLI's --strict ended with its command
        load_hull(spec)


def test_waves_refuses_zero_speed_as_resistance_does(cli):
    code, out, err = cli("waves", "builtin:wigley?L=100&B=10&T=6.25&D=10", "--speed", "0")
    assert code == 2 and err.count("\n") == 1 and "--speed 0: expected a positive number of knots" in err


def test_stability_refuses_a_kg_above_the_deck(cli):
    from hullopt.app.commands.stability import check_kg

    code, _, err = cli("stability", "builtin:box?L=100&B=20&D=10", "--displacement", "8200", "--kg", "12")
    assert code == 2 and err.count("\n") == 1
    assert "--kg 12 m is above the deck, 10 m above the baseline" in err and "--kg-above-deck" in err
    box = load_hull("builtin:box?L=100&B=20&D=10").sections
    check_kg(10.0, box)  # at the deck: accepted
    check_kg(12.0, box, above_deck=True)
