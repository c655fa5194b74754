#!/usr/bin/env python3
"""The layer rule of geodem's sources (docs/architecture.md, "Layers").

    base  <-  engine  <-  app  <-  cli (apps/: the command line; bindings/: Python)

A file may include its own layer and the layers below it, never one above. The base and the
engine read no file: they include no format or file library (toml++, nlohmann_json, zlib,
<fstream>, <filesystem>). Every folder of src/ belongs to exactly one layer (a new folder must
be added to LAYERS). No source file is longer than 500 lines. Prints every violation and
exits 1 when there is one; run by CTest as layers.check.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"
LAYERS = {
    "base": ["base"],
    "engine": ["materials", "particles", "clumps", "walls", "structures", "contacts",
               "broadphase", "integrate", "controllers", "measure", "world", "domain"],
    "app": ["io", "scene", "lab", "study", "kinds", "distributed"],
}
RANK = {"base": 0, "engine": 1, "app": 2, "cli": 3}
NO_FILES = re.compile(r"^(toml\+\+/|nlohmann/|zlib\.h$|fstream$|filesystem$)")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
MAX_LINES = 500


def layer_of(path: Path):
    rel = path.relative_to(ROOT)
    if rel.parts[0] in ("apps", "bindings"):
        return "cli"
    folder = path.relative_to(SRC).parts[0]
    for layer, folders in LAYERS.items():
        if folder in folders:
            return layer
    return None


def main() -> int:
    problems = []
    sources = sorted(p for p in [*SRC.rglob("*"), *(ROOT / "apps").rglob("*"),
                                 *(ROOT / "bindings").rglob("*")]
                     if p.suffix in (".hpp", ".cpp", ".h"))
    for path in sources:
        rel = path.relative_to(ROOT)
        layer = layer_of(path)
        if layer is None:
            problems.append(f"{rel}: its folder belongs to no layer (scripts/check_layers.py)")
            continue
        lines = path.read_text().splitlines()
        if len(lines) > MAX_LINES:
            problems.append(f"{rel}: {len(lines)} lines (at most {MAX_LINES})")
        for number, line in enumerate(lines, 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            bracket, name = m.groups()
            target = SRC / name
            if bracket == '"' and target.is_file():
                other = layer_of(target)
                if other is not None and RANK[other] > RANK[layer]:
                    problems.append(f"{rel}:{number}: the {layer} layer includes "
                                    f"{name} of the {other} layer")
            elif bracket == "<" and layer in ("base", "engine") and NO_FILES.match(name):
                problems.append(f"{rel}:{number}: the {layer} layer reads no file, but "
                                f"includes <{name}>")
    for p in problems:
        print(p)
    print(f"layers: {len(sources)} files, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
