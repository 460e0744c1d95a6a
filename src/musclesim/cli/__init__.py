"""The `musclesim` command line: build, run, export, sweep, loops, identify, drift, dataset,
diagnose, calibrate, benchmark-diagnosis, bench, linear, characterise, table.

The top layer: it parses arguments, calls the public interfaces of the layers below (cosim, batch,
analysis, hysteresis, diagnosis, benchmark) and prints; nothing imports it.

Mistakes a user can fix end in one sentence on stderr and exit status 2; a failed simulation
exits with status 1 after writing the results it reached.
"""
import argparse
import json
import math
import sys
from pathlib import Path

from musclesim.errors import UserError

__all__ = ["main"]


def _cmd_build(args):
    from musclesim.cosim import build_all

    for path in build_all(args.fmus, fmi=args.fmi):
        print(f"built {path}")
    return 0


def _cmd_run(args):
    from musclesim.cosim import run_scenario

    summary, res = run_scenario(args.scenario, args.out, args.fmus, args.set, args.stop_time,
                                host=args.host)
    out = Path(args.out)
    if summary["description"]:  # the file's words: overrides may have changed what it says
        print(summary["description"] + (f" (with --set {', '.join(args.set)})" if args.set else ""))
    for name, unit in summary["units"].items():  # a metric without a value: a warning says why
        value = summary[name]
        print(f"{name}: no value" if value is None else f"{name} = {value:.6g} {unit}")
    if (out / "results.png").is_file():  # the previous run's plot is gone: this run's, if drawn
        print(f"wrote {out / 'results.csv'}, {out / 'summary.json'} and {out / 'results.png'}")
    else:  # no plot of fewer than two rows
        print(f"wrote {out / 'results.csv'} and {out / 'summary.json'}")
    for warning in summary["warnings"]:
        print(f"musclesim: warning from {warning}", file=sys.stderr)
    if res.error:
        print(f"musclesim: run stopped: {res.error} (results up to then are kept)", file=sys.stderr)
        return 1
    return 0


def _cmd_export(args):
    from musclesim.cosim import check_fresh, export_fmu, export_ssp, load_scenario

    s = load_scenario(args.scenario, args.set, args.stop_time)
    check_fresh(args.fmus)
    if args.ssp is not None:
        print(f"wrote {export_ssp(s, args.fmus, args.ssp)}")
    else:
        print(f"wrote {export_fmu(s, args.fmus, args.fmu, args.fmi)}")
    return 0


def _cmd_sweep(args):
    from musclesim.batch import run_sweep

    summary = run_sweep(args.scenario, grid=args.grid, out=args.out, fmu_dir=args.fmus,
                        scheduler=args.scheduler, workers=args.workers, overrides=args.set,
                        stop_time=args.stop_time)
    print(json.dumps(summary, indent=2))
    return 1 if summary.get("failed") else 0


def _cmd_linear(args):
    from musclesim.analysis import (bending, crawler, format_bending, format_crawler,
                                    format_pneumatic, format_sma_load, format_sma_thermal,
                                    gain_table_toml, load_gains_toml, pneumatic,
                                    pneumatic_gains_toml, sma_load, sma_thermal)
    from musclesim.cosim import check_fresh, replace_file

    if args.system == "crawler":
        report, text, toml = crawler(), format_crawler, None
    elif args.system == "bending":
        report, text, toml = bending(), format_bending, None
    elif args.system == "sma-thermal":
        report, text, toml = sma_thermal(), format_sma_thermal, gain_table_toml
    elif args.system == "sma-load":
        check_fresh(args.fmus)
        report, text, toml = sma_load(args.fmus), format_sma_load, load_gains_toml
    else:
        check_fresh(args.fmus)
        report, text, toml = pneumatic(args.fmus), format_pneumatic, pneumatic_gains_toml
    if args.write and toml is None:
        raise UserError(f"--write is for sma-thermal, sma-load and pneumatic, not {args.system}")
    written = []
    if args.write and args.system == "pneumatic":  # one file per actuator kind, into a folder
        Path(args.write).mkdir(parents=True, exist_ok=True)
        for actuator in report["loops"]:
            written.append(Path(args.write) / f"pneumatic-{actuator}-pid.toml")
            replace_file(written[-1], toml(report, actuator))
    elif args.write:
        written.append(Path(args.write))
        replace_file(written[-1], toml(report))
    print(json.dumps(report, indent=2) if args.json else text(report))
    for path in written:
        print(f"wrote the gains to {path}", file=sys.stderr)
    return 0


