"""Write the diagnosis's worked examples (README, "Diagnosis"): two measured data sets recorded on
the virtual SMA benches with one effect hidden, plus the benches' nuisances (thermocouple noise
and quantisation, strain-gauge noise, quantisation and a one-sample latency).

    .venv/bin/python scenarios/data/make_examples.py      (from the repository's root)

- sma-tracking-thermocouple-lag: the tracking bench, thermocouple with a 0.25 s lag;
- sma-stress-ignored: the stress bench, whose model ignores stress, on a wire that follows it.
"""
from pathlib import Path

from musclesim import blind

HERE = Path(__file__).parent
EXAMPLES = {
    "sma-tracking-thermocouple-lag": (
        {"bench": "tracking", "values": {"thermocouple.tau": 0.25}},
        "SMA wire temperature tracking on the bench (PID, 125 MPa); the thermocouple's lag is "
        "not in the model"),
    "sma-stress-ignored": (
        {"bench": "stress", "values": {"wire.stress_blend": 1.0}},
        "SMA wire heated by a voltage wave under a 105..145 MPa load; the model uses one 125 MPa "
        "surface"),
}

if __name__ == "__main__":
    for i, (name, (truth, description)) in enumerate(EXAMPLES.items()):
        case = {"case": name, "latency_samples": 1, "seed": 100 + i, "strain_gain": 1.0, **truth}
        time, cols = blind.record(case, HERE.parent, HERE.parent.parent / "fmus")
        scenario, inputs, outputs, _ = blind.BENCHES[case["bench"]]
        blind.write_data_set(HERE / name, time, cols, inputs, outputs, scenario, description)
        print(f"wrote {HERE / name}")
