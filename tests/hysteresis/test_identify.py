"""musclesim.hysteresis.identify: identification from FORC experiments (§forc-identification):
the ForcReference profile, `identify` on synthetic records from a known surface (no FMUs), its
errors and a reduced closed-loop run on the FMUs. (The validation numbers:
tests/hysteresis/test_validation.py.)"""
import json
import math

import numpy as np
import pytest

from musclesim.hysteresis import validation
from musclesim.hysteresis import identify as ident
from musclesim.cosim import Master, Signal, load_scenario, signal_units, write_results
from musclesim.components.sma import datasets, forcfile
from musclesim.components.sma.reference_wire import ReferenceWire
from musclesim.components.sources import forc
from musclesim.errors import UserError

from conftest import SCENARIOS

WIRE = ReferenceWire()
HEADER = ["time", "reference.T_ref", "reference.run", "reference.phase", "thermocouple.T_meas",
          "wire.strain", "wire.stress"]


# ---- the reference profile ---------------------------------------------------------------------

def test_forc_reference_runs_peaks_and_phases():
    p = forc.ForcParams(period=20.0, t_start=5.0)
    assert p.n_runs == 21 and p.duration == 5.0 + 21 * 20.0
    assert forc.value(0.0, p) == (p.T_low, -1.0, forc.IDLE)  # before the first run
    for j in range(21):
        t0 = 5.0 + 20.0 * j
        T, run, phase = forc.value(t0 + 10.0, p)  # mid-run: the peak, cooling starts
        assert T == pytest.approx(303.15 + 5.0 * j) and run == j and phase == forc.COOLING
        assert forc.value(t0 + 5.0, p)[2] == forc.HEATING
        assert forc.value(t0 + 1e-9, p)[0] == pytest.approx(p.T_low)  # every run starts at b0
    assert forc.value(p.duration + 1.0, p) == (p.T_low, -1.0, forc.IDLE)
    with pytest.raises(ValueError, match="T_step"):
        forc.ForcParams(T_step=7.0).check()
    with pytest.raises(ValueError, match="period"):
        forc.ForcParams(period=0.0).check()


def test_the_scenario_period_does_not_outrun_free_cooling():
    s = load_scenario(SCENARIOS / "sma-forc-identification.toml")
    period = s.instances["reference"].parameters["period"]
    assert s.stop_time == pytest.approx(21 * period)
    # tau = rho c d / 4 h = 1.71 s (§thermal-model), ambient 20 C, T_low 30 C
    assert forc.min_period(100.0, 10.0, 1.71) < 0.85 * period


# ---- synthetic records from a known surface ----------------------------------------------------

