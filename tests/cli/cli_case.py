"""The command-line tests' shared parts (test_cli.py, test_cli_scenarios.py,
test_cli_checkpoints.py): run() on the binary their command line names (GEODEM, set by
each module's main block), the small scene in 2D or 3D, and a test case in a temporary
folder that writes scenarios and checks their input errors (CliCase).
"""
import subprocess
import tempfile
import unittest
from pathlib import Path

from small_scenarios import SMALL_SCENE

GEODEM = None


def scene(dim):
    if dim == 3:
        return SMALL_SCENE.format(dim=3, gravity="[0, 0, -9.81]", normal="[0, 0, 1]",
                                  lo="[0, 0, 0]", hi="[0.1, 0.1, 0.1]")
    return SMALL_SCENE.format(dim=2, gravity="[0, -9.81]", normal="[0, 1]",
                              lo="[0, 0]", hi="[0.1, 0.1]")


def run(*args):
    return subprocess.run([GEODEM, *args], capture_output=True, text=True, timeout=300)


class CliCase(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, text, name="s.toml"):
        p = self.dir / name
        p.write_text(text)
        return str(p)

    def assertBadInput(self, text, *fragments, args=()):
        path = self.write(text)
        r = run("check", path, *args)
        self.assertEqual(r.returncode, 2, f"expected exit 2, got {r.returncode}: {r.stderr}")
        for frag in fragments:
            self.assertIn(frag, r.stderr)
        return r