def _cmd_characterise(args):
    from musclesim.analysis import ELONGATION_TARGET, gait_references, gait_references_toml
    from musclesim.cosim import replace_file, run_scenario

    summary, res = run_scenario(args.scenario, args.out, args.fmus, args.set)
    if res.error:
        raise UserError(f"{args.scenario}: the characterisation run stopped: {res.error}")
    refs = gait_references(res)
    print(f"central: {refs['p_central']:.1f} Pa for {ELONGATION_TARGET:g} m "
          f"elongation ({refs['elongation_at_ramp_end']:.4f} m at the end of the ramp)")
    for i, where in ((1, "back"), (2, "front")):
        print(f"{where} extremal: firm ground contact from {refs[f'p_firm{i}']:.1f} Pa, "
              f"reference {refs[f'p_anchor{i}']:.1f} Pa")
    print(f"wrote the run to {args.out}")
    if args.write:
        replace_file(args.write, gait_references_toml(refs, args.scenario))
        print(f"wrote the gait references to {args.write}", file=sys.stderr)
    return 0


def _cmd_loops(args):
    from musclesim.hysteresis import loops_main

    out = loops_main(args.stress, args.band, model_path=args.model, as_json=args.json,
                     plot_path=args.plot)
    print(json.dumps(out, indent=2) if args.json else out)
    return 0


def _cmd_drift(args):
    from musclesim.hysteresis import DriftProtocol, drift_main

    protocol = DriftProtocol(rounds=args.rounds, cycles=args.cycles,
                             samples_per_cycle=args.samples_per_cycle,
                             compare=tuple(args.compare))
    protocol.check()
    print(drift_main(args.scenario, protocol, as_json=args.json))
    return 0


def _cmd_bench(args):
    from musclesim.hysteresis import format_preisach_timing, preisach_timing

    report = preisach_timing()
    print(json.dumps(report, indent=2) if args.json else format_preisach_timing(report))
    return 0


def _cmd_identify(args):
    from musclesim.hysteresis import identify_main

    out = identify_main(args.records, args.out, validate=args.validate, as_json=args.json)
    print(json.dumps(out, indent=2) if args.json else out)
    return 0


def _cmd_dataset_check(args):
    from musclesim.diagnosis import load_dataset

    ds = load_dataset(args.dataset, check_model=args.model, fmu_dir=args.fmus)
    train, held = ds.parts()
    kind = "scalar-only" if ds.scalar_only else f"{len(ds.time)} samples, {len(ds.columns)} columns"
    print(f"{ds.path}: OK ({kind}; experiments {', '.join(ds.experiments)}; "
          f"train {', '.join(train)}; held out {', '.join(held)})")
    return 0


