"""The report's ``consistency`` sentence: whether observed signals that share an upstream state
place the gap in a sensor or in the plant (`cross_signal`)."""
from musclesim.diagnosis.problem import affected, downstream
from musclesim.diagnosis.thresholds import DEVIATES

__all__ = ["cross_signal"]


def cross_signal(unit, entries, selected):
    """Where the gap lies, from the observed signals' consistency: the report's
    ``consistency`` sentence, or None when no two observed signals share an upstream state.

    Signals that depend on one unobserved state (the thermocouple and the strain on the wire's
    temperature) locate a difference: an effect that changes only its sensor's channel, the
    other signals agreeing with the calibrated plant, places the gap in the sensor; an effect of
    the plant must improve every signal downstream of it together.
    """
    shared = {inst: affected(unit, (inst,)) for inst in unit.instances}
    shared = {i: cols for i, cols in shared.items() if len(cols) > 1}
    if not shared or not entries:
        return None
    # the nearest common source: of those feeding the most signals, the one feeding fewest
    # instances (the wire, not the load that pulls on it)
    most = max(len(cols) for cols in shared.values())
    source = min((i for i in shared if len(shared[i]) == most),
                 key=lambda i: len(downstream(unit, (i,))))
    e = selected[0] if selected else entries[0]
    j = e.get("judged")
    if not j:
        return None
    ps = e.get("per_signal", {})

    def change(cols):
        return ", ".join(f"{c} {ps[c]['before']:.3g} -> {ps[c]['after']:.3g}" for c in cols
                         if c in ps)

    others = [c for c in shared[source] if c not in j["signals"] and c in ps]
    what = "The selected" if selected else "The best-ranked (not counting)"
    unsure = "" if e["counts"] else " (it does not count, so nothing is placed)"
    if others:
        agree = [c for c in others if ps[c]["after"] <= DEVIATES * unit.noise[c]]
        tail = (f"with it (the calibration refitted) {_names(others)} agree with the model of "
                f"{source} within the noise ({change(others)}): the gap is placed in the sensor, "
                f"not in {source}" if len(agree) == len(others) else
                f"{_names(c for c in others if c not in agree)} still deviate "
                f"({change(others)}): {source} differs from its model too")
        return (f"{_names(shared[source])} all depend on the state of {source}. {what} "
                f"{e['label']} can change only {_names(j['signals'])} "
                f"({change(j['signals'])}); {tail}{unsure}.")
    return (f"{_names(shared[source])} all depend on the state of {source}; {what.lower()} "
            f"{e['label']} acts on it and changes them together ({change(j['signals'])}): the gap "
            f"is placed in {source}, where the signals agree, not in one sensor{unsure}.")


def _names(signals):
    """`signals` printed, comma-separated."""
    return ", ".join(map(str, signals))
