"""musclesim.cosim.build: a component whose module fails to import ends the build in one sentence
naming it and the cause; the build's child process (the cores as plain Python) writes the start
values compiled cores give."""
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


def test_the_build_in_a_child_writes_the_start_values_of_compiled_cores(tmp_path,
                                                                        monkeypatch):
    """The child process that builds runs the cores as plain Python; the model descriptions it
    writes (the start values of every output) are those of a build in this process, compiled."""
    import re
    import zipfile

    names = ["SmaWire", "CrawlerBody", "PreisachInverse"]
    plain = build.build_all(tmp_path / "child", names=names)
    monkeypatch.setattr(build, "COMPILED", False)  # build here, where the cores are compiled
    here = build.build_all(tmp_path / "here", names=names)

    def description(fmu):
        with zipfile.ZipFile(fmu) as zf:
            text = zf.read("modelDescription.xml").decode()
        return re.sub(r'(generationDateAndTime|guid)="[^"]*"', "", text)
    assert [description(f) for f in plain] == [description(f) for f in here]
