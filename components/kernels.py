"""Every component's compiled kernel by kind number, for the co-simulation master's fused step.

`KERNELS` lists the kernels (`musclesim.fmu.kernel.Kernel`) of the components whose slaves are
`KernelSlave`s; `KINDS` gives each its number; `evaluate` and `advance` call the kernel of a kind
number, so that one compiled loop (`musclesim.cosim.fused`) steps instances of many components.
A component joins by adding its kernel to `KERNELS` and a branch to both functions (a test checks
that every kind reaches its own kernel).
"""
from __future__ import annotations

from musclesim.components.crawler import body, friction, gait, inputs
from musclesim.fmu.compiled import jit
from musclesim.fmu.kernel import Kernel

__all__ = ["KERNELS", "KINDS", "evaluate", "advance"]

KERNELS: tuple[Kernel, ...] = (body.KERNEL, friction.KERNEL, inputs.KERNEL, gait.KERNEL)
KINDS: dict[Kernel, int] = {k: i for i, k in enumerate(KERNELS)}


@jit
def evaluate(kind, p, x, u, t, y):
    """``KERNELS[kind].evaluate(p, x, u, t, y)``."""
    if kind == 0:
        body.evaluate(p, x, u, t, y)
    elif kind == 1:
        friction.evaluate(p, x, u, t, y)
    elif kind == 2:
        inputs.evaluate(p, x, u, t, y)
    elif kind == 3:
        gait.evaluate(p, x, u, t, y)


@jit
def advance(kind, p, x, u, y, t, dt):
    """``KERNELS[kind].advance(p, x, u, y, t, dt)``."""
    if kind == 0:
        body.advance(p, x, u, y, t, dt)
    elif kind == 1:
        friction.advance(p, x, u, y, t, dt)
    elif kind == 2:
        inputs.advance(p, x, u, y, t, dt)
    elif kind == 3:
        gait.advance(p, x, u, y, t, dt)
