"""The FMI 3.0 face of every musclesim slave: one physics, two standards.

`Fmi3Face` is a pythonfmu3 co-simulation slave that holds one instance of a component's FMI 2.0
`Slave` class (`inner_class`) and passes every call to it: the same variables, in the same order
(Real as Float64, Integer as Int32, Boolean as Boolean), after the independent variable ``time``
(value reference 0, so a variable's value reference is the FMI 2.0 one plus 1), with the same
units, display units, descriptions, start values, direct feedthrough and default experiment;
its FMU state is the inner slave's, serialized the same way. `musclesim build --fmi 3` ships it
in FMI 3.0 FMUs only: it imports pythonfmu3, besides pythonfmu, which the FMI 2.0 base needs.
"""
from __future__ import annotations

from typing import Any, Callable, Sequence
from xml.etree.ElementTree import Element, SubElement

import pythonfmu

from pythonfmu3 import (Boolean, DefaultExperiment, Fmi3Causality, Fmi3Initial, Fmi3Slave,
                        Fmi3Variability, Float64, Int32)

from musclesim.fmu.slave import Slave


# FMI 2.0 variable class -> FMI 3.0
_TYPES: dict[type, Callable[..., Any]] = {pythonfmu.Real: Float64, pythonfmu.Integer: Int32,
                                          pythonfmu.Boolean: Boolean}


def _enum(cls: Any, fmi2_value: Any) -> Any:
    return None if fmi2_value is None else cls[fmi2_value.name]


class Fmi3Face(Fmi3Slave):
    """An FMI 3.0 co-simulation slave passing every call to an FMI 2.0 musclesim `Slave`."""

    inner_class: type[Slave] | None = None  # the component's `Slave` subclass, set per FMU

    def __init__(self, **kwargs: Any) -> None:
        """`**kwargs`: pythonfmu3's (``instance_name``, ``resources``, ``visible``, ...), passed
        on to it; the inner slave takes its instance name, resources and visibility."""
        super().__init__(**kwargs)
        if self.inner_class is None:
            raise TypeError("Fmi3Face is a base: a subclass sets inner_class")
        inner = self.inner = self.inner_class(instance_name=kwargs["instance_name"],
                                              resources=kwargs.get("resources"),
                                              visible=kwargs.get("visible", False))
        self.log_queue = inner.log_queue  # one queue: the inner slave logs, the C layer reads
        for attr in ("author", "license", "description", "modelName"):
            # pythonfmu reads them from the class first, as components declare them
            setattr(self, attr, getattr(type(inner), attr, getattr(inner, attr)))
        d = type(inner).default_experiment
        self.default_experiment = DefaultExperiment(d.start_time, d.stop_time, d.step_size,
                                                    d.tolerance)
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous,
                                       description="Simulation time", getter=self._time))
        for vr, v in inner.vars.items():
            self.register_variable(_TYPES[type(v)](
                v.name, causality=_enum(Fmi3Causality, v.causality),
                variability=_enum(Fmi3Variability, v.variability),
                initial=_enum(Fmi3Initial, v.initial), description=v.description,
                getter=v.getter, setter=v.setter))

    def _time(self) -> float:
        return self.inner.time

    # ---- FMI calls, passed on -------------------------------------------------------------------
    def setup_experiment(self, start_time: float) -> None:
        """FMI 3.0's start of the experiment at `start_time`, passed on."""
        self.inner.setup_experiment(start_time)

    def enter_initialization_mode(self) -> None:
        """FMI enterInitializationMode, passed on."""
        self.inner.enter_initialization_mode()

    def exit_initialization_mode(self) -> None:
        """FMI exitInitializationMode, passed on."""
        self.inner.exit_initialization_mode()

    def do_step(self, current_time: float, step_size: float) -> bool:
        """FMI doStep from `current_time` by `step_size`, passed on."""
        return self.inner.do_step(current_time, step_size)

    def terminate(self) -> None:
        """FMI terminate, passed on."""
        self.inner.terminate()

    def get_float64(self, vrs: Sequence[int]) -> list[float]:
        """FMI getFloat64 of value references `vrs` (0: time; the others the FMI 2.0 one + 1)."""
        if 0 in vrs:
            return [self.inner.time if vr == 0 else self.inner.get_real([vr - 1])[0]
                    for vr in vrs]
        return self.inner.get_real([vr - 1 for vr in vrs])

    def set_float64(self, vrs: Sequence[int], values: Sequence[float]) -> None:
        """FMI setFloat64 of value references `vrs` to `values` (time cannot be set)."""
        if 0 in vrs:
            raise ValueError("time is the independent variable: it cannot be set")
        self.inner.set_real([vr - 1 for vr in vrs], values)

    def get_int32(self, vrs: Sequence[int]) -> list[int]:
        """FMI getInt32 of value references `vrs`."""
        return self.inner.get_integer([vr - 1 for vr in vrs])

    def get_boolean(self, vrs: Sequence[int]) -> list[bool]:
        """FMI getBoolean of value references `vrs`."""
        return self.inner.get_boolean([vr - 1 for vr in vrs])

    def set_int32(self, vrs: Sequence[int], values: Sequence[int]) -> None:
        """FMI setInt32 of value references `vrs` to `values`."""
        self.inner.set_integer([vr - 1 for vr in vrs], values)

    def set_boolean(self, vrs: Sequence[int], values: Sequence[bool]) -> None:
        """FMI setBoolean of value references `vrs` to `values`."""
        self.inner.set_boolean([vr - 1 for vr in vrs], values)

    def _get_fmu_state(self) -> dict[str, Any]:
        return self.inner._get_fmu_state()

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        self.inner._set_fmu_state(state)

    # static, as pythonfmu3's C layer calls them: the FMI 2.0 slave's own (pickle)
    _fmu_state_to_bytes = staticmethod(Slave._fmu_state_to_bytes)
    _fmu_state_from_bytes = staticmethod(Slave._fmu_state_from_bytes)

    # ---- model description ---------------------------------------------------------------------
    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """The FMI 3.0 model description, pythonfmu3's (`model_options`: its options) with the
        inner slave's units and a complete ModelStructure."""
        root = super().to_xml(model_options or {})
        vr = {v.get("name"): v.get("valueReference") for v in root.find("ModelVariables")}
        structure = self.inner.describe_units(root, typed=lambda v: v)
        outputs = self.inner.feedthrough()
        for name, deps in outputs:
            SubElement(structure, "Output", valueReference=vr[name],
                       dependencies=" ".join(vr[d] for d in deps))
        # outputs are initial="calculated": initial unknowns, depending on everything
        for name, _ in outputs:
            SubElement(structure, "InitialUnknown", valueReference=vr[name])
        return root