def _cmd_diagnose(args):
    from musclesim.batch import dask_client, dask_map
    from musclesim.cosim import check_fresh
    from musclesim.diagnosis import diagnose, load_dataset, write_report

    models = {}
    for item in args.model:
        experiment, sep, ref = item.rpartition("=")
        if not ref:
            raise UserError(f"--model {item!r}: give SCENARIO or EXPERIMENT=SCENARIO")
        models[experiment if sep else "*"] = ref
    ds = load_dataset(args.dataset, check_model=True, fmu_dir=args.fmus, models=models)
    check_fresh(args.fmus)
    traces = {}
    with dask_client(args.scheduler, args.workers) as client:
        report = diagnose(ds, args.fmus, dask_map(client),
                          lambda text: print(f"musclesim: {text}", file=sys.stderr), traces)
    paths = write_report(args.out, report, traces)
    print(f"verdict: {report['verdict']} ({report['explanation']})")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def _cmd_calibrate(args):
    import json
    from pathlib import Path

    from musclesim.batch import dask_client, dask_map
    from musclesim.cosim import check_fresh
    from musclesim.diagnosis import calibrate, calibration_markdown, load_dataset

    ds = load_dataset(args.dataset, check_model=True, fmu_dir=args.fmus)
    check_fresh(args.fmus)
    with dask_client(args.scheduler, args.workers) as client:
        report = calibrate(ds, args.fmus, dask_map(client),
                           lambda text: print(f"musclesim: {text}", file=sys.stderr))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "calibration.json").write_text(json.dumps(report, indent=1) + "\n")
    text = calibration_markdown(report)
    (out / "calibration.md").write_text(text)
    print(text, end="")
    print(f"wrote {out / 'calibration.json'}, {out / 'calibration.md'}")
    return 0


def _cmd_benchmark_diagnosis(args):
    from musclesim.batch import dask_client, dask_map
    from musclesim.cosim import check_fresh
    from musclesim.benchmark import run_blind_benchmark

    check_fresh(args.fmus)
    with dask_client(args.scheduler, args.workers) as client:
        scores = run_blind_benchmark(args.cases, args.seed, args.out, args.fmus, args.scenarios,
                                     dask_map(client),
                                     lambda text: print(f"musclesim: {text}", file=sys.stderr),
                                     bench=args.bench, duration=args.duration,
                                     multiplier=args.multiplier, crawler=args.crawler)
    print(json.dumps({k: v for k, v in scores.items() if k != "per_case"}, indent=2))
    print(f"wrote {Path(args.out) / 'scores.json'} (per-case table inside)")
    return 0


def _cmd_table(args):
    from musclesim.analysis import sma_position

    report = sma_position(args.out, args.scenario, args.fmus, args.stop_time,
                          args.scheduler, args.workers, args.only, run=not args.no_run)
    for name, stats in report.items():
        if stats["cells"] == 0:
            print(f"{name}: no case finished yet")
        else:
            print(f"{name}: {stats['cells']} cells, mean strain RMSE {stats['rmse'][0]:.4g} "
                  f"(std {stats['rmse'][1]:.3g}), {stats['percent'][0]:.3g} % of the maximum "
                  "reference strain")
        for cid, error in stats["failed"].items():
            print(f"  case {cid} failed: {error}")
    print(f"wrote the tables (CSV, Markdown) and the per-case figures into {args.out}")
    return 1 if any(stats["failed"] for stats in report.values()) else 0


