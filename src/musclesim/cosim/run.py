"""One scenario run from file to folder: load, check the FMUs are fresh, run, write."""
from musclesim.cosim import build, master, results, scenario


def run_scenario(path, out, fmu_dir="fmus", overrides=(), stop_time=None, with_plot=True):
    """Load, run and write one scenario (the plot only `with_plot`); return (summary, results)."""
    s = scenario.load(path, overrides, stop_time)
    build.check_fresh(fmu_dir)
    m = master.Master(s, fmu_dir)
    res = m.run()
    summary = results.write_all(out, s, res, results.signal_units(m), with_plot)
    return summary, res
