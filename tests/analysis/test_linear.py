"""Linear analysis of the crawler (§two-mass) with python-control, API and command line."""
import json

import numpy as np
import pytest

from musclesim import cli
from musclesim.analysis import linear_crawler, linear_sma_thermal
from musclesim.components.crawler.body import BodyParams


@pytest.mark.parametrize("m1, m2", [(0.2, 0.2), (0.3, 0.2), (0.15, 0.4)])
def test_controllability_ranks_and_subspace(m1, m2):
    r = linear_crawler.crawler(BodyParams(m1=m1, m2=m2))
    assert r["rank_fa_only"] == 2
    assert r["rank_all_inputs"] == 4
    expected = [[1, 0, -m1 / m2, 0], [0, 1, 0, -m1 / m2]]  # §two-mass
    np.testing.assert_allclose(r["controllable_subspace_fa_only"], expected, atol=1e-9)
    assert r["centre_of_mass_reachable_fa_only"] is False


def test_cli_json_and_text(capsys):
    assert cli.main(["linear", "crawler", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["rank_fa_only"], report["rank_all_inputs"]) == (2, 4)
    assert cli.main(["linear", "crawler"]) == 0
    text = capsys.readouterr().out
    assert "2 of 4" in text and "4 of 4" in text and "no locomotion without friction" in text


# ---- SMA wire temperature loop (§temperature-control)
# -----------------------------------------------------
@pytest.fixture(scope="module")
def sma_report():
    return linear_sma_thermal.sma_thermal()


def test_sma_thermal_plants_and_designed_poles(sma_report):
    import control as ct

    from musclesim.components.sma import thermal

    points = sma_report["points"]
    assert [q["T_op"] for q in points] == pytest.approx([30 + 5 * i for i in range(21)])
    # near room temperature the plant is the free-cooling lump: tau = rho c d / 4h (§sma-material)
    assert points[0]["time_constant"] == pytest.approx(thermal.time_constant(thermal.ThermalParams()),
                                                       rel=0.01)
    # the plant gain grows with the operating voltage: why the gains are scheduled
    # (§temperature-control)
    assert points[-1]["plant_gain"] > 2.5 * points[0]["plant_gain"]
    d = sma_report["design"]
    for q in points:
        plant, _ = linear_sma_thermal.sma_thermal_plant(q["T_op"], T_amb=d["T_amb"], sigma=d["sigma"])
        closed = ct.feedback(ct.tf([q["Kp"], q["Ki"]], [1, 0]) * ct.tf(plant))
        poles = sorted(ct.poles(closed), key=lambda z: z.imag)
        wd = d["omega_n"] * np.sqrt(1 - d["zeta"] ** 2)
        np.testing.assert_allclose(poles, [-d["zeta"] * d["omega_n"] - 1j * wd,
                                           -d["zeta"] * d["omega_n"] + 1j * wd], rtol=1e-6)
        assert q["phase_margin_deg"] > 60 and q["sampled_pole_radius"] < 1


@pytest.mark.parametrize("a, b", [(-0.58, 0.31), (-0.1, 2.0), (-476.0, 480.0)])
def test_pi_placement_by_hand_is_python_controls_place(a, b):
    """design_pi's Kp = (2 zeta omega_n + a) / b, Ki = omega_n^2 / b (written out, no LAPACK) are
    the gains python-control's `place` finds on the plant augmented with the error's integral."""
    import control as ct

    from musclesim.analysis.design import design_pi

    omega_n, zeta = 8.0, 0.9
    wd = omega_n * np.sqrt(1 - zeta ** 2)
    K = ct.place(np.array([[a, 0.0], [-1.0, 0.0]]), np.array([[b], [0.0]]),
                 [complex(-zeta * omega_n, wd), complex(-zeta * omega_n, -wd)])
    plant = ct.ss([[a]], [[b]], [[1.0]], [[0.0]])
    np.testing.assert_allclose(design_pi(plant, omega_n, zeta), (K[0, 0], -K[0, 1]), rtol=1e-12)


def test_shipped_gain_table_is_the_design_output(sma_report):
    """The scenario's gains come from the design step, not typed in: rerun it to change them. Bit
    for bit: the design solves no linear system through LAPACK/BLAS (whose kernels, chosen per
    CPU, round differently) and the wire it is made on takes the C library's exp, not numpy's."""
    from conftest import SCENARIOS

    assert (SCENARIOS / "params" / "sma-thermal-gains.toml").read_text() \
        == linear_sma_thermal.gain_table_toml(sma_report)


def test_cli_sma_thermal_writes_the_table(tmp_path, capsys):
    out = tmp_path / "gains.toml"
    assert cli.main(["linear", "sma-thermal", "--json", "--write", str(out)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert len(report["points"]) == 21 and out.read_text().count('"Kp[') == 21
