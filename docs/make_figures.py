"""Make the figures the documentation shows: the plot of each flagship scenario, as
`musclesim run` draws it, into docs/figures/<scenario>.png.

    python docs/make_figures.py [SCENARIO ...]

Run it after `musclesim build` from the repository's root; it takes about 15 minutes on two
cores (the position control's 550 s at 2.5 kHz is most of it). The figures are committed, so
that the docs build in seconds; rerun this when a flagship scenario or its components change.
"""
import shutil
import sys
import tempfile
from pathlib import Path

from musclesim.cosim import run_scenario

ROOT = Path(__file__).resolve().parents[1]
FLAGSHIPS = ("crawler-ideal", "crawler-gait-forward", "sma-temperature-tracking",
             "sma-position-control", "sma-multiplier-bands", "bending-one-wire", "quadruped-walk",
             "sma-forc-identification", "sma-drift")


def main(names):
    for name in names or FLAGSHIPS:
        with tempfile.TemporaryDirectory() as out:
            summary, _ = run_scenario(ROOT / "scenarios" / f"{name}.toml", out, ROOT / "fmus")
            if not summary["completed"]:
                sys.exit(f"{name}: the run stopped: {summary['error']}")
            shutil.copyfile(Path(out) / "results.png", ROOT / "docs" / "figures" / f"{name}.png")
        metrics = ", ".join(f"{k} = {summary[k]:.4g} {u}" for k, u in summary["units"].items()
                            if summary[k] is not None)
        print(f"{name}: {metrics}")


if __name__ == "__main__":
    main(sys.argv[1:])
