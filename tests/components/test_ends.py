"""Cold ends (components/sma/ends.py, §named-effects): the fin profile by hand, the zones' table
and its errors."""
import math

import pytest

from musclesim.components.sma import ends


def test_cold_ends_follow_the_fin_profile():
    # 127 um in still air, k = 18 W/(m K): L_f = sqrt(k d / 4h) = 2.39 mm, G_f = 9.54e-5 W/K
    d, k, h, length = 127e-6, 18.0, 100.0, 58.42e-3
    assert ends.fin_length(d, k, h) == pytest.approx(math.sqrt(18 * 127e-6 / 400), rel=1e-12)
    g_f = ends.fin_conductance(d, k, h)
    assert g_f == pytest.approx(k * (math.pi * d ** 2 / 4) / ends.fin_length(d, k, h), rel=1e-12)
    assert ends.end_cooling(g_f, d, k, h) == pytest.approx(0.5)  # contact = fin: half the excess
    table = ends.zones(0.8, length, d, k, h)
    # both ends' zones cover 2 x 4 L_f; each zone's factor is 1 - beta times exp(-x)'s mean there
    assert sum(w for w, _ in table) == pytest.approx(8 * ends.fin_length(d, k, h) / length)
    assert table[0][1] == pytest.approx(1 - 0.8 * (1 - math.exp(-0.5)) / 0.5)
    assert [g for _, g in table] == sorted(g for _, g in table)  # warmer away from the clamps
    # the excess lost in the zones is beta times the integral of exp(-x / L_f) over 4 L_f, per end
    lost = sum(w * (1 - g) for w, g in table) * length
    assert lost == pytest.approx(2 * 0.8 * ends.fin_length(d, k, h) * (1 - math.exp(-4)))
    assert ends.zone_temperatures(80.0, 20.0, table) == pytest.approx([20 + 60 * g for _, g in table])
    assert ends.zones(0.0, length, d, k, h) == []
    with pytest.raises(ValueError, match="too short"):
        ends.zones(0.5, 10e-3, d, k, h)
    with pytest.raises(ValueError, match="end_cooling"):
        ends.zones(1.5, length, d, k, h)
