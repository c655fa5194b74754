#!/usr/bin/env python3
"""Helpers for parameter studies: run many geodem scenarios, two at a time by default.

A study writes one scenario per case (TOML text from a template), runs
`geodem run` on each into its own folder and reads back summary.json. Cases that
already have a summary.json are not run again, so a study can be resumed.
"""
import json
import os
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path


def find_geodem():
    here = Path(__file__).resolve().parent.parent
    for cand in (os.environ.get("GEODEM"), here / "build" / "geodem"):
        if cand and Path(cand).is_file():
            return str(cand)
    raise SystemExit("geodem not found: build it (scripts/build.sh) or set GEODEM=/path/to/geodem")


def run_case(geodem, folder, scenario_text):
    """Runs one scenario in `folder` (scenario.toml, out/); returns its summary."""
    folder = Path(folder)
    summary = folder / "out" / "summary.json"
    if summary.is_file():
        return json.loads(summary.read_text())
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "scenario.toml").write_text(scenario_text)
    proc = subprocess.run([geodem, "run", str(folder / "scenario.toml"), "--out",
                           str(folder / "out"), "--overwrite", "--quiet"], capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{folder}: geodem failed ({proc.returncode}):\n{proc.stderr}")
    return json.loads(summary.read_text())


def run_cases(cases, jobs=2):
    """cases: list of (folder, scenario_text). Returns the summaries in order."""
    geodem = find_geodem()
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        return list(ex.map(lambda c: run_case(geodem, c[0], c[1]), cases))