def _parser():
    from musclesim import __version__

    p = argparse.ArgumentParser(
        prog="musclesim", description="Artificial-muscle physics as FMI co-simulation components: "
        "build the FMUs, run and sweep scenarios, analyse, and diagnose a model's gap to a bench.")
    p.add_argument("--version", action="version", version=f"musclesim {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    def common(q):
        q.add_argument("--fmus", default="fmus", help="folder of built FMUs (default: fmus)")

    def scenario_args(q):
        q.add_argument("scenario", help="scenario TOML file (for sweep: or a sweep file)")
        q.add_argument("--set", action="append", default=[], metavar="INST.PARAM=VALUE",
                       help="override a parameter (repeatable)")
        q.add_argument("--stop-time", type=float, help="replace the scenario's stop time [s]")
        common(q)

    q = sub.add_parser("build", help="build every component into FMUs")
    q.add_argument("--fmus", help="folder to build into (default: fmus; fmus3 with --fmi 3)")
    q.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                   help="FMI version: 2.0 co-simulation FMUs (default) or 3.0 ones, from the "
                   "same slaves; the runner runs either")
    q.set_defaults(func=_cmd_build)

    q = sub.add_parser("run", help="run a scenario, write results.csv, summary.json, a plot")
    scenario_args(q)
    q.add_argument("--out", required=True, help="output folder")
    q.add_argument("--host", choices=("direct", "fmpy"), default="direct",
                   help="who calls the FMUs `musclesim build` made: this process directly "
                   "(default) or fmpy, through the FMI C API; the results are the same bits "
                   "(other FMUs always run on fmpy)")
    q.set_defaults(func=_cmd_run)

    q = sub.add_parser("export", help="export a scenario as an SSP archive or as one FMU")
    scenario_args(q)
    to = q.add_mutually_exclusive_group(required=True)
    to.add_argument("--ssp", help="the .ssp file to write (SSP 1.0: the scenario's FMUs, wiring "
                    "and values)")
    to.add_argument("--fmu", help="the .fmu file to write: the whole scenario as one "
                    "co-simulation FMU (FMPy's container FMU; Jacobi scenarios)")
    q.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                   help="with --fmu: FMI 2.0 (default) or 3.0 for the one FMU; the FMUs inside "
                   "are those in --fmus, of either version")
    q.set_defaults(func=_cmd_export)

    q = sub.add_parser("sweep", help="run a scenario over a parameter grid on Dask")
    scenario_args(q)
    q.add_argument("--grid", action="append", default=[], metavar="INST.PARAM=START:STOP:N",
                   help="a grid axis (repeatable)")
    q.add_argument("--out", required=True, help="output folder (one result per case)")
    q.add_argument("--scheduler", help="address of an existing Dask scheduler")
    q.add_argument("--workers", type=_positive, help="workers of the local cluster")
    q.set_defaults(func=_cmd_sweep)

    q = sub.add_parser("loops", help="steady strain loops of cycled temperature bands (SMA wire)")
    q.add_argument("--stress", type=float, required=True, help="constant stress [Pa]")
    q.add_argument("--band", action="append", required=True, metavar="T_LO:T_HI",
                   help="temperature band in C (repeatable)")
    q.add_argument("--model", help="FORC data file, or a wire parameter .toml (default: the "
                                   "reference wire)")
    q.add_argument("--plot", help="write the loops plot to this PNG")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_loops)

    q = sub.add_parser("drift", help="the long-duration drift test: RMSE between the "
                                     "averaged loops of tests 1, 13 and 25 per stress")
    q.add_argument("scenario", nargs="?", default="scenarios/sma-drift.toml",
                   help="scenario whose instance 'wire' sets the drift (default: "
                        "scenarios/sma-drift.toml)")
    q.add_argument("--rounds", type=_positive, default=25, help="rounds of the five stresses")
    q.add_argument("--cycles", type=_positive, default=20, help="cycles per test")
    q.add_argument("--samples-per-cycle", type=_positive, default=200,
                   help="temperature samples per 20 s cycle")
    q.add_argument("--compare", type=_positive, nargs="+", default=[1, 13, 25],
                   metavar="TEST", help="tests whose averaged loops are compared, in pairs")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_drift)

    q = sub.add_parser("identify", help="FORC surfaces from identification records (SMA wire)")
    q.add_argument("records", nargs="+",
                   help="sweep output folder, run folders or results.csv files (one per stress)")
    q.add_argument("--out", required=True, help="the FORC data file to write")
    q.add_argument("--validate", action="store_true",
                   help="also report errors against the virtual wire")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_identify)

    q = sub.add_parser("dataset", help="measured data sets (sim-to-real diagnosis)")
    actions = q.add_subparsers(dest="action", required=True)
    c = actions.add_parser("check", help="validate a data set, reporting every problem at once")
    c.add_argument("dataset", help="data set directory (manifest.toml [+ data.csv])")
    c.add_argument("--model", action="store_true",
                   help="also check it against its scenario and the FMUs")
    common(c)
    c.set_defaults(func=_cmd_dataset_check)

    def dask_args(q):
        q.add_argument("--scheduler", help="address of a running Dask scheduler (default: a "
                       "local cluster)")
        q.add_argument("--workers", type=_positive,
                       help="local worker processes (default: cores)")

    q = sub.add_parser("diagnose", help="sim-to-real gap diagnosis of a measured data set")
    q.add_argument("dataset", help="data set folder (manifest.toml + data.csv)")
    q.add_argument("--out", required=True, help="folder for report.json, report.md and plots")
    q.add_argument("--model", action="append", default=[], metavar="[EXPERIMENT=]SCENARIO",
                   help="diagnose against this scenario instead of the manifest's (for every "
                   "experiment, or the one named; repeatable)")
    dask_args(q)
    common(q)
    q.set_defaults(func=_cmd_diagnose)

    q = sub.add_parser("calibrate", help="fit the open values a scalar-only data set names "
                       "([[calibrate]]) to its training metrics; predict the held-out ones")
    q.add_argument("dataset", help="data set folder (manifest.toml)")
    q.add_argument("--out", required=True, help="folder for calibration.json and calibration.md")
    dask_args(q)
    common(q)
    q.set_defaults(func=_cmd_calibrate)

    q = sub.add_parser("benchmark-diagnosis",
                       help="blind check of the diagnosis on virtual hardware with hidden effects")
    q.add_argument("--cases", type=_count, default=40,
                   help="number of cases (default 40; 0 with --crawler: crawler cases only)")
    q.add_argument("--seed", type=int, default=1, help="seed of the hidden truths (default 1)")
    q.add_argument("--out", required=True, help="folder for the cases, key and scores.json")
    q.add_argument("--scenarios", default="scenarios", help="folder of the bench scenarios")
    q.add_argument("--bench", choices=["own", "independent"], default="own",
                   help="own: the library's FMUs with hidden effects (default); independent: "
                        "an SMA bench written apart from the library (scores under "
                        "'independent' in scores.json)")
    q.add_argument("--duration", type=_duration, default=None,
                   help="independent bench: seconds recorded per SMA case (default 120)")
    q.add_argument("--multiplier", type=_positive, default=0, metavar="N",
                   help="own bench: N extra cases on the capstan multiplier's bench "
                        "(default none)")
    q.add_argument("--crawler", type=_positive, default=0, metavar="N",
                   help="independent bench: N extra cases on its pneumatic crawler, 12 s each "
                        "(default none; scores also per bench)")
    dask_args(q)
    common(q)
    q.set_defaults(func=_cmd_benchmark_diagnosis, subparser=q)

    q = sub.add_parser("table", help="the study's tables: sma-position (the position-control "
                                     "matrix, on Dask)")
    q.add_argument("table", choices=["sma-position"], help="which tables")
    q.add_argument("--out", required=True, help="folder for the cases, tables and figures")
    q.add_argument("--scenario", default="scenarios/sma-position-control.toml",
                   help="the position-control scenario the cases override")
    q.add_argument("--stop-time", type=float, help="shorter runs than the scenario's 550 s")
    q.add_argument("--only", action="append", choices=["constant-stress", "stress-aware",
                                                       "stress-ignored"],
                   help="run only these tables (repeatable)")
    q.add_argument("--no-run", action="store_true",
                   help="run no case: write the tables and figures of the cases finished so far")
    dask_args(q)
    common(q)
    q.set_defaults(func=_cmd_table)

    q = sub.add_parser("bench", help="timing benchmarks of the pure cores (on demand)")
    q.add_argument("core", choices=["preisach"], help="the core to time")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.set_defaults(func=_cmd_bench)

    q = sub.add_parser("characterise", help="the crawler's characterisation: the gait's pressure "
                                            "references")
    q.add_argument("scenario", nargs="?", default="scenarios/crawler-characterisation.toml",
                   help="the characterisation scenario (default: %(default)s)")
    q.add_argument("--out", default="results/crawler-characterisation",
                   help="folder for the run's results (default: %(default)s)")
    q.add_argument("--write", metavar="FILE", help="write the references (TOML) the gait "
                                                   "scenarios read")
    q.add_argument("--set", action="append", default=[], metavar="INST.PARAM=VALUE",
                   help="override a parameter (repeatable)")
    common(q)
    q.set_defaults(func=_cmd_characterise)

    q = sub.add_parser("linear", help="linear analysis with python-control")
    q.add_argument("system", choices=["crawler", "sma-thermal", "sma-load", "pneumatic",
                                      "bending"],
                   help="the system to analyse")
    q.add_argument("--json", action="store_true", help="print JSON instead of text")
    q.add_argument("--write", metavar="FILE", help="sma-thermal, sma-load: write the controller "
                   "parameters (TOML) a scenario can read; pneumatic: a folder that receives "
                   "pneumatic-central-pid.toml and pneumatic-extremal-pid.toml")
    common(q)
    q.set_defaults(func=_cmd_linear)
    return p


