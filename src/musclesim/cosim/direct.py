"""The direct host: the FMUs musclesim built, run in this process without the FMI C layer.

A musclesim FMU is a pythonfmu archive: its resources hold a Python slave class, and pythonfmu's
native library calls that class's methods (``get_real``, ``set_real``, ``do_step``...) for every FMI
call, crossing ctypes, C++ and back into Python per call. The slave is Python already, so a master
in the same Python process can load the class the archive ships (``resources/slavemodule.txt``
names its script, read from the archive: nothing is unpacked) and call those same methods itself:
the same code, the same calls in the same order, hence the same results to the bit, without the
round trip. The slave gets no resources folder: it reads the installed package's data files, of
which the archive's are copies.

An archive qualifies only where the code it ships is the code this process has imported: the
folder's ``BUILD.json`` (written by `musclesim.cosim.build_all`) lists the file with its digest,
and the sources it was built from are the installed ones (`build.built_here`). Its script imports
the slave from ``musclesim.components``, which here resolves to the installed package, equal by
that digest to the copy the archive ships. Every other FMU (another tool's, a package's, a stale
one of ours) is hosted by fmpy as before.

`DirectSlave` mirrors what the master uses of fmpy's ``FMU2Slave``: an exception a slave raises is
logged as pythonfmu's C layer logs it (an fmi2Error message holding the exception's repr) and
raised as fmpy's ``FMICallException``, so a failure reads the same on both hosts.
"""
import types
import zipfile

from fmpy.fmi1 import FMICallException

ERROR = 3  # fmi2Error

_CLASSES: dict[bytes, type] = {}  # content of the resources' script -> slave class


def slave_class(fmu_path, model_identifier):
    """The slave class the pythonfmu FMU at `fmu_path` ships, its resources' script read from the
    archive (nothing is unpacked) and executed once per process, as pythonfmu executes it."""
    with zipfile.ZipFile(fmu_path) as zf:
        name = zf.read("resources/slavemodule.txt").decode().strip()
        source = zf.read(f"resources/{name}.py")
    if source not in _CLASSES:
        module = types.ModuleType(f"{name}_direct")
        module.__file__ = f"{fmu_path}/resources/{name}.py"
        exec(compile(source, module.__file__, "exec"), module.__dict__)  # noqa: S102 - ours
        _CLASSES[source] = getattr(module, model_identifier)
    return _CLASSES[source]


class DirectSlave:
    """One instance of a musclesim slave class (`musclesim.fmu.Slave`), called the way
    pythonfmu's C layer calls it; its batched `Slave.reader` and `Slave.writer` serve the loop.

    The messages the slave logs go to `log` as (status, message) pairs after every call, as
    fmpy's logger callback delivers them.
    """

    def __init__(self, cls, instance_name, log):
        self.log = log
        self.name = instance_name
        # no resources folder: the slave reads this package's data files (the installed ones,
        # which the archive's are copies of)
        self.slave = self._call("fmi2Instantiate", cls, instance_name=instance_name,
                                resources=None, visible=False)

    def _call(self, function, method, *args, **kwargs):
        try:
            result = method(*args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - the C layer catches every exception, too
            self.failed(function, exc)
        self.drain()
        return result

    def failed(self, function, exc):
        """Log `exc` as pythonfmu's C layer does and raise it as fmpy would."""
        self.drain()
        self.log.append((ERROR, repr(exc)))
        raise FMICallException(function=function, status=ERROR) from exc

    def drain(self):
        """Move the messages the slave logged to `log`."""
        queue = getattr(getattr(self, "slave", None), "log_queue", None)
        if queue:
            self.log.extend((int(m.status), m.msg) for m in queue)
            queue.clear()

    def setup_experiment(self, start_time, stop_time):
        self._call("fmi2SetupExperiment", self.slave.setup_experiment, start_time, stop_time, None)

    def enter_initialization_mode(self):
        self._call("fmi2EnterInitializationMode", self.slave.enter_initialization_mode)

    def exit_initialization_mode(self):
        self._call("fmi2ExitInitializationMode", self.slave.exit_initialization_mode)

    def terminate(self):
        self._call("fmi2Terminate", self.slave.terminate)

    def set_real(self, vrs, values, kinds=None):
        """Set `vrs` to `values`; the slave keeps Integer and Boolean values (`kinds`) as floats
        too, so one call sets them all."""
        self._call("fmi2SetReal", self.slave.set_real, list(vrs), [float(v) for v in values])

    # The calls of the master's loop: closures over preallocated value-reference lists, with the
    # error handling of `_call` written out (a Python call less per FMI call).
    def reader(self, vrs, out, kinds=None):
        """A function that writes the values of `vrs` into the array `out` (one batched call)."""
        if not vrs:
            return None
        get, queue, failed = self.slave.reader(list(vrs)), self.slave.log_queue, self.failed

        def read():
            try:
                out[:] = get()
            except Exception as exc:  # noqa: BLE001
                failed("fmi2GetReal", exc)
            if queue:
                self.drain()
        return read

    def writer(self, vrs, slots, values, kinds=None):
        """A function that sets `vrs` to ``values[slots]`` (one batched call)."""
        if not vrs:
            return None
        set_, queue, failed = self.slave.writer(list(vrs)), self.slave.log_queue, self.failed

        def write():
            try:
                set_(values.take(slots).tolist())
            except Exception as exc:  # noqa: BLE001
                failed("fmi2SetReal", exc)
            if queue:
                self.drain()
        return write

    def stepper(self):
        """A function doing one fmi2DoStep(t, h)."""
        do_step, queue, failed = self.slave.do_step, self.slave.log_queue, self.failed

        def step(t, h):
            try:
                done = do_step(t, h)
            except Exception as exc:  # noqa: BLE001
                failed("fmi2DoStep", exc)
            if queue:
                self.drain()
            if not done:
                failed("fmi2DoStep", RuntimeError("do_step returned False"))
        return step
