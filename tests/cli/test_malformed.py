"""Malformed scenarios: every file of tests/malformed/ must be refused cleanly.

Each case is a small valid scenario with one defect (tests/malformed/cases.txt lists them with
the fragments their message must contain). `geodem check FILE` must exit with 2 within 30 s,
print on stderr a message that starts with "error:", names the file and contains every
fragment, and show no sign of a crash.

Run by CTest: python3 test_malformed.py GEODEM_BINARY REPO_ROOT
"""
import os
import subprocess
import sys
import unittest
from pathlib import Path

GEODEM = None
ROOT = None
TIMEOUT_S = 30
CRASH_SIGNS = ("terminate called", "Sanitizer", "Segmentation", "Assertion", "core dumped",
               "std::", "what():")


def malformed_dir():
    return ROOT / "tests" / "malformed"


def read_cases():
    """{file name: [fragment, ...]} from cases.txt, in file order."""
    cases = {}
    for n, line in enumerate((malformed_dir() / "cases.txt").read_text().splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = [f.strip() for f in line.split(" | ")]
        name, fragments = fields[0], [f for f in fields[1:] if f]
        if name in cases:
            raise ValueError(f"cases.txt:{n}: {name} listed twice")
        if not fragments:
            raise ValueError(f"cases.txt:{n}: {name} has no fragments")
        cases[name] = fragments
    return cases


def check(path):
    """(exit code, stderr) of `geodem check PATH`; exit code None when it hung."""
    try:
        # The same memory on every machine: a case too large for 16 GB is refused as such.
        r = subprocess.run([GEODEM, "check", str(path)], capture_output=True,
                           timeout=TIMEOUT_S, cwd=path.parent,
                           env=dict(os.environ, GEODEM_MEMORY_LIMIT="16e9"))
    except subprocess.TimeoutExpired as e:
        return None, (e.stderr or b"").decode("utf-8", "replace")
    return r.returncode, r.stderr.decode("utf-8", "replace")


class MalformedTest(unittest.TestCase):
    def test_corpus_is_complete(self):
        cases = read_cases()
        files = sorted(p.name for p in malformed_dir().glob("*.toml"))
        self.assertGreaterEqual(len(files), 40)
        self.assertEqual(sorted(cases), files, "cases.txt and the .toml files must match")

    def test_base_scenarios_are_valid(self):
        # The cases are these scenarios with one defect each: the bases must pass, so that a
        # case fails for its own defect only.
        bases = sorted((malformed_dir() / "valid").glob("*.toml"))
        self.assertGreaterEqual(len(bases), 4)
        for path in bases:
            with self.subTest(file=path.name):
                code, err = check(path)
                self.assertEqual(code, 0, f"{path.name}: {err}")

    def test_each_case_is_refused_with_a_clear_message(self):
        for name, fragments in read_cases().items():
            with self.subTest(file=name):
                path = malformed_dir() / name
                code, err = check(path)
                self.assertIsNotNone(code, f"{name}: hung (no exit within {TIMEOUT_S} s)")
                for sign in CRASH_SIGNS:
                    self.assertNotIn(sign, err, f"{name}: crashed: {err}")
                self.assertGreaterEqual(code, 0, f"{name}: killed by signal {-code}: {err}")
                self.assertEqual(code, 2, f"{name}: expected exit 2, got {code}: {err!r}")
                self.assertTrue(err.startswith("error:"), f"{name}: {err!r}")
                self.assertIn(name, err, f"{name}: the message does not name the file")
                for fragment in fragments:
                    self.assertIn(fragment, err, f"{name}: '{fragment}' missing from {err!r}")


if __name__ == "__main__":
    GEODEM = os.path.abspath(sys.argv.pop(1))
    ROOT = Path(sys.argv.pop(1)).resolve()
    unittest.main(verbosity=2)
