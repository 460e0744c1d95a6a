"""Communication points at t0 + k h (docs/user/scenarios.md, the master algorithm): a square wave
sampled on its edges switches at the same points in musclesim, FMPy and libcosim, and musclesim's
and FMPy's runs of it are the same bits, times included."""
import numpy as np
from fmpy import simulate_fmu

from musclesim.cosim import Master, Signal, forget_fmu_resource_paths, load_scenario
from musclesim.export import export_ssp

from export.test_ssp import run_libcosim  # tests/export/test_ssp.py

S = Signal.parse

H, STOP = 1e-3, 2.0
WAVE = {"kind": 2.0, "amplitude": 1.0, "frequency": 1.0}  # edges at 0.5, 1, 1.5 and 2 s


def switches(y):
    return list(np.flatnonzero(np.diff(y)) + 1)


def test_a_square_wave_switches_where_fmpy_and_libcosim_switch_it(fmu_dir, tmp_path):
    path = tmp_path / "square.toml"
    path.write_text(f'step = {H}\nstop_time = {STOP}\nalgorithm = "jacobi"\nrecord = ["src.y"]\n'
                    '[instances.src]\ncomponent = "SignalSource"\nparameters = { '
                    + ", ".join(f"{k} = {v}" for k, v in WAVE.items()) + " }\n")
    s = load_scenario(path)
    ours = Master(s, fmu_dir).run()
    k = np.arange(s.n_steps + 1)
    assert np.array_equal(ours.time, k * H)
    assert switches(ours[S("src.y")]) == [500, 1000, 1500, 2000]

    fmpy = simulate_fmu(str(fmu_dir / "SignalSource.fmu"), start_values=WAVE, stop_time=STOP,
                        output_interval=H, output=["y"])
    forget_fmu_resource_paths()
    assert np.array_equal(fmpy["time"], ours.time)
    assert np.array_equal(fmpy["y"], ours[S("src.y")])

    _, cosim = run_libcosim(export_ssp(s, fmu_dir, tmp_path / "square.ssp"), ["src.y"],
                            s.n_steps, s.step)
    assert switches(cosim["src.y"]) == switches(ours[S("src.y")])

