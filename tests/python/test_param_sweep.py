# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random option sets on valid models (tests/tools/param_sweep.py): every run of the CLI ends with
a sane mesh (every triangle and quad edge used at most twice, finite coordinates) or a one-line
refusal, never a crash, a hang or a garbled message. A seeded handful in every test run; the
campaigns are in docs/robustness.md ("Parameter sweeps")."""
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "tests", "data")
CLI = os.path.join(ROOT, "build", "bin", "paramesh")
TOOL = os.path.join(ROOT, "tests", "tools", "param_sweep.py")


@pytest.mark.skipif(not os.path.exists(CLI), reason="needs build/bin/paramesh")
def test_random_options_mesh_or_refuse(tmp_path):
    models = [os.path.join(DATA, m) for m in ("screw.step", "wing.brep", "occBSplCone.brep")]
    p = subprocess.run([sys.executable, TOOL, CLI, *models, "--cases", "12", "--seed", "5", "--timeout", "120",
                        "--out", str(tmp_path)], capture_output=True, text=True, timeout=1800)
    out = p.stdout[p.stdout.index("{"):]
    r = json.loads(out)
    assert p.returncode == 0 and not r["failures"], r["failures"]
    assert r["cases"] == 12
    assert r["counts"].get("exit 0", 0) >= 9, r["counts"]       # measured 11 of 12
    # a run the final audit did not pass is degraded (exit 3) with its problems named; measured: 1,
    # occBSplCone's apex with a layer on its seam (a triangle there spans half the cone)
    assert len(r["degraded_by_audit"]) <= 1, r["degraded_by_audit"]
    for x in r["refused"]:                                      # a refusal says why, in one line
        assert x["reason"] and "\n" not in x["reason"], x
