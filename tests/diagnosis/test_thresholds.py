"""Every threshold of the diagnosis in one place, each said why (a comment above it or its
group), and their values consistent with each other."""
import ast
import inspect

from musclesim.diagnosis import thresholds as th


def test_every_threshold_has_its_reason_written_above_it():
    source = inspect.getsource(th)
    lines = source.splitlines()
    names = []
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign):
            name = node.targets[0].id
            names.append(name)
            above = lines[node.lineno - 2].strip()
            # a comment, or the previous constant of the same group (which has one)
            assert above.startswith("#") or above.split(" = ")[0] in names[:-1], name
    assert {"DEVIATES", "NAME_LEVEL", "PROFILE_SCALE"} <= set(names)


def test_the_thresholds_agree_with_each_other():
    assert 0 < th.RESIDUAL_SHARE < th.MIN_SHRINKAGE < 1  # a gap left small is a gap shrunk
    assert th.NAME_LEVEL == th.CREDIBLE and 0.5 < th.CREDIBLE < 1
    assert 0 < th.PAIR_PRIOR < 1 and 0 < th.PROFILE_SCALE < 0.5
    assert th.NOISE_FLOOR < th.METRIC_FLOOR < 1
    assert th.STRUCTURED >= th.DEVIATES  # not structured is within what does not deviate
    for count in (th.MAX_ALIGN, th.MIN_VALUES_PER_PARAMETER, th.STEPS, th.MAX_ITERATIONS,
                  th.PERIOD_POINTS, th.REFINED, th.PASSES, th.BOOTSTRAP, th.BLOCKS,
                  th.WINDOWS, th.MAX_AR_ORDER):
        assert isinstance(count, int) and count > 0
