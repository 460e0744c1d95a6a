"""Dask worker preload of test_cluster_without_shared_files.py: the worker process records every
file it opens, creates, changes or removes and every library it loads (Python's audit events),
one JSON line each ({"kind": "read" | "write" | "dlopen", "event", "path"}), in the file named by
the environment variable MUSCLESIM_TEST_AUDIT (inside the worker's own folder).

Relative paths are made absolute against the working directory at the time of the event.
"""
import json
import os
import sys
import threading

_WRITES = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND
_COPIES = {"shutil.copyfile", "shutil.copytree"}  # (source: read, destination: written)
_MOVES = {"os.rename", "os.replace", "shutil.move"}  # both paths change
_LINKS = {"os.symlink", "os.link"}  # (target, new link: written)
_CHANGES = {"os.mkdir", "os.remove", "os.rmdir", "os.truncate", "os.chmod", "os.chown",
            "os.utime", "shutil.rmtree", "tempfile.mkdtemp", "tempfile.mkstemp"}
_LOG = open(os.environ["MUSCLESIM_TEST_AUDIT"], "a", buffering=1, encoding="utf-8")
_LOCK = threading.Lock()


def _record(kind, event, paths):
    for path in paths:
        if path is None or isinstance(path, int):  # a file descriptor: opened before
            continue
        path = os.fsdecode(path)
        if kind != "dlopen" or os.sep in path:  # a library's bare name is no path
            path = os.path.abspath(path)
        line = json.dumps({"kind": kind, "event": event, "path": path})
        with _LOCK:
            _LOG.write(line + "\n")


def _hook(event, args):
    try:
        if event == "open":
            path, _, flags = args
            _record("write" if flags & _WRITES else "read", event, [path])
        elif event in ("os.listdir", "os.scandir"):
            _record("read", event, args[:1])
        elif event in _COPIES or event in _LINKS:
            _record("read", event, args[:1])
            _record("write", event, args[1:2])
        elif event in _MOVES:
            _record("write", event, args[:2])
        elif event in _CHANGES:
            _record("write", event, args[:1])
        elif event == "ctypes.dlopen":
            _record("dlopen", event, args[:1])
    except Exception as exc:  # never break the worker's own call; say what was not recorded
        with _LOCK:
            _LOG.write(json.dumps({"kind": "error", "event": event, "path": repr(exc)}) + "\n")


sys.addaudithook(_hook)
