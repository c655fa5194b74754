"""The quick examples give the figures their READMEs quote: deposit2d and deposit3d run and
their figures equal the committed examples/NAME/expected/numbers.json within a relative
1e-6 (scripts/refresh-examples.sh re-measures them all when the physics changes).

Run by CTest: python3 test_examples.py GEODEM_BINARY REPO_ROOT
"""
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

GEODEM = None
ROOT = None


class ExamplesTest(unittest.TestCase):
    def test_quick_examples_match_their_expected_figures(self):
        with tempfile.TemporaryDirectory() as tmp:
            for ex in ("deposit2d", "deposit3d"):
                out = Path(tmp) / ex
                r = subprocess.run([GEODEM, "run", str(ROOT / "examples" / ex / "scenario.toml"),
                                    "--out", str(out), "--quiet", "--threads", "1"],
                                   capture_output=True, text=True, timeout=300)
                self.assertEqual(r.returncode, 0, r.stderr)
                r = subprocess.run([sys.executable, str(ROOT / "scripts" / "example_numbers.py"),
                                    str(out), "--compare",
                                    str(ROOT / "examples" / ex / "expected" / "numbers.json")],
                                   capture_output=True, text=True)
                self.assertEqual(r.returncode, 0, r.stdout + r.stderr)


if __name__ == "__main__":
    GEODEM = sys.argv.pop(1)
    ROOT = Path(sys.argv.pop(1))
    unittest.main(verbosity=2)
