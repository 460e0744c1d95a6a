"""A slave whose physics is a compiled kernel: `Kernel` names a component's two core functions and
the variables they take and give; `KernelSlave` is the thin adapter that calls them.

A kernel is two functions in the subset `musclesim.fmu.compiled.jit` compiles, on float64 arrays:

- ``evaluate(p, x, u, t, y)``: write the outputs ``y`` from the parameters ``p``, the state ``x``,
  the inputs ``u`` and the time ``t``, changing nothing else (`Slave.evaluate`'s rule);
- ``advance(p, x, u, y, t, dt)``: advance the state ``x`` in place from ``t`` to ``t + dt`` with
  the inputs ``u`` held, ``y`` being the outputs just evaluated at ``t``.

``u`` holds the inputs named in `Kernel.inputs` (those in `Kernel.clamps` clamped to their range
before the kernel sees them, the first clamp warned, NaN refused: `Slave.clamped_input`), ``y``
the outputs named in `Kernel.outputs` (every output of the slave), in that order; `no_state` is
the advance of a kernel without state. The slave's `setup` fills ``self.kp`` (parameters, packed
once) and ``self.kx`` (the state), its `initialize` may set ``self.kx`` from the inputs. Because
the whole state is in those arrays, the co-simulation master can run many kernels in one compiled
loop (`musclesim.cosim.fused`) and give the same bits as these per-call adapters.
"""
from __future__ import annotations

import operator
from dataclasses import dataclass
from typing import Any, Callable, ClassVar

import numpy as np

from musclesim.fmu.compiled import jit
from musclesim.fmu.slave import Slave

__all__ = ["Kernel", "KernelSlave", "no_state"]


@jit
def no_state(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
             dt: float) -> None:
    """The advance of a kernel without state (a source, a sequencer): nothing changes, whatever
    the parameters `p`, state `x`, inputs `u`, outputs `y`, time `t` and step `dt`."""


@dataclass(frozen=True)
class Kernel:
    """A component's compiled core (see the module docstring): `evaluate`, `advance` and the FMI
    names of the `inputs` and `outputs` they take and give, in array order; `clamps`: (input,
    lower, upper) of the inputs held to a range."""

    evaluate: Callable[..., Any]
    advance: Callable[..., Any]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    clamps: tuple[tuple[str, float, float], ...] = ()


class KernelSlave(Slave):
    """Base of a slave whose `evaluate` and `advance` are its class's `kernel`: its `setup` sets
    ``kp`` and ``kx`` (float64 arrays)."""

    kernel: ClassVar[Kernel]
    # what evaluate writes besides the output variables: the inputs as the kernel took them and
    # the outputs it gave, as arrays (the state is `kx`; evaluate changes nothing else)
    buffers: ClassVar[tuple[str, ...]] = ("ku", "ky")

    def __init__(self, **kwargs: Any) -> None:
        """`**kwargs`: pythonfmu's, passed on (see `Slave`)."""
        super().__init__(**kwargs)
        k = self.kernel
        self.kp = np.zeros(0)
        self.kx = np.zeros(0)
        self.ku = np.zeros(len(k.inputs))
        self.ky = np.zeros(len(k.outputs))
        self._kin = [name.replace(".", "_") for name in k.inputs]
        self._kout = [name.replace(".", "_") for name in k.outputs]
        # one C call each way per kernel call (a Python loop over the variables cost as much as
        # the kernel itself); attrgetter gives a tuple of two names or more
        self._kget = operator.attrgetter(*self._kin, *self._kin[:1]) if self._kin else None
        self._kclamps = [(k.inputs.index(name), name, lo, hi) for name, lo, hi in k.clamps]

    def _inputs(self, t: float) -> np.ndarray:
        u = self.ku
        if self._kget is not None:
            u[:] = self._kget(self)[:len(u)]
        for i, name, lo, hi in self._kclamps:
            u[i] = self.clamped_input(name, lo, hi, t)
        return u

    def kernel_inputs(self) -> list[float]:
        """The inputs `Kernel.inputs` as set, unclamped."""
        return [getattr(self, attr) for attr in self._kin]

    def kernel_dirty(self) -> bool:
        """Whether an input was set or a step taken since the outputs were evaluated."""
        return self._dirty

    def restore_kernel(self, x: np.ndarray, u: np.ndarray, y: np.ndarray, time: float,
                       dirty: bool) -> None:
        """Take the state `x`, the inputs `u` (`Kernel.inputs`), the outputs `y` last evaluated,
        the clock `time` [s] and whether the outputs are out of date (`dirty`) that a master
        reached running the kernel itself."""
        self.kx[:], self.ky[:], self.time, self._dirty = x, y, time, dirty
        self.__dict__.update(zip(self._kin, u.tolist()))
        self.__dict__.update(zip(self._kout, y.tolist()))

    def note_clamp(self, name: str, value: float, lo: float, hi: float, t: float) -> None:
        """Warn of input `name` at `value` clamped to [`lo`, `hi`] at time `t` [s] as
        `clamped_input` does (once per input): a master that ran the kernel itself met it."""
        attr = name.replace(".", "_")
        held = getattr(self, attr)
        setattr(self, attr, value)
        self.clamped_input(name, lo, hi, t)
        setattr(self, attr, held)

    def evaluate(self) -> None:
        """The kernel's outputs at the current state, inputs and time."""
        y = self.ky
        self.kernel.evaluate(self.kp, self.kx, self._inputs(self.time), self.time, y)
        self.__dict__.update(zip(self._kout, y.tolist()))

    def advance(self, t: float, dt: float) -> None:
        """The kernel's step over [`t`, `t` + `dt`] [s] with the inputs held (the outputs were
        evaluated at `t` just before: `Slave.do_step`)."""
        self.kernel.advance(self.kp, self.kx, self._inputs(t), self.ky, t, dt)
