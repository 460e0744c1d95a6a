"""musclesim.cosim.build: a component whose module fails to import ends the build in one sentence
naming it and the cause."""
import pytest

from musclesim.cosim import build
from musclesim.errors import UserError


@pytest.mark.parametrize("source, cause", [
    ("raise RuntimeError('no scipy here\\nsecond line')", "RuntimeError: no scipy here second line"),
    ("import musclesim_no_such_module_x", "ModuleNotFoundError: No module named "
                                          "'musclesim_no_such_module_x'"),
    ("def broken(:\n", "SyntaxError: "),
])
def test_a_component_that_fails_to_import_is_named_with_the_cause(tmp_path, monkeypatch, source,
                                                                  cause):
    (tmp_path / "musclesim_broken_slave.py").write_text(source)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(build.CATALOGUE, "Broken", "musclesim_broken_slave:BrokenSlave")
    with pytest.raises(UserError) as err:
        build.build_all(tmp_path / "fmus", names=["Broken"])
    message = str(err.value)
    assert message.startswith("component Broken cannot be built: its module "
                              "musclesim_broken_slave fails to import (" + cause)
    assert "\n" not in message and message.endswith(")")
    assert not list((tmp_path / "fmus").glob("*.fmu"))
