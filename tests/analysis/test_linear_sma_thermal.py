"""musclesim.analysis.linear_sma_thermal: the SMA wire's linear thermal plants and the
gain-scheduled temperature PI (§temperature-control), API and command line."""
import json

import numpy as np
import pytest

from musclesim import cli
from musclesim.analysis import linear_sma_thermal


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
