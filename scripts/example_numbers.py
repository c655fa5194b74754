#!/usr/bin/env python3
"""The figures an example's README quotes, from a run's summary.json, as JSON; and their
comparison with the committed ones (examples/NAME/expected/numbers.json).

    scripts/example_numbers.py RUN_DIR                 print the figures
    scripts/example_numbers.py RUN_DIR --compare FILE  exit 1 when one differs by more
                                                       than --rtol (default 1e-6) of it
"""
import argparse
import json
import sys
from pathlib import Path

TEST_KEYS = ("confining_stress", "porosity_initial", "peak_q", "phi_peak_deg",
             "phi_residual_deg", "axial_strain_at_peak", "young_modulus", "steps")


def numbers(run_dir):
    s = json.loads((Path(run_dir) / "summary.json").read_text())
    r = s["results"]
    if s["kind"] == "scene":
        out = {k: r[k] for k in ("time", "steps", "dt", "total_weight", "coordination", "porosity")
               if k in r}
        out["particles"] = r["particles"]
        for name, w in sorted(r.get("walls", {}).items()):
            out[f"wall {name} force"] = w["force"]
        for st in r.get("stages", []):
            out[f"stage {st['name']}"] = {k: st[k] for k in ("stop_reason", "steps", "end_time")}
            for servo in st.get("servos", []):
                out[f"stage {st['name']}"][f"servo {servo['wall']} stress"] = servo["stress"]
            for name, w in st["walls"].items():
                out[f"stage {st['name']}"][f"wall {name} point"] = w["point"]
        return out
    if s["kind"] == "triaxial":
        out = {"tests": [{k: t[k] for k in TEST_KEYS if k in t} for t in r.get("tests", [r])]}
        for k in ("phi_deg", "cohesion"):
            if k in r.get("mohr_coulomb", {}):
                out[f"mohr_coulomb {k}"] = r["mohr_coulomb"][k]
        return out
    raise SystemExit(f"{run_dir}: kind {s['kind']} has its own refresh script")


def differences(got, want, rtol, path=""):
    if isinstance(want, dict):
        keys = set(want) | set(got if isinstance(got, dict) else {})
        return [d for k in sorted(keys) for d in
                differences((got or {}).get(k), want.get(k), rtol, f"{path}.{k}")]
    if isinstance(want, list):
        if not isinstance(got, list) or len(got) != len(want):
            return [f"{path}: {got} against {want}"]
        return [d for i, (g, w) in enumerate(zip(got, want))
                for d in differences(g, w, rtol, f"{path}[{i}]")]
    if isinstance(want, (int, float)) and isinstance(got, (int, float)):
        return [] if abs(got - want) <= rtol * max(abs(want), 1e-300) else \
            [f"{path}: {got:.8g} against {want:.8g}"]
    return [] if got == want else [f"{path}: {got} against {want}"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("--compare")
    ap.add_argument("--rtol", type=float, default=1e-6)
    a = ap.parse_args()
    got = numbers(a.run_dir)
    if not a.compare:
        print(json.dumps(got, indent=1))
        return 0
    diff = differences(got, json.loads(Path(a.compare).read_text()), a.rtol)
    for d in diff:
        print(f"{a.run_dir}: {d}")
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main())
