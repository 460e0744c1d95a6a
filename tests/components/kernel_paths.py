"""A kernel slave's compiled functions against their plain-Python source (`.py_func`), bit for bit,
on the arrays a short run gives them (musclesim.fmu.kernel, musclesim.fmu.compiled)."""
import numpy as np
import pytest


def assert_paths_agree(slave, inputs, dt, steps):
    """Drive `slave` (made with conftest's in_process) through `steps` communication steps of
    `dt`, its inputs set by ``inputs(k)`` (a dict of attribute: value, or None) before step k; at
    each step call its kernel's compiled and plain evaluate and advance on copies of the arrays
    and require the same bits. Skipped where the kernel runs as Python (no numba)."""
    kernel = type(slave).kernel
    if getattr(kernel.evaluate, "py_func", None) is None:
        pytest.skip("the kernel is not compiled here (numba absent or MUSCLESIM_COMPILE=0)")
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    for k in range(steps):
        for name, value in (inputs(k) or {}).items():
            setattr(slave, name, value)
        slave.set_real([], [])
        slave.get_real([])
        t = slave.time
        u = slave._inputs(t).copy()
        ys = []
        for fn in (kernel.evaluate, kernel.evaluate.py_func):
            y = np.zeros(len(kernel.outputs))
            fn(slave.kp.copy(), slave.kx.copy(), u.copy(), t, y)
            ys.append(y)
        assert ys[0].tobytes() == ys[1].tobytes(), (k, ys)
        xs = []
        for fn in (kernel.advance, kernel.advance.py_func):
            x = slave.kx.copy()
            fn(slave.kp.copy(), x, u.copy(), ys[0].copy(), t, dt)
            xs.append(x)
        assert xs[0].tobytes() == xs[1].tobytes(), (k, xs)
        slave.do_step(t, dt)
        assert slave.kx.tobytes() == xs[0].tobytes(), k  # the slave took the same step
