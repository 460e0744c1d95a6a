"""musclesim.errors: `UserError`, the one exception for a mistake a user can fix, is what the
command line prints as one sentence (exit status 2) where any other exception is a bug shown with
its traceback; it is no ValueError, so a layer's `except ValueError` never swallows it."""
import pytest

from musclesim import cli
from musclesim.errors import UserError


def test_a_user_error_is_its_own_kind_of_exception():
    assert issubclass(UserError, Exception) and not issubclass(UserError, ValueError)
    with pytest.raises(UserError, match="^wire.T_amb: not a number$"):
        raise UserError("wire.T_amb: not a number")


def test_the_command_line_prints_a_user_error_as_one_sentence(tmp_path, capsys):
    missing = tmp_path / "nowhere.toml"
    assert cli.main(["run", str(missing), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("musclesim: ") and "nowhere.toml" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
