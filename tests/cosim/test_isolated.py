"""Instances in child processes of their own (musclesim.cosim.isolated): fmpy's bits, the same
warnings, a scenario's ``isolate`` key checked. A crash there is tests/cli/test_bad_inputs.py's."""
import multiprocessing
from dataclasses import replace

import numpy as np
import pytest

from musclesim.cosim import Master, load_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS


def test_an_isolated_run_is_fmpy_s_bits_and_leaves_no_process(fmu_dir):
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", stop_time=0.1)
    on_fmpy = Master(s, fmu_dir, host="fmpy").run()
    one = replace(s, instances={**s.instances,
                                "body": replace(s.instances["body"], isolate=True)})
    for m in (Master(one, fmu_dir), Master(s, fmu_dir, isolate=True)):
        res = m.run()
        assert res.error is None and m.fused is False
        assert np.array_equal(res.time, on_fmpy.time)
        assert np.array_equal(res.data, on_fmpy.data)
        assert res.warnings == on_fmpy.warnings
    assert m.hosts == dict.fromkeys(s.instances, "isolated")
    assert [p for p in multiprocessing.active_children()  # a Dask cluster's may run too
            if p.name.startswith("musclesim FMU")] == []


def test_a_scenario_s_isolate_key_is_true_or_false(tmp_path):
    text = (SCENARIOS / "crawler-ideal.toml").read_text()
    path = tmp_path / "crawler-ideal.toml"
    path.write_text(text.replace("[instances.body]\n", "[instances.body]\nisolate = true\n", 1))
    assert load_scenario(path).instances["body"].isolate
    path.write_text(text.replace("[instances.body]\n", '[instances.body]\nisolate = "yes"\n', 1))
    with pytest.raises(UserError, match="instance 'body': isolate = 'yes' must be true or false"):
        load_scenario(path)
