"""``hullopt motions``: the KCS added-resistance curve at Fn 0.26 in head seas against the towing-tank range
(issue 16: σ_aw peak 6–14 at λ/L 0.95–1.4, short-wave level 1.5–3.5, the motion part dominant at the peak;
the KCS experiments: Simonsen et al. 2013, "EFD and CFD for KCS heaving and pitching in
regular head waves", J. Mar. Sci. Technol. 18, 435–459), JSON keys, the plot and bad input."""

import json

import numpy as np
import pytest

import hullopt.app.cli as cli

KCS = "examples/hulls/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230&n=61"
KEYS = ("lambda_over_l", "omega", "omega_e", "heave", "pitch", "sigma_aw", "sigma_aw_motion", "sigma_aw_reflection")


@pytest.fixture(autouse=True)
def _no_global_config(monkeypatch):
    monkeypatch.setattr(cli, "configure_jax", lambda: None)  # tests already run in float64


def run(capsys, *args):
    code = cli.main(["motions", *args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
@pytest.mark.slow
def test_kcs_added_resistance_curve_in_the_tank_range(capsys, hulls, tmp_path, monkeypatch):
    monkeypatch.chdir(hulls.parent.parent)
    png = tmp_path / "kcs.png"
    code, out, err = run(capsys, KCS, "--speed", "24", "--draft", "10.8", "--kg", "7.28",
                         "--lambdas", "0.3,0.4,0.95,1.1,1.2,1.3,1.4,2.0", "--json", "--plot", str(png))
    assert code == 0, err
    d = json.loads(out)
    for key in KEYS:
        assert len(d[key]) == 8
    lam, sig = np.asarray(d["lambda_over_l"]), np.asarray(d["sigma_aw"])
    motion, refl = np.asarray(d["sigma_aw_motion"]), np.asarray(d["sigma_aw_reflection"])
    np.testing.assert_allclose(motion + refl, sig, rtol=1e-12)
    assert d["fn"] == pytest.approx(0.26, abs=0.001)
    peak = int(np.argmax(sig))
    assert 0.95 <= lam[peak] <= 1.4 and 6.0 <= sig[peak] <= 14.0  # measured 11.4 at λ/L 1.1
    assert motion[peak] > refl[peak]  # measured 9.67 vs 1.74
    assert np.all((1.5 <= sig[:2]) & (sig[:2] <= 3.5))  # λ/L 0.3, 0.4: measured 3.13, 3.24
    heave, pitch = np.asarray(d["heave"]), np.asarray(d["pitch"])
    # long waves (λ/L 2): measured 0.99 and 1.07 (heave was 1.10 while a spurious transom term stood at the
    # first wet strip)
    assert heave[-1] == pytest.approx(1.0, abs=0.1) and pitch[-1] == pytest.approx(1.1, abs=0.1)
    assert heave[0] < 0.05 and pitch[0] < 0.05  # short waves
    omega, omega_e = np.asarray(d["omega"]), np.asarray(d["omega_e"])
    np.testing.assert_allclose(omega_e, omega + omega**2 / 9.80665 * d["speed"], rtol=1e-12)  # head seas
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("args,needle", [
    (["--speed", "-3"], "--speed"),
    (["--speed", "10", "--lambdas", "0.5,x"], "--lambdas"),
    (["--speed", "10", "--lambdas", "0.5,-1"], "--lambdas"),
    (["--speed", "10", "--lambdas", "1:2"], "--lambdas"),
    (["--speed", "10", "--kyy", "2"], "--kyy"),
    (["--speed", "10", "--kg", "-1"], "--kg"),
    (["--speed", "10", "--heading", "400"], "--heading"),
])
def test_bad_input_is_one_line_error(capsys, args, needle):
    code, out, err = run(capsys, "builtin:wigley?L=100&B=10&T=6.25&D=9&n=21&m=11", "--draft", "6.25", *args)
    assert code != 0 and needle in err + out


@pytest.mark.parametrize("speed_kn,warned", [(12.0, False), (18.5, True)])
@pytest.mark.slow
def test_warns_outside_the_validated_froude_range(capsys, speed_kn, warned):
    # Fn 0.197 and 0.304 on a 100 m Wigley (L/B 10): GB's motion part is 1.8× Journée's tank peaks at Fn 0.3.
    code, out, err = run(capsys, "builtin:wigley?L=100&B=10&T=6.25&D=9&n=21&m=11", "--draft", "6.25",
                         "--speed", str(speed_kn), "--lambdas", "1.0", "--json")
    assert code == 0, err
    assert ("warning:" in err and "Fn 0.30 > 0.25" in err) == warned
    json.loads(out)  # the warning stays off stdout