def _count(text):
    """argparse type: an integer of at least 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text} must be at least 0")
    return value


def _positive(text):
    """argparse type: an integer of at least 1."""
    value = _count(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text} must be at least 1")
    return value


def _duration(text):
    """argparse type: seconds recorded per independent bench case, at least one reference
    period (10 s)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not math.isfinite(value) or value < 10:
        raise argparse.ArgumentTypeError(f"{text} s is shorter than one period of the bench's "
                                         "reference (10 s)")
    return value


# every command's outputs, checked before the command does any work: (option, folder or file)
_OUTPUTS = {"build": [("fmus", "dir")], "run": [("out", "dir")],
            "export": [("ssp", "file"), ("fmu", "file")],
            "sweep": [("out", "dir")], "loops": [("plot", "file")], "identify": [("out", "file")],
            "diagnose": [("out", "dir")], "calibrate": [("out", "dir")],
            "benchmark-diagnosis": [("out", "dir")],
            "table": [("out", "dir")], "characterise": [("out", "dir"), ("write", "file")],
            "linear": [("write", "file")]}


def _check_outputs(args):
    from musclesim.cosim import check_output_dir, check_output_file

    for option, kind in _OUTPUTS.get(args.command, ()):
        path = getattr(args, option)
        if path is None:
            continue
        if kind == "dir" or (args.command == "linear" and args.system == "pneumatic"):
            check_output_dir(path, f"--{option}")
        else:
            check_output_file(path, f"--{option}")


def main(argv=None):
    """Entry point of the `musclesim` console script.

    Exit status: 0 done, 1 a run or case failed (its results kept), 2 a mistake in the input,
    130 / 143 stopped by SIGINT / SIGTERM (what was written so far is kept).
    """
    args = _parser().parse_args(argv)
    if args.command == "build" and args.fmus is None:  # each FMI version its own folder
        args.fmus = "fmus" if args.fmi == 2 else "fmus3"
    if getattr(args, "cases", None) == 0 and not args.crawler:  # benchmark-diagnosis
        args.subparser.error("argument --cases: 0 must be at least 1 (0 only with --crawler)")
    try:
        from musclesim.cosim import Interrupted, interruptible

        with interruptible():
            _check_outputs(args)
            return args.func(args)
    except UserError as exc:
        print(f"musclesim: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C before the handlers were in place (while importing);
        # first, since the name Interrupted below is unbound until that import is done
        print("musclesim: interrupted by SIGINT before any work", file=sys.stderr)
        return 130
    except Interrupted as exc:
        print(f"musclesim: {exc}; what was written so far is kept", file=sys.stderr)
        return exc.exit_code


if __name__ == "__main__":
    sys.exit(main())
