#!/usr/bin/env python3
"""Fill the tables of RESULTS.md (between the <!-- tables --> markers) from the
measure.json files: sidebyside.py, table.py (DEM + packbed N = 2000 and 4000), hist.py."""
import os
import re
import subprocess
import sys

H = os.path.dirname(os.path.abspath(__file__))
run = lambda *a: subprocess.run([sys.executable, os.path.join(H, a[0]), *a[1:]],
                                capture_output=True, text=True, check=True, cwd=H).stdout
block = ("<!-- tables -->\n### Side by side (the calibration view)\n\n" + run("sidebyside.py") + "\n"
         + run("table.py", "packbed", "packbed_n4000")
         + "\n### Contact-number histograms (fraction of slab particles, tol 1e-3)\n\n"
         + run("hist.py", "packbed") + "<!-- /tables -->\n")
p = os.path.join(H, "RESULTS.md")
s = open(p).read()
s = re.sub(r"<!-- tables -->.*?<!-- /tables -->\n", lambda m: block, s, flags=re.S)
open(p, "w").write(s)
