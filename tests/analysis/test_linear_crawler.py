"""musclesim.analysis.linear_crawler: the crawler body's controllability (§two-mass) with
python-control, API and command line."""
import json

import numpy as np
import pytest

from musclesim import cli
from musclesim.analysis import linear_crawler
from musclesim.components.crawler.body import BodyParams


@pytest.mark.parametrize("m1, m2", [(0.2, 0.2), (0.3, 0.2), (0.15, 0.4)])
def test_controllability_ranks_and_subspace(m1, m2):
    r = linear_crawler.crawler(BodyParams(m1=m1, m2=m2))
    assert r["rank_fa_only"] == 2
    assert r["rank_all_inputs"] == 4
    expected = [[1, 0, -m1 / m2, 0], [0, 1, 0, -m1 / m2]]  # §two-mass
    np.testing.assert_allclose(r["controllable_subspace_fa_only"], expected, atol=1e-9)
    assert r["centre_of_mass_reachable_fa_only"] is False


def test_cli_json_and_text(capsys):
    assert cli.main(["linear", "crawler", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["rank_fa_only"], report["rank_all_inputs"]) == (2, 4)
    assert cli.main(["linear", "crawler"]) == 0
    text = capsys.readouterr().out
    assert "2 of 4" in text and "4 of 4" in text and "no locomotion without friction" in text
