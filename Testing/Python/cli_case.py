# SPDX-License-Identifier: GPL-3.0-or-later
"""Base of the command-line tests: a temporary folder per test, and `python3 -m ctsplines` run
as a subprocess inside it with its exit code checked."""
import os
import subprocess
import sys
import tempfile
import unittest


class CommandLineCase(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.dir = self._tmp.name

    def tearDown(self):
        self._tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def assertNoVTKNoise(self, text):
        """No VTK error report, pipeline trace or object address in a message meant for users."""
        for noise in ("ERROR: In", "vtkExecutive", "returned failure", "Debug: Off"):
            self.assertNotIn(noise, text)
        # An object's address as VTK prints it, "(0x55d4...)": not a bare "0x", which a random
        # temporary folder's name may hold (/tmp/tmpmqwwy0xw made a test fail).
        self.assertNotRegex(text, r"\(0x[0-9a-f]+\)")

    def cli(self, *args, code=0):
        # Run inside the temporary folder: default output names land there too.
        p = subprocess.run([sys.executable, "-m", "ctsplines", *args], capture_output=True,
                           text=True, timeout=300, stdin=subprocess.DEVNULL, cwd=self.dir)
        self.assertEqual(p.returncode, code, f"args {args}\nstdout:\n{p.stdout}\n"
                         f"stderr:\n{p.stderr}")
        return p
