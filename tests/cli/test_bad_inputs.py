"""Issue 21, item 7: a corpus of bad inputs and interruptions of the command line.

Every case asserts the exit status (2 a mistake in the input, 1 a failed run, 130 / 143 a signal),
one sentence on stderr starting with ``musclesim: `` that names the culprit, no traceback, and
what is on disk afterwards: a refused command leaves its workspace (``tmp_path``, the current
folder during the test, holding the previous run's outputs) exactly as it was, creates nothing,
prints nothing on stdout (no work was done) and leaves no ``musclesim_run_<pid>_*`` folder.

The commands run in this process (``cli.main``); only the signal tests and a crash start a
subprocess.
"""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import warnings
import zipfile
from pathlib import Path
from types import SimpleNamespace

import pytest

from musclesim import cli

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"
POSITION = SCENARIOS / "sma-position-control.toml"
MEASURED = SCENARIOS / "data" / "sma-stress-ignored"
STUDY = SCENARIOS / "data" / "study-fast-actuation"
CRAWLER_FMUS = ("CrawlerBody", "FrictionBlock", "FrictionSwitchingInputs")  # what IDEAL uses
PREVIOUS = {"summary.json": '{"run_id": "previous", "completed": true, "status": "completed"}\n',
            "results.csv": "time,previous.run\n0,0\n0.001,1e-06\n",
            "results.png": "not really a PNG\n"}


# ---- helpers ------------------------------------------------------------------------------------

