"""The own benches' cases of the blind benchmark (musclesim.benchmark.cases): each bench's
effects drawn from their own streams, reproducible from the seed, one draw for every instance
of a component; the multiplier's cases apart from the others (§capstan-multiplier,
§named-effects)."""
from musclesim.benchmark import cases as own
from musclesim.diagnosis import effects


def test_the_crawlers_effects_hide_one_draw_in_every_actuator():
    """The pneumatic crawler's effects are in the blind plan (their own stream), one magnitude
    for every instance of the component."""
    cases = own.plan(60, seed=1)
    crawler = [c for c in cases if c["bench"] == "crawler"]
    assert crawler and all(c["kind"] == "effect" for c in crawler)
    assert {c["effect"] for c in crawler} <= set(own.BENCHES["crawler"][3])
    for c in crawler:
        by_par = {}
        for key, v in c["values"].items():
            by_par.setdefault(key.split(".", 1)[1], set()).add(v)
        assert all(len(vs) == 1 for vs in by_par.values()), c  # one draw per parameter
    assert own.plan(60, seed=1) == cases  # reproducible from the seed


def test_the_weight_bench_hides_the_weights_inertia():
    """Load inertia is in the blind plan (on the weight bench, from the load benches' stream)."""
    cases = own.plan(20, seed=1)
    weight = [c for c in cases if c["bench"] == "weight"]
    assert weight and all(c["effect"] == "load inertia" for c in weight)
    assert all(0.3 <= c["values"]["weight.inertia"] <= 1.0 for c in weight)


def test_multiplier_cases_are_drawn_from_their_own_stream():
    cases = own.plan_multiplier(30, seed=2)
    assert cases == own.plan_multiplier(30, seed=2)
    assert [c["case"] for c in cases[:2]] == ["case-m000", "case-m001"]
    assert {c["bench"] for c in cases} == {"multiplier"}
    drawn = {c["effect"] for c in cases if c["kind"] == "effect"}
    assert drawn == set(own.BENCHES["multiplier"][3])
    assert 0 < sum(c["kind"] == "none" for c in cases) < 15
    for c in cases:
        for (inst, par, lo, hi) in own.MAGNITUDES.get(c["effect"], []):
            assert lo <= abs(c["values"][f"{inst}.{par}"]) <= hi
    # every effect of the bench is in the library, on a component the bench has
    for name in own.BENCHES["multiplier"][3]:
        assert effects.find(name).component in ("CapstanMultiplier", "DeadWeight")