def synthetic(tmp_path, F, sigma, name, dt=0.01, period=20.0, T_step=5.0, edit=None):
    """A record of the FORC runs at stress sigma whose strain comes straight from F(a, b):
    rising from b0, eps = F(T, b0); falling from the peak a, eps = F(a, b0) - F(a, T)."""
    p = forc.ForcParams(T_step=T_step, period=period)
    t = np.arange(0.0, p.duration + dt / 2, dt)
    ref = np.array([forc.value(x, p) for x in t])
    T_C = ref[:, 0] - 273.15
    run, phase = ref[:, 1], ref[:, 2]
    peaks = np.where(run >= 0, 30.0 + T_step * run, 30.0)
    eps = np.where(phase >= 0, F(T_C, 30.0, sigma), F(peaks, 30.0, sigma) - F(peaks, T_C, sigma))
    cols = {"time": t, "reference.T_ref": ref[:, 0], "reference.run": run,
            "reference.phase": phase, "thermocouple.T_meas": T_C + 273.15, "wire.strain": eps,
            "wire.stress": np.full_like(t, sigma)}
    if edit:
        edit(cols)
    folder = tmp_path / name
    folder.mkdir()
    names = [h for h in HEADER if h in cols]
    np.savetxt(folder / "results.csv", np.column_stack([cols[h] for h in names]),
               delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    (folder / "summary.json").write_text(json.dumps(
        {"completed": True, "parameters": {"reference": {"T_step": T_step, "period": period}}}))
    return folder


def wire_F(a, b, sigma):
    return WIRE.F(a, b, sigma)


def test_identify_recovers_a_known_surface(tmp_path):
    stresses = (105e6, 125e6, 145e6)
    folders = [synthetic(tmp_path, wire_F, s, f"s{k}") for k, s in enumerate(stresses)]
    out = tmp_path / "forc.csv"
    surface = ident.identify(folders[::-1], out)  # any order
    assert surface.stresses.tolist() == list(stresses)
    exact = WIRE.hypersurface(surface.temps, stresses).table
    assert np.abs(surface.table - exact).max() < 2e-6  # only linear interpolation between samples
    assert validation.surface_error(surface)["max_abs"] < 2e-6
    temps, st, table, _ = forcfile.read(out)  # the documented file, read back
    assert temps.tolist() == list(range(30, 131, 5)) and st.tolist() == list(stresses)
    assert np.allclose(np.tril(table), np.tril(surface.table), atol=1e-15, equal_nan=True)


def test_identify_reads_a_sweep_folder_and_a_coarse_grid(tmp_path):
    sweep = tmp_path / "sweep"
    (sweep / "cases").mkdir(parents=True)
    for k, s in enumerate((110e6, 140e6)):
        synthetic(sweep / "cases", wire_F, s, f"case{k}", dt=0.02, T_step=25.0)
    surface = ident.identify(sweep)
    assert surface.temps.tolist() == [30.0, 55.0, 80.0, 105.0, 130.0]
    assert validation.surface_error(surface)["max_abs"] < 1e-5


def drop(column):
    return lambda cols: cols.pop(column)


def in_run(j, fn):
    def edit(cols):
        mask = cols["reference.run"] == j
        fn(cols, mask)
    return edit


def lower_peak(cols, mask):
    cols["thermocouple.T_meas"][mask] = np.minimum(cols["thermocouple.T_meas"][mask], 370.0)


def bump_on_cooling(cols, mask):
    idx = np.flatnonzero(mask & (cols["reference.phase"] < 0))
    cols["thermocouple.T_meas"][idx[len(idx) // 2]] += 2.0


def stop_early(cols, mask):
    cols["thermocouple.T_meas"][mask] = np.maximum(cols["thermocouple.T_meas"][mask], 310.0)


def vary_stress(cols):
    cols["wire.stress"] = cols["wire.stress"] * (1 + 0.01 * np.sin(cols["time"]))


def shrink_strain(cols, mask):
    cols["wire.strain"][mask] *= 0.5  # F(100, b) below F(95, b): not a FORC surface


@pytest.mark.parametrize("edit, match", [
    (drop("wire.strain"), r"results.csv has no column 'wire.strain'"),
    (in_run(18, lower_peak), r"run 18 \(peak 120 C\) never reaches its peak"),
    (in_run(12, bump_on_cooling), r"run 12 .*rises again by 1.529 K to 62.000 C on the descending"),
    (in_run(9, stop_early), r"run 9 .*stops cooling at 36.850 C, above the grid temperature 30"),
    (vary_stress, r"the stress \(wire.stress\) varies"),
    (in_run(14, shrink_strain), r"not a FORC surface \(run 14, peak 100 C\)"),
])
def test_bad_records_are_refused_naming_file_and_run(tmp_path, edit, match):
    folder = synthetic(tmp_path, wire_F, 125e6, "bad", dt=0.05, edit=edit)
    with pytest.raises(UserError, match=match) as err:
        ident.identify(folder)
    assert "bad" in str(err.value)  # the file is named


def test_a_record_cut_short_and_duplicate_stresses_are_refused(tmp_path):
    def cut(cols):  # the record ends after run 10
        keep = cols["time"] < 220.0
        cols.update({k: v[keep] for k, v in cols.items()})

    short = synthetic(tmp_path, wire_F, 125e6, "short", dt=0.05, edit=cut)
    with pytest.raises(UserError, match=r"run 11 \(peak 85 C\) has no samples"):
        ident.identify(short)
    one, two = (synthetic(tmp_path, wire_F, 125e6, n, dt=0.05) for n in ("one", "two"))
    with pytest.raises(UserError, match="are both at 1.25e\\+08 Pa"):
        ident.identify([one, two])
    with pytest.raises(UserError, match="neither a results.csv"):
        ident.identify(tmp_path / "nothing")


# ---- the closed loop on the FMUs, reduced ------------------------------------------------------

def closed_loop(fmu_dir, tmp_path, sigma, period, T_step=25.0):
    """The identification scenario at stress sigma, with 5 runs of `period` s (peaks 25 K apart)."""
    n = int(round(100 / T_step)) + 1
    s = load_scenario(SCENARIOS / "sma-forc-identification.toml",
                      [f"load.offset={sigma * 1.26677e-8!r}", f"reference.T_step={T_step!r}",
                       f"reference.period={period!r}"], stop_time=n * period)
    m = Master(s, fmu_dir)
    res = m.run()
    assert res.error is None, res.error
    folder = tmp_path / f"run-{sigma:g}-{period:g}"
    write_results(folder, s, res, signal_units(m), with_plot=False)
    return folder, res


def test_identify_from_the_closed_loop_on_the_virtual_wire(fmu_dir, tmp_path):
    fast = [closed_loop(fmu_dir, tmp_path, s, 20.0) for s in (105e6, 145e6)]
    for _, res in fast:
        # K: the loop follows the sinusoids
        assert np.sqrt(np.mean(res[Signal("pid", "e")] ** 2)) < 0.15
    surface = ident.identify([f for f, _ in fast])
    assert surface.temps.tolist() == [30.0, 55.0, 80.0, 105.0, 130.0]
    assert surface.stresses.tolist() == [105e6, 145e6]
    err = validation.surface_error(surface)
    assert err["max_abs"] < 2e-4  # 0.5 % of the maximum strain
    # rate independence on the FMU: the same runs 1.5 times as slow give the same surface
    slow, _ = closed_loop(fmu_dir, tmp_path, 105e6, 30.0)
    again = ident.identify(slow)
    assert np.abs(again.table[0] - surface.table[0]).max() < 5e-5