def run(capsys, *argv):
    """Exit status, stdout and stderr of ``musclesim ARGV`` run in this process (argparse's
    refusals end in SystemExit, as from the console script). Python warnings, which pytest would
    otherwise collect, are added to stderr, where the console script prints them."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            code = cli.main([str(a) for a in argv])
        except SystemExit as exc:
            code = exc.code
    out, err = capsys.readouterr()
    err += "".join(warnings.formatwarning(w.message, w.category, w.filename, w.lineno)
                   for w in caught)
    return code, out, err


def assert_one_sentence(err, out, culprits, forbidden=()):
    """stderr is one line, ``musclesim: ...``, naming every culprit; no traceback anywhere and
    none of the `forbidden` strings (values read from a file that are not ours to print)."""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("musclesim: "), err
    for culprit in culprits:
        assert str(culprit) in lines[0], (culprit, err)
    assert "Traceback" not in err + out
    for secret in forbidden:
        assert secret not in err + out


def snapshot(*roots):
    """Every file, folder and link under `roots`: kind, size, modification time, and for files up
    to 64 kB a digest of the content, so that any file created, removed or rewritten shows."""
    state = {}
    for root in roots:
        for dirpath, dirnames, filenames in os.walk(root):
            for name in dirnames + filenames:
                p = Path(dirpath) / name
                st = p.lstat()
                if p.is_symlink():
                    state[p] = ("link", os.readlink(p))
                elif p.is_dir():
                    state[p] = ("dir",)
                else:
                    digest = hashlib.sha256(p.read_bytes()).hexdigest() if st.st_size <= 65536 \
                        else None
                    state[p] = ("file", st.st_size, st.st_mtime_ns, digest)
    return state


def run_folders(pid=None):
    """The temporary folders of the runs of process `pid` (default: this one)."""
    return sorted(Path(tempfile.gettempdir()).glob(f"musclesim_run_{pid or os.getpid()}_*"))


def half_written(root):
    """Files a write in progress would leave: ``.name.tmp``, ``.stem.tmp.png``, output probes."""
    return sorted(p for p in Path(root).rglob(".*") if ".tmp" in p.name or "probe" in p.name)


def csv_header(path):
    """The header of a results file: its first line, split (plain CSV, no comment line)."""
    return Path(path).read_text().splitlines()[0].split(",")


@pytest.fixture
def ws(tmp_path, fmu_dir, monkeypatch):
    """A workspace in tmp_path, the current folder: a previous run's outputs in out/, a file,
    an empty folder, and writers of modified scenario copies and of tampered FMUs."""
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    for name, text in PREVIOUS.items():
        (out / name).write_text(text)
    (tmp_path / "afile").write_text("a file, not a folder\n")
    (tmp_path / "afolder").mkdir()

    def scenario(*replacements, name="bad.toml", base=IDEAL):
        text = base.read_text()
        for old, new in zip(replacements[::2], replacements[1::2]):
            assert old in text, old
            text = text.replace(old, new, 1)
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        return path

    def fmus(edit=None, extra=(), with_stamp=False, name="foreign", replace=None):
        """A folder with copies of the crawler's FMUs, FrictionBlock.fmu rewritten: `edit(entry
        name, bytes)` returns the new bytes (None drops the entry), `extra` entries (name or
        ZipInfo, bytes) are added, or `replace` gives the file's whole content. Without BUILD.json
        (`with_stamp` False) the FMUs are foreign: no digest protects them, the reader must."""
        folder = tmp_path / name
        folder.mkdir()
        for comp in CRAWLER_FMUS:
            shutil.copy(fmu_dir / f"{comp}.fmu", folder)
        if with_stamp:
            shutil.copy(fmu_dir / "BUILD.json", folder)
        target = folder / "FrictionBlock.fmu"
        if replace is not None:
            target.write_bytes(replace(target.read_bytes()))
            return folder
        with zipfile.ZipFile(fmu_dir / "FrictionBlock.fmu") as src, \
                zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as dst:
            for info in src.infolist():
                data = src.read(info)
                if edit is not None:
                    data = edit(info.filename, data)
                if data is not None:
                    dst.writestr(info.filename, data)
            for entry, data in extra:
                dst.writestr(entry, data)
        return folder

    def crawler_dataset(name="ds-crawler"):
        """A measured data set whose model is a copy of the crawler scenario beside it."""
        folder = tmp_path / name
        folder.mkdir()
        shutil.copy(IDEAL, folder / "crawler-ideal.toml")
        (folder / "manifest.toml").write_text('scenario = "crawler-ideal.toml"\n'
                                              'outputs = ["body.x_cm"]\n'
                                              "[split]\nheld_out_fraction = 0.5\n")
        (folder / "data.csv").write_text("time,body.x_cm\n0,0\n0.5,0.01\n1,0.02\n1.5,0.03\n")
        return folder

    return SimpleNamespace(root=tmp_path, out=out, afile=tmp_path / "afile",
                           afolder=tmp_path / "afolder", fmus_dir=fmu_dir, scenario=scenario,
                           fmus=fmus, crawler_dataset=crawler_dataset)


def run_argv(ws, scenario, *extra, fmus=None):
    return ["run", scenario, "--out", ws.out, "--fmus", fmus or ws.fmus_dir, *extra]


def in_description(old, new):
    """An `edit` for `ws.fmus` replacing text in modelDescription.xml."""
    def edit(name, data):
        if name != "modelDescription.xml":
            return data
        assert old in data
        return data.replace(old, new, 1)
    return edit


def symlink_entry(name):
    info = zipfile.ZipInfo(name)
    info.external_attr = 0o120777 << 16  # a symbolic link, as `zip --symlinks` stores one
    return info


def extends_cycle(ws):
    (ws.root / "a.toml").write_text('extends = "b.toml"\nname = "a"\n')
    (ws.root / "b.toml").write_text('extends = "a.toml"\nname = "b"\n')
    return run_argv(ws, ws.root / "a.toml"), ["extends itself through", ws.root / "a.toml",
                                              ws.root / "b.toml"]


def parameters_file(ws, reference, content=None, link_to=None):
    """A scenario in sub/ whose body reads `reference`; the file is written with `content`
    (or is a link to `link_to`) when given."""
    sub = ws.root / "sub"
    sub.mkdir()
    if content is not None:
        (sub / reference).write_text(content)
    if link_to is not None:
        link_to.write_text(content or 'api_token = "s3cret-value"\n')
        (sub / reference).symlink_to(link_to)
    return ws.scenario('component = "CrawlerBody"',
                       f'component = "CrawlerBody"\nparameters_file = "{reference}"',
                       name="sub/scenario.toml")


def sweep_file(ws, plot):
    path = ws.root / "sweep.toml"
    path.write_text(f'[sweep]\nscenario = "{IDEAL}"\ngrid = ["inputs.phi=0:1:2"]\n'
                    f"[sweep.plot]\n{plot}\n")
    return path


def measured(ws, manifest, data):
    folder = ws.root / "ds"
    folder.mkdir()
    (folder / "manifest.toml").write_text(manifest)
    (folder / "data.csv").write_text(data)
    return folder


def forc_file(ws, strain):
    """A FORC data file (two temperatures, one stress) whose line 3 holds `strain`."""
    path = ws.root / "forc.csv"
    path.write_text(f"stress_Pa,a_C,b_C,F\n1e8,30,30,0\n1e8,35,30,{strain}\n1e8,35,35,0\n")
    return path


SMA_MANIFEST = ('scenario = "{}"\ninputs = ["wire.u"]\noutputs = ["wire.strain"]\n'
                "[split]\nheld_out_fraction = 0.5\n")
CELSIUS_MANIFEST = (f'scenario = "{SCENARIOS / "sma-bench-stress.toml"}"\ninputs = ["wire.u"]\n'
                    'outputs = ["wire.T"]\n[split]\nheld_out_fraction = 0.5\n')
SMA_DATA = "time,wire.u,wire.strain\n0,0.1,0\n0.1,{},0\n0.2,0.1,0\n0.3,0.1,0\n"
BIG_COMMENT = b"<!--" + b" " * (20 * 2**20) + b"-->"  # 20 MiB; deflates to ~20 kB


# ---- refused before any work: exit 2, one sentence, the workspace untouched ---------------------
# id -> ws -> (argv, the culprits the sentence must name[, strings it must not print])
REFUSED = {
    # the scenario file
    "scenario-is-a-folder": lambda ws: (
        run_argv(ws, SCENARIOS), [SCENARIOS, "is a folder, not a scenario file"]),
    "scenario-does-not-exist": lambda ws: (
        run_argv(ws, ws.root / "nope.toml"), [ws.root / "nope.toml", "does not exist"]),
    "scenario-malformed-toml": lambda ws: (
        run_argv(ws, ws.scenario("[metrics]", "[metrics\n")), [ws.root / "bad.toml",
                                                                "is not valid TOML"]),
    "scenario-unknown-key": lambda ws: (
        run_argv(ws, ws.scenario("stop_time = 60.0", "stop_time = 60.0\nstoptime = 2.0")),
        ["unknown key 'stoptime'"]),
    "scenario-extends-cycle": extends_cycle,
    "scenario-extends-missing-file": lambda ws: (
        run_argv(ws, ws.scenario('name = "crawler-ideal"', 'extends = "gone.toml"')),
        [ws.root / "gone.toml", "cannot be read"]),
    "component-relative-path": lambda ws: (
        run_argv(ws, ws.scenario('component = "FrictionBlock"',
                                 'component = "../x/FrictionBlock"')),
        ["instance 'friction1'", "'../x/FrictionBlock'", "not a path"]),
    "component-absolute-path": lambda ws: (
        run_argv(ws, ws.scenario('component = "FrictionBlock"',
                                 'component = "/abs/FrictionBlock"')),
        ["instance 'friction1'", "'/abs/FrictionBlock'", "not a path"]),
    "parameters-file-etc-passwd": lambda ws: (
        run_argv(ws, parameters_file(ws, "../../../etc/passwd")),
        ["instance 'body'", "'../../../etc/passwd'", "lies outside the scenario's folder"],
        ["root:"]),
    "parameters-file-link-out-of-folder": lambda ws: (
        run_argv(ws, parameters_file(ws, "link.toml", link_to=ws.root / "outside.toml")),
        ["'link.toml'", "lies outside the scenario's folder"], ["s3cret-value"]),
    "parameters-file-holds-a-secret": lambda ws: (
        run_argv(ws, parameters_file(ws, "body.toml", 'm1 = 0.3\napi_token = "s3cret-value"\n')),
        ["instance 'body'", ws.root / "sub" / "body.toml", "api_token"], ["s3cret-value"]),
    # limits of time and size
    "step-1e-12-for-1e6-s": lambda ws: (
        run_argv(ws, ws.scenario("step = 1e-3", "step = 1e-12"), "--stop-time", "1e6"),
        ["step 1e-12 s", "smallest allowed"]),
    "step-1e-300": lambda ws: (
        run_argv(ws, ws.scenario("step = 1e-3", "step = 1e-300")), ["step 1e-300 s"]),
    "too-many-steps": lambda ws: (
        run_argv(ws, ws.scenario("step = 1e-3", "step = 1e-7"), "--stop-time", "1e6"),
        ["1e+06 s in steps of 1e-07 s", "more than the 100,000,000"]),
    "stop-time-inf": lambda ws: (
        run_argv(ws, IDEAL, "--stop-time", "inf"), ["--stop-time inf is not a finite number"]),
    "stop-time-nan": lambda ws: (
        run_argv(ws, IDEAL, "--stop-time", "nan"), ["--stop-time nan is not a finite number"]),
    "stop-time-beyond-1e9-s": lambda ws: (
        run_argv(ws, IDEAL, "--stop-time", "2e9"), ["stop time must lie within +-1e+09 s"]),
    "start-time-beyond-1e9-s": lambda ws: (
        run_argv(ws, ws.scenario("stop_time = 60.0", "stop_time = 60.0\nstart_time = -2e9")),
        ["start and stop time must lie within +-1e+09 s"]),
    "too-many-recorded-values": lambda ws: (
        run_argv(ws, ws.scenario("step = 1e-3", "step = 1e-6"), "--stop-time", "90"),
        ["90000001 rows of 10 recorded signals", "more than the 100,000,000"]),
    # --set and --fmus
    "set-unknown-instance": lambda ws: (
        run_argv(ws, IDEAL, "--set", "robot.m1=1"), ["--set 'robot.m1=1'", "no instance 'robot'"]),
    "set-without-value": lambda ws: (
        run_argv(ws, IDEAL, "--set", "body.m1"), ["--set 'body.m1'", "instance.parameter=value"]),
    "set-infinite-value": lambda ws: (
        run_argv(ws, IDEAL, "--set", "body.m1=inf"), ["--set 'body.m1=inf'", "must be finite"]),
    "fmu-folder-missing": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.root / "nofmus"),
        [ws.root / "nofmus" / "CrawlerBody.fmu", "musclesim build"]),
    # output paths, checked before any work (stdout stays empty: nothing was computed)
    "run-out-is-a-file": lambda ws: (
        ["run", IDEAL, "--out", ws.afile, "--fmus", ws.fmus_dir],
        [f"--out {ws.afile} is a file, not a folder"]),
    "run-out-under-a-file": lambda ws: (
        ["run", IDEAL, "--out", ws.afile / "sub", "--fmus", ws.fmus_dir],
        [f"--out {ws.afile / 'sub'} cannot be written", f"{ws.afile} is a file"]),
    "run-out-in-proc": lambda ws: (
        ["run", IDEAL, "--out", "/proc/musclesim-x", "--fmus", ws.fmus_dir],
        ["--out /proc/musclesim-x: cannot create /proc/musclesim-x",
         "(No such file or directory)"]),
    "diagnose-out-is-a-file": lambda ws: (
        ["diagnose", MEASURED, "--out", ws.afile, "--fmus", ws.fmus_dir],
        [f"--out {ws.afile} is a file"]),
    "calibrate-out-is-a-file": lambda ws: (
        ["calibrate", STUDY, "--out", ws.afile, "--fmus", ws.fmus_dir],
        [f"--out {ws.afile} is a file"]),
    "calibrate-time-series": lambda ws: (
        ["calibrate", MEASURED, "--out", ws.root / "cal", "--fmus", ws.fmus_dir],
        [MEASURED, "musclesim calibrate takes scalar metrics only"]),
    "diagnose-nothing-held-out": lambda ws: (
        ["diagnose", STUDY.parent / "study-fast-actuation-joint", "--out", ws.root / "diag",
         "--fmus", ws.fmus_dir], ["holds nothing out (held_out = [])", "musclesim calibrate"]),
    "calibrate-no-open-value": lambda ws: (
        ["calibrate", SCENARIOS / "data" / "crawler-real", "--out", ws.root / "cal", "--fmus",
         ws.fmus_dir], ["crawler-real names no open value", "[[calibrate]]"]),
    "predict-declaration-missing": lambda ws: (
        ["predict", ws.root / "none.toml", "--out", ws.root / "p.json", "--fmus", ws.fmus_dir],
        [f"predictions declaration {ws.root / 'none.toml'}", "No such file"]),
    "predict-a-scenario-as-declaration": lambda ws: (
        ["predict", IDEAL, "--out", ws.root / "p.json", "--fmus", ws.fmus_dir],
        [f"predictions declaration {IDEAL}", "unknown key 'connections'"]),
    "predict-out-under-a-file": lambda ws: (
        ["predict", SCENARIOS / "predictions" / "fast-actuation.toml", "--out",
         ws.afile / "p.json", "--fmus", ws.fmus_dir],
        [f"--out {ws.afile / 'p.json'} cannot be written"]),
    "loops-plot-under-a-file": lambda ws: (
        ["loops", "--stress", "1.25e8", "--band", "30:130", "--plot", ws.afile / "x.png"],
        [f"--plot {ws.afile / 'x.png'} cannot be written"]),
    "build-fmus-is-a-file": lambda ws: (
        ["build", "--fmus", ws.afile], [f"--fmus {ws.afile} is a file"]),
    "sweep-out-is-a-file": lambda ws: (
        ["sweep", IDEAL, "--grid", "inputs.phi=0:1:2", "--out", ws.afile, "--fmus", ws.fmus_dir],
        [f"--out {ws.afile} is a file"]),
    "export-ssp-under-a-file": lambda ws: (
        ["export", IDEAL, "--ssp", ws.afile / "x.ssp", "--fmus", ws.fmus_dir],
        [f"--ssp {ws.afile / 'x.ssp'} cannot be written"]),
    "export-ssp-not-named-ssp": lambda ws: (
        ["export", IDEAL, "--ssp", ws.root / "x.zip", "--fmus", ws.fmus_dir],
        [ws.root / "x.zip", "must have a name ending in .ssp"]),
    "identify-out-is-a-folder": lambda ws: (
        ["identify", ws.out, "--out", ws.afolder], [f"--out {ws.afolder} is a folder"]),
    "table-out-is-a-file": lambda ws: (
        ["table", "sma-position", "--out", ws.afile, "--fmus", ws.fmus_dir],
        [f"--out {ws.afile} is a file"]),
    "characterise-write-is-a-folder": lambda ws: (
        ["characterise", "--out", ws.root / "char", "--write", ws.afolder, "--fmus", ws.fmus_dir],
        [f"--write {ws.afolder} is a folder"]),
    "linear-write-is-a-folder": lambda ws: (
        ["linear", "sma-thermal", "--write", ws.afolder], [f"--write {ws.afolder} is a folder"]),
    "linear-write-for-crawler": lambda ws: (
        ["linear", "crawler", "--write", ws.root / "gains.toml"],
        ["--write is for sma-thermal, sma-load and pneumatic, not crawler"]),
    # sweeps
    "grid-axis-unknown-instance": lambda ws: (
        ["sweep", IDEAL, "--grid", "robot.phi=0:1:2", "--out", ws.root / "sw", "--fmus",
         ws.fmus_dir], ["grid axis 'robot.phi'", "no instance 'robot'"], ["--set"]),
    "grid-axis-one-point": lambda ws: (
        ["sweep", IDEAL, "--grid", "inputs.phi=0:1:1", "--out", ws.root / "sw", "--fmus",
         ws.fmus_dir], ["--grid", "'inputs.phi=0:1:1'", "n >= 2"]),
    "grid-axis-not-a-number": lambda ws: (
        ["sweep", IDEAL, "--grid", "inputs.phi=0:x:3", "--out", ws.root / "sw", "--fmus",
         ws.fmus_dir], ["grid axis 'inputs.phi'", "'x'"]),
    "sweep-plot-bad-kind": lambda ws: (
        ["sweep", sweep_file(ws, 'kind = "pie"\nx = "inputs.phi"\nmetrics = ["x1_final"]'),
         "--out", ws.root / "sw", "--fmus", ws.fmus_dir],
        [f"sweep file {ws.root / 'sweep.toml'}", 'kind = "line"']),
    "sweep-plot-unknown-metric": lambda ws: (
        ["sweep", sweep_file(ws, 'kind = "line"\nx = "inputs.phi"\nmetrics = ["speed"]'),
         "--out", ws.root / "sw", "--fmus", ws.fmus_dir],
        [f"sweep file {ws.root / 'sweep.toml'}", "plot metric(s) speed"]),
    # measured data and FORC data files
    "dataset-value-1e308": lambda ws: (
        ["dataset", "check", measured(ws, SMA_MANIFEST.format("sma-bench-stress"),
                                      SMA_DATA.format("1e308"))],
        [ws.root / "ds", "data.csv line 3, column 'wire.u'", "larger than 1e+12"]),
    # a temperature in degrees Celsius where the model's unit is K: its values say so, --model
    # or not (the units come from the scenario's FMUs whenever they can be read)
    "dataset-temperature-in-celsius": lambda ws: (
        ["dataset", "check", measured(ws, CELSIUS_MANIFEST, "time,wire.u,wire.T\n0,0.1,40\n"
                                          "0.1,0.2,50\n0.2,0.1,60\n0.3,0.1,50\n"),
         "--fmus", ws.fmus_dir],
        [ws.root / "ds", "data.csv: column 'wire.T' is in K, but its values (40 to 60) are "
         "degrees Celsius, not kelvin: add 273.15"]),
    "dataset-condition-in-celsius": lambda ws: (
        ["dataset", "check", measured(ws, CELSIUS_MANIFEST + '[conditions]\n"wire.T_amb" = 20\n',
                                      "time,wire.u,wire.T\n0,0.1,313\n0.1,0.2,323\n0.2,0.1,333\n"
                                      "0.3,0.1,323\n"), "--fmus", ws.fmus_dir],
        [ws.root / "ds", "[conditions] 'wire.T_amb' = 20 is in K, but that value is degrees "
         "Celsius, not kelvin: write 293.15"]),
    "dataset-scenario-not-found": lambda ws: (
        ["dataset", "check", measured(ws, SMA_MANIFEST.format("no-such-scenario"),
                                      SMA_DATA.format("0.1")), "--model", "--fmus", ws.fmus_dir],
        [ws.root / "ds", "scenario 'no-such-scenario' not found"]),
    "dataset-not-a-folder": lambda ws: (
        ["dataset", "check", ws.afile], [f"data set {ws.afile} is not a directory"]),
    "diagnose-model-without-scenario": lambda ws: (
        ["diagnose", MEASURED, "--out", ws.root / "diag", "--model", "x=", "--fmus", ws.fmus_dir],
        ["--model 'x='"]),
    "forc-file-strain-1e304": lambda ws: (
        ["loops", "--stress", "1e8", "--band", "30:35", "--model", forc_file(ws, "1e304")],
        [f"{ws.root / 'forc.csv'} line 3, column F: 1e+304 lies outside -1 to 1"]),
    "forc-file-nan": lambda ws: (
        ["loops", "--stress", "1e8", "--band", "30:35", "--model", forc_file(ws, "nan")],
        [f"{ws.root / 'forc.csv'} line 3, column F: nan is not a finite number"]),
    "loops-band-malformed": lambda ws: (
        ["loops", "--stress", "1e8", "--band", "30-130"], ["band '30-130'"]),
    "identify-nothing-to-read": lambda ws: (
        ["identify", ws.root / "nothing", "--out", ws.root / "forc.csv"],
        [ws.root / "nothing", "is neither a results.csv"]),
    # untrusted FMU archives, refused on the read path of every command (run, export, sweep,
    # dataset check --model) before any work; foreign FMUs: no BUILD.json protects them
    "fmu-description-over-16-MiB": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(in_description(b"?>", b"?>" + BIG_COMMENT))),
        [ws.root / "foreign" / "FrictionBlock.fmu", "modelDescription.xml is larger than 16 MiB"]),
    "fmu-description-declares-a-dtd": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(in_description(
            b"?>", b'?>\n<!DOCTYPE x [<!ENTITY lol "lol">]>'))),
        [ws.root / "foreign" / "FrictionBlock.fmu", "declares a DTD or entities"]),
    "fmu-description-malformed": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(lambda n, d: b"<fmiModelDescription"
                                         if n == "modelDescription.xml" else d)),
        [ws.root / "foreign" / "FrictionBlock.fmu", "cannot read modelDescription.xml"]),
    "fmu-without-description": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(lambda n, d: None if n == "modelDescription.xml" else d)),
        [ws.root / "foreign" / "FrictionBlock.fmu", "is not a readable FMU", "modelDescription"]),
    "fmu-not-a-zip": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(replace=lambda data: b"MZ garbage, not an archive")),
        [ws.root / "foreign" / "FrictionBlock.fmu", "is not a readable FMU"]),
    "fmu-truncated": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(replace=lambda data: data[:len(data) // 2])),
        [ws.root / "foreign" / "FrictionBlock.fmu", "is not a readable FMU"]),
    "fmu-entry-absolute-path-run": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(extra=[("/tmp/musclesim-evil.txt", b"x")])),
        [f"FMU {ws.root / 'foreign' / 'FrictionBlock.fmu'}", "entry '/tmp/musclesim-evil.txt'",
         "absolute path"]),
    "fmu-entry-dotdot-export": lambda ws: (
        ["export", IDEAL, "--ssp", ws.root / "x.ssp", "--fmus",
         ws.fmus(extra=[("resources/../../evil.txt", b"x")])],
        [f"FMU {ws.root / 'foreign' / 'FrictionBlock.fmu'}", "entry 'resources/../../evil.txt'",
         "('..')"]),
    "fmu-entry-symlink-sweep": lambda ws: (
        ["sweep", IDEAL, "--grid", "inputs.phi=0:1:2", "--out", ws.root / "sw", "--fmus",
         ws.fmus(extra=[(symlink_entry("resources/passwd"), b"/etc/passwd")])],
        [f"FMU {ws.root / 'foreign' / 'FrictionBlock.fmu'}", "entry 'resources/passwd'",
         "is a link"]),
    "fmu-entry-symlink-dataset-check": lambda ws: (
        ["dataset", "check", ws.crawler_dataset(), "--model", "--fmus",
         ws.fmus(extra=[(symlink_entry("resources/passwd"), b"/etc/passwd")])],
        [ws.root / "ds-crawler", f"FMU {ws.root / 'foreign' / 'FrictionBlock.fmu'}",
         "entry 'resources/passwd'", "is a link"]),
    "fmu-replaced-beside-its-build-json": lambda ws: (
        run_argv(ws, IDEAL, fmus=ws.fmus(in_description(b"?>", b"?>\n<!-- edited -->"),
                                         with_stamp=True, name="stamped")),
        [ws.root / "stamped" / "FrictionBlock.fmu", "is not the FMU `musclesim build` made"]),
}


@pytest.mark.parametrize("case", REFUSED)
def test_refused_before_any_work(case, ws, capsys):
    argv, culprits, *forbidden = REFUSED[case](ws)
    before, fmus_before = snapshot(ws.root), snapshot(ws.fmus_dir)
    code, out, err = run(capsys, *argv)
    assert code == 2, err
    assert_one_sentence(err, out, culprits, *forbidden)
    assert out == ""  # nothing was computed
    # nothing created, removed or rewritten: the previous run's outputs are intact
    assert snapshot(ws.root) == before
    assert snapshot(ws.fmus_dir) == fmus_before
    assert not Path("/proc/musclesim-x").exists() and not Path("/tmp/musclesim-evil.txt").exists()
    assert run_folders() == []


# ---- an output file in a folder that does not exist yet: the folder is made, as --out's is ------
# id -> ws -> (argv, the file written)
NEW_FOLDER = {
    "loops-plot": lambda ws: (
        ["loops", "--stress", "1.25e8", "--band", "50:100", "--plot", ws.root / "new" / "x.png"],
        ws.root / "new" / "x.png"),
    "linear-write": lambda ws: (
        ["linear", "sma-thermal", "--write", ws.root / "new" / "deeper" / "gains.toml"],
        ws.root / "new" / "deeper" / "gains.toml"),
    "export-ssp": lambda ws: (
        ["export", IDEAL, "--ssp", ws.root / "new" / "x.ssp", "--fmus", ws.fmus_dir],
        ws.root / "new" / "x.ssp"),
    "build-fmus": lambda ws: (["build", "--fmus", ws.root / "new" / "fmus"],
                              ws.root / "new" / "fmus" / "BUILD.json"),
}


@pytest.mark.parametrize("case", NEW_FOLDER)
def test_an_output_file_in_a_new_folder_is_written(case, ws, capsys):
    argv, written = NEW_FOLDER[case](ws)
    code, out, err = run(capsys, *argv)
    assert code == 0, err
    assert written.is_file() and "Traceback" not in err + out
    assert half_written(ws.root) == []


def test_writers_make_the_folder_of_their_file(tmp_path):
    # characterise --write and identify --out write through these too
    from matplotlib.figure import Figure

    from musclesim.cosim import replace_file, save_figure

    replace_file(tmp_path / "a" / "b.toml", "x = 1\n")
    save_figure(Figure(), tmp_path / "c" / "d.png")
    assert (tmp_path / "a" / "b.toml").read_text() == "x = 1\n"
    assert (tmp_path / "c" / "d.png").stat().st_size > 0


# ---- refused by argparse: exit 2, usage and one error line naming the option --------------------
ARGPARSE = {
    "benchmark-diagnosis-cases-0": (["benchmark-diagnosis", "--cases", "0", "--out", "bench"],
                                    "argument --cases: 0 must be at least 1 (0 only with --crawler)"),
    "benchmark-diagnosis-duration-short": (
        ["benchmark-diagnosis", "--bench", "independent", "--duration", "5", "--out", "bench"],
        "argument --duration: 5 s is shorter than one period of the bench's reference (10 s)"),
    "diagnose-workers-0": (["diagnose", str(MEASURED), "--out", "diag", "--workers", "0"],
                           "argument --workers: 0 must be at least 1"),
    "sweep-workers-0": (["sweep", str(IDEAL), "--out", "sw", "--workers", "0"],
                        "argument --workers: 0 must be at least 1"),
    "sweep-workers-not-a-number": (["sweep", str(IDEAL), "--out", "sw", "--workers", "two"],
                                   "argument --workers: 'two' is not a whole number"),
}


@pytest.mark.parametrize("case", ARGPARSE)
def test_refused_by_the_argument_parser(case, ws, capsys):
    argv, expected = ARGPARSE[case]
    before = snapshot(ws.root)
    code, out, err = run(capsys, *argv)
    assert code == 2
    lines = err.strip().splitlines()
    assert lines[0].startswith("usage: musclesim ")
    assert lines[-1] == f"musclesim {argv[0]}: error: {expected}"
    assert "Traceback" not in err + out and out == ""
    assert snapshot(ws.root) == before


# ---- refused once the run has started: the run's own files say so ------------------------------

def assert_stopped_run(out, error_part):
    """out/ holds one run's files, stopped: results.csv with this run's header and no row,
    ``completed: false``, ``status: stopped`` and the error; the previous run's files are gone
    (none of its plot beside this run's summary), nothing half-written."""
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False and summary["status"] == "stopped"
    assert error_part in summary["error"] and summary["run_id"] != "previous"
    assert csv_header(out / "results.csv")[:2] == ["time", "body.flange_a.s"]
    assert len((out / "results.csv").read_text().splitlines()) == 1  # the header: no row
    assert sorted(p.name for p in out.iterdir()) == ["results.csv", "summary.json"]
    assert half_written(out) == []


def test_fmu_without_binaries_is_one_sentence_and_a_stopped_run(ws, capsys):
    # fmpy raises a bare Exception when the FMU's library is missing: no traceback, exit 2
    foreign = ws.fmus(lambda name, data: None if name.startswith("binaries/") else data)
    code, out, err = run(capsys, *run_argv(ws, IDEAL, "--stop-time", "0.05", fmus=foreign))
    fmu = foreign / "FrictionBlock.fmu"
    assert code == 2, err
    assert_one_sentence(err, out, [f"FMU {fmu} cannot be loaded as instance 'friction1'",
                                   "Cannot find shared library"])
    assert_stopped_run(ws.out, f"FMU {fmu} cannot be loaded")
    assert run_folders() == []


def test_fmu_without_resources_is_one_sentence_when_isolated(ws):
    """pythonfmu's fmi2Instantiate dereferences the missing resources and crashes its process
    (SIGSEGV); isolated, that process is a child of the run's: the run ends in one sentence."""
    foreign = ws.fmus(lambda name, data: None if name.startswith("resources/") else data)
    proc = subprocess.Popen(
        [sys.executable, "-m", "musclesim.cli", *map(str, run_argv(
            ws, IDEAL, "--stop-time", "0.05", "--isolate", fmus=foreign))],
        cwd=ws.root, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 1, err
    assert run_folders(proc.pid) == []  # the run removed its own folder
    assert_one_sentence(err, out, ["instance 'friction1' (FrictionBlock) failed while loading",
                                   "at t = 0 s", "SIGSEGV"])
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["status"] == "stopped" and "SIGSEGV" in summary["error"]


def test_a_crash_mid_run_keeps_the_rows_recorded_before_it(ws, capsys):
    """An isolated FMU that dies in a step at 0.02 s: one sentence naming it and the time, the
    20 rows before it kept, nothing half-written, no child process left."""
    crash = ("import ctypes as _c\n\n\nclass FrictionBlock(_Slave):\n"
             "    def do_step(self, t, dt):\n"
             "        if t >= 0.0195:\n"
             "            _c.string_at(0)  # reads address 0: SIGSEGV\n"
             "        return super().do_step(t, dt)\n")

    def edit(name, data):
        if name != "resources/musclesim_fmu_FrictionBlock.py":
            return data
        return data.replace(b"class FrictionBlock(_Slave):\n    pass\n", crash.encode())
    foreign = ws.fmus(edit)
    scenario = ws.scenario("[instances.friction1]\n", "[instances.friction1]\nisolate = true\n")
    code, out, err = run(capsys, *run_argv(ws, scenario, "--stop-time", "0.05", fmus=foreign))
    assert code == 1, err
    assert "instance 'friction1' (FrictionBlock) failed in a step at t = 0.02 s" in err
    assert "SIGSEGV" in err and "Traceback" not in err
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["status"] == "stopped" and summary["end_time"] == pytest.approx(0.02)
    assert len((ws.out / "results.csv").read_text().splitlines()) == 1 + 21  # t = 0 ... 0.02
    assert half_written(ws.out) == [] and run_folders() == []
    import multiprocessing
    assert [p for p in multiprocessing.active_children()  # a Dask cluster's may run too
            if p.name.startswith("musclesim FMU")] == []


def test_fmu_unpacking_past_the_cap_is_refused_as_it_is_written(ws, capsys, monkeypatch):
    # a zip bomb: the entry declares its size honestly here, but the cap counts bytes written.
    # 2 MiB stands for the 512 MiB cap, which the FMU's 1 MB and the 2 MiB of zeros pass.
    from musclesim.cosim import host

    monkeypatch.setattr(host, "MAX_EXTRACTED", 2 * 2**20)
    foreign = ws.fmus(extra=[("resources/zeros.bin", bytes(2 * 2**20))])
    code, out, err = run(capsys, *run_argv(ws, IDEAL, "--stop-time", "0.05", fmus=foreign))
    assert code == 2, err
    assert_one_sentence(err, out, [f"FMU {foreign / 'FrictionBlock.fmu'}",
                                   "entry 'resources/zeros.bin' takes the archive past 2 MiB"])
    assert_stopped_run(ws.out, "resources/zeros.bin")
    assert run_folders() == []  # the partly unpacked FMU is gone with the run's folder


@pytest.mark.parametrize("entry, problem", [
    ("/etc/musclesim-evil", "has an absolute path"),
    ("resources/../../musclesim-evil", "leaves the archive's folder ('..')"),
    (symlink_entry("resources/evil-link"), "is a link"),
], ids=["absolute", "dotdot", "symlink"])
def test_extract_fmu_refuses_an_entry_and_leaves_nothing(entry, problem, tmp_path):
    # read_fmu refuses these first on every command's path; extraction checks them again
    from musclesim.cosim.host import extract_fmu
    from musclesim.errors import UserError

    fmu = tmp_path / "evil.fmu"
    with zipfile.ZipFile(fmu, "w") as zf:
        zf.writestr("modelDescription.xml", "<fmiModelDescription/>")
        zf.writestr(entry, "x")
    dest = tmp_path / "unpacked"
    with pytest.raises(UserError) as exc:
        extract_fmu(fmu, dest)
    name = entry if isinstance(entry, str) else entry.filename
    assert str(exc.value) == f"FMU {fmu}: entry {name!r} {problem}, refused"
    assert not dest.exists() and not Path("/etc/musclesim-evil").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["evil.fmu"]


# ---- failed runs: exit 1, the rows up to the failure kept ---------------------------------------
# id -> (--set overrides, the sentence naming the culprit, rows written before it)
FAILED = {
    "fmu-fails-at-initialization": (
        ["--set", "body.c=-1.3"], "instance 'body' (CrawlerBody) failed during initialization at "
        "t = 0 s: c must be non-negative (got -1.3)", 0),
    "signal-overflows-mid-run": (
        ["--set", "inputs.f_mean=1.7e308", "--set", "inputs.f_amp=1e308"],
        "signal inputs.f_a became inf at t = 0.016 s", 17),
}


@pytest.mark.parametrize("case", FAILED)
def test_failed_run_names_the_culprit_and_keeps_its_rows(case, ws, capsys):
    overrides, sentence, n_rows = FAILED[case]
    code, out, err = run(capsys, *run_argv(ws, IDEAL, "--stop-time", "0.1", *overrides))
    assert code == 1, err
    assert err.strip().splitlines() == [
        f"musclesim: run stopped: {sentence} (results up to then are kept)"]
    assert "Traceback" not in err + out
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["completed"] is False and summary["status"] == "stopped"
    assert summary["error"] == sentence
    rows = complete_rows(ws.out)
    assert summary["run_id"] != "previous" and len(rows) == n_rows
    plotted = ["results.png"] if n_rows > 1 else []  # the previous run's plot is gone either way
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv", *plotted, "summary.json"]
    assert ("results.png" in out) == bool(plotted)  # says it wrote only what it wrote
    assert half_written(ws.root) == [] and run_folders() == []


def test_failed_run_prints_nothing_else_from_the_console_script(ws):
    # plotting values near the float limit made matplotlib warn of an overflow on stderr; in this
    # process that depends on what ran before, so the console script's own stderr is checked
    overrides, sentence, _ = FAILED["signal-overflows-mid-run"]
    proc = subprocess.run(
        [sys.executable, "-m", "musclesim.cli",
         *map(str, run_argv(ws, IDEAL, "--stop-time", "1.2", *overrides))],
        cwd=ws.root, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    # one sentence: a stopped run's empty metric windows are explained by why it stopped
    assert proc.stderr.splitlines() == [
        f"musclesim: run stopped: {sentence} (results up to then are kept)"]
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv", "results.png",
                                                         "summary.json"]


# ---- allowed, with a warning --------------------------------------------------------------------

def test_metric_window_after_the_stop_time_is_a_warning(ws, capsys):
    path = ws.scenario("[metrics]", '[metrics]\nlate = { signal = "body.x_cm", op = "max", '
                                    "from = 5.0 }")
    code, out, err = run(capsys, *run_argv(ws, path, "--stop-time", "1.2"))
    warning = "metric late: no sample in its window (5 to inf s) of a run ending at 1.2 s"
    assert code == 0, err
    assert err.strip().splitlines() == [f"musclesim: warning from {warning}"]
    assert "Traceback" not in err + out and "late: no value" in out.splitlines()
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["completed"] is True and summary["warnings"] == [warning]
    assert summary["late"] is None  # JSON null, not NaN (which no strict JSON reader takes)
    assert summary["run_id"] != "previous" and csv_header(ws.out / "results.csv")[0] == "time"
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv", "results.png",
                                                         "summary.json"]
    assert half_written(ws.root) == [] and run_folders() == []


# ---- interruptions: a real process, a real signal -----------------------------------------------

def start_long_run(ws, out):
    """`musclesim run` of the SMA position control for 30 s of model time on the fmpy host (a
    Python call per FMU and step: some seconds of wall time; fused on the direct host it ends
    within a second) in a subprocess, returned once its results.csv.part holds rows."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "musclesim.cli", "run", str(POSITION), "--stop-time", "30",
         "--host", "fmpy", "--out", str(out), "--fmus", str(ws.fmus_dir)],
        cwd=ws.root, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    csv = out / "results.csv.part"
    while time.monotonic() < deadline and proc.poll() is None:
        lines = csv.read_bytes().splitlines() if csv.is_file() else []
        if len(lines) > 3:
            return proc
        time.sleep(0.1)
    proc.kill()
    pytest.fail(f"no rows before the run ended or timed out: {proc.communicate()}")


def complete_rows(out, allow_cut_last=False, name="results.csv"):
    """The rows of out/`name`, each checked to be complete (every column a number), below this
    run's header (not the previous run's); with `allow_cut_last` the last line may be a cut row
    without its line end."""
    text = (out / name).read_text()
    lines = text.split("\n")
    header, rows, last = lines[0], lines[1:-1], lines[-1]
    assert header.startswith("time,") and header != "time,previous.run"
    if allow_cut_last:
        assert header.count(",") >= last.count(",")  # a prefix of a row, or nothing
    else:
        assert last == ""  # the file ends with a line end
    for row in rows:
        fields = row.split(",")
        assert len(fields) == header.count(",") + 1
        [float(f) for f in fields]
    return rows


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signal_stops_the_run_and_keeps_its_rows(signum, ws):
    proc = start_long_run(ws, ws.out)
    proc.send_signal(signum)
    out, err = proc.communicate(timeout=60)
    name = signal.Signals(signum).name
    assert proc.returncode == 128 + signum
    assert err.strip().splitlines() == [f"musclesim: interrupted by {name}; what was written so "
                                        "far is kept"]
    assert "Traceback" not in out
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["completed"] is False and summary["status"] == "stopped"
    assert summary["error"].startswith(f"interrupted by {name} at t = ")
    rows = complete_rows(ws.out)
    assert summary["run_id"] != "previous"
    assert len(rows) > 1 and float(rows[-1].split(",")[0]) == summary["end_time"] < 30
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv", "results.png",
                                                         "summary.json"]
    assert half_written(ws.root) == [] and run_folders(proc.pid) == []


def test_sigkill_leaves_one_run_and_the_next_run_replaces_it(ws, capsys):
    proc = start_long_run(ws, ws.out)
    orphans = run_folders(proc.pid)
    assert len(orphans) == 1  # the run's unpacked FMUs, which no finally removes after SIGKILL
    proc.kill()
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    # what a killed run leaves: its own summary (running) and its rows so far in a file whose
    # name says the run did not end, nothing of the previous run
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["completed"] is False and summary["status"] == "running"
    run_id = summary["run_id"]
    rows = complete_rows(ws.out, allow_cut_last=True, name="results.csv.part")
    assert run_id != "previous" and rows
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv.part", "summary.json"]
    # the next run into the same folder replaces both files consistently and removes the orphaned
    # folder (unless a run of another process on this machine already has)
    code, out, err = run(capsys, "run", POSITION, "--stop-time", "0.02", "--out", ws.out,
                         "--fmus", ws.fmus_dir)
    assert code == 0, err
    summary = json.loads((ws.out / "summary.json").read_text())
    assert summary["completed"] is True and summary["status"] == "completed"
    rows = complete_rows(ws.out)
    assert summary["run_id"] != run_id and len(rows) == 51  # 0.02 s / 0.4 ms + 1
    assert sorted(p.name for p in ws.out.iterdir()) == ["results.csv", "results.png",
                                                         "summary.json"]
    assert not orphans[0].exists() and run_folders() == []
    assert half_written(ws.root) == []


def wait_for(proc, ready, what, timeout=90):
    """Poll until `ready()` holds while `proc` runs; fail naming `what` otherwise."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        if ready():
            return
        time.sleep(0.1)
    proc.kill()
    pytest.fail(f"{what} did not happen before the process ended or timed out: "
                f"{proc.communicate()}")


def test_sigterm_stops_a_sweep_keeping_its_finished_cases_and_it_resumes(ws, capsys):
    # one worker: the cases run in this process, about 0.5 s each (most of it writing 100 000
    # rows), so that the signal lands before the last one ends
    argv = ["sweep", str(IDEAL), "--grid", "inputs.phi=0:3:6", "--stop-time", "100", "--out",
            str(ws.root / "sweep"), "--fmus", str(ws.fmus_dir), "--workers", "1"]
    proc = subprocess.Popen([sys.executable, "-m", "musclesim.cli", *argv], cwd=ws.root,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    csv_path = ws.root / "sweep" / "sweep.csv"
    wait_for(proc, lambda: csv_path.is_file() and len(csv_path.read_text().splitlines()) > 2,
             "two finished cases")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143
    assert err.strip().splitlines()[-1] == ("musclesim: interrupted by SIGTERM; what was "
                                            "written so far is kept")
    assert "Traceback" not in err
    recorded = [r for r in csv_path.read_text().splitlines()[1:] if ",True," in r]
    # a case may finish between the signal and its line in sweep.csv: its folder counts
    done = [c for c in (ws.root / "sweep" / "cases").iterdir()
            if json.loads((c / "summary.json").read_text()).get("completed") is True]
    assert 2 <= len(recorded) <= len(done) < 6
    code, out, err = run(capsys, *argv)  # the same command resumes: only the rest runs
    summary = json.loads(out)
    assert code == 0 and summary["skipped"] == len(done) and summary["completed"] == 6
    assert summary["ran"] == 6 - len(done)


def test_ctrl_c_stops_a_diagnosis_in_one_line_workers_included(ws, fmu_dir):
    """Ctrl-C reaches the whole process group, the local Dask cluster's workers too: only the
    command acts on it (one line, exit 130), the workers print nothing, and no report is left."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "musclesim.cli", "diagnose", str(MEASURED), "--out",
         str(ws.root / "diag"), "--fmus", str(fmu_dir), "--workers", "2"],
        cwd=ws.root, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        start_new_session=True)
    err_lines = []

    def fitting():
        line = proc.stderr.readline()
        err_lines.append(line)
        return line.startswith("musclesim: fitting")

    wait_for(proc, fitting, "the fitting stage")
    os.killpg(proc.pid, signal.SIGINT)  # what a terminal's Ctrl-C does
    _, rest = proc.communicate(timeout=60)
    err = "".join(err_lines) + rest
    assert proc.returncode == 130, err
    assert err.strip().splitlines()[-1] == ("musclesim: interrupted by SIGINT; what was written "
                                            "so far is kept")
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert not (ws.root / "diag" / "report.json").exists()
