"""Measured data sets written by hand for the data-set tests (test_dataset, test_manifest,
test_measured, test_modelcheck): a good crawler set, and the means to spoil it."""
import math

import pytest

from musclesim.diagnosis import dataset
from musclesim.errors import UserError

from conftest import SCENARIOS

COLUMNS = ["inputs.f_a", "body.x_cm"]
GOOD_MANIFEST = """\
description = "hand-written crawler data"
scenario = "crawler-ideal"
inputs = ["inputs.f_a"]
outputs = ["body.x_cm"]

[units]
"inputs.f_a" = "N"
"body.x_cm" = "m"

[experiments.first]
span = [0.0, 0.5]
[experiments.second]
span = [0.5, 0.9]
metrics.mean_speed = { value = 0.02, unit = "m/s", uncertainty = 0.001 }

[split]
held_out = ["second"]
"""


def good_rows(n=10, dt=0.1):
    """Samples of a made-up run: a sine force and a creeping centre of mass."""
    return [[round(i * dt, 10), math.sin(i), 0.01 * i] for i in range(n)]


def write_set(folder, manifest=GOOD_MANIFEST, header=("time", *COLUMNS), rows=None):
    """Write data.csv (unless `rows` is False) and manifest.toml by hand, not via the simulator."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "manifest.toml").write_text(manifest)
    if rows is not False:
        rows = good_rows() if rows is None else rows
        lines = [",".join(header)] + [",".join(str(v) for v in row) for row in rows]
        (folder / "data.csv").write_text("\n".join(lines) + "\n")
    return folder


def problems_of(folder, **kwargs):
    """The message of the UserError loading the set in `folder` raises (scenario names looked up
    in the repository's scenarios unless `kwargs` say otherwise)."""
    kwargs.setdefault("scenarios_dir", SCENARIOS)
    with pytest.raises(UserError) as info:
        dataset.load(folder, **kwargs)
    return str(info.value)


def replace_in_good(old, new):
    return GOOD_MANIFEST.replace(old, new)


def rows_with(i, j, value):
    rows = good_rows()
    rows[i][j] = value
    return rows


REAL = SCENARIOS / "data" / "crawler-real"

SCALAR = ('scenario = "crawler-ideal"\n'
          '[experiments.a]\nconditions = { "body.k" = 210.0 }\n'
          'metrics.mean_speed = { value = 0.02, unit = "m/s" }\n'
          '[experiments.b]\nmetrics.mean_speed = { value = 0.03, unit = "m/s" }\n'
          '[conditions]\n"body.c" = 1.2\n[split]\nheld_out = ["b"]\n')
