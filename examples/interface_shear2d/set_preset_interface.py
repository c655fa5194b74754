#!/usr/bin/env python3
"""Writes the interface calibrations of refresh_expected.sh --calibrate into the presets:
the [interface] table of presets/{sand,silt}_2d.toml takes the calibrated local friction
and the macroscopic friction and adhesion its verification seeds measured (with their
scatter in the comment). The rest of each preset is left as it is.

Usage: set_preset_interface.py OUT   (OUT holds calibrate_sand/ and calibrate_silt/)
"""
import json
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def interface_table(material, summary):
    itf = tomllib.loads(material.read_text())["interface"]
    verification = json.loads(summary.read_text())["results"]["verification"]
    scatter, seeds = verification["scatter"], verification["seeds"]
    return (
        "[interface]\n"
        f"local_friction_deg = {itf['local_friction_deg']:.4f}\n"
        f"macro_friction_deg = {itf['macro_friction_deg']:.4f}   # verified, {seeds} fresh seeds: "
        f"+- {scatter['interface_friction_deg']:.2f} deg\n"
        f"macro_adhesion = {itf['macro_adhesion']:.1f}   # Pa (+- {scatter['interface_adhesion']:.0f})\n")


def main():
    out = Path(sys.argv[1])
    for soil in ("sand", "silt"):
        cal = out / f"calibrate_{soil}"
        preset = ROOT / "presets" / f"{soil}_2d.toml"
        text = preset.read_text()
        table = interface_table(cal / "material.toml", cal / "summary.json")
        new, n = re.subn(r"\[interface\]\n(?:[a-z_]+ = [^\n]*\n)+", table, text, count=1)
        if n != 1:
            sys.exit(f"{preset}: no [interface] table to replace")
        preset.write_text(new)
        print(f"{preset.relative_to(ROOT)}:\n{table}")


if __name__ == "__main__":
    main()
