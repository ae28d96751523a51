#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random parameter combinations on valid CAD models: the CLI must mesh or refuse, never crash.

usage: param_sweep.py PARAMESH MODEL [MODEL...] [--cases N] [--seed S] [--timeout SEC] [--out DIR]

Each case draws a model and options: --size (diagonal / 15 to / 300), sometimes
--curvature-angle (3 to 40), --max-deviation (2e-4 to 5e-3 of the size), --min-size, --grading
(1.05 to 2.5), --quads, --order 2, --proximity, --threads 1 or 2, and a boundary layer on 1-4
random edges (first height size / 200 to size / 5, 1 to 12 rows). The run gets a time limit (a
case whose element estimate is huge is expected to stop at --max-elements, set to 3e6). Every
outcome must be one of: exit 0 (or 3, some faces failed, each named in the report) with a mesh
that passes fuzz_inputs.py's check (finite coordinates, no triangle with a repeated node, every
triangle and quad edge used at most twice, no unused node; a run whose final audit did not pass must
exit 3, and is listed in "degraded_by_audit"), or an exit code 1-5 with a one-line reason. A signal, a sanitizer report, a time-out or a
reason of several lines is a failure; its command line is kept in DIR/failures.txt.
Prints JSON: counts per outcome, the refusals (exit 1-5: reason and command) and the failures.
Exit status 1 when any failed. Run with Debian's /usr/bin/python3 (meshio)."""
import argparse
import json
import os
import random
import re
import subprocess
import sys
import tempfile

from fuzz_inputs import check_mesh  # tests/tools: the same sanity check as the fuzzer's


def diag_and_edges(model):
    code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part\n"
            "p=sys.argv[1]; s=Part.Shape()\n"
            "s.read(p) if p.lower().endswith(('.brep','.brp')) else None\n"
            "s = s if p.lower().endswith(('.brep','.brp')) else Part.read(p)\n"
            "print(s.BoundBox.DiagonalLength, len(s.Edges))")
    out = subprocess.check_output([sys.executable, "-c", code, model]).decode().split()
    return float(out[-2]), int(out[-1])


def audit_failure(report):
    """The final audit's problems when it did not pass (None when it passed)."""
    try:
        with open(report) as f:
            audit = json.load(f).get("audit")
    except (OSError, ValueError):
        return "no readable report"
    if audit is None:
        return "the report has no audit"
    # a failed face (exit 3, named in the report) is the audit's "faces without elements": not an escape
    problems = [x for x in audit["problems"] if not re.match(r"\d+ faces without elements", x)]
    return "audit: " + "; ".join(problems) if problems else None


def draw(rng, model, diag, nedges):
    size = diag / rng.uniform(15, 300)
    args = ["--size", repr(size), "--max-elements", "3000000", "--threads", str(rng.choice([1, 2]))]
    if rng.random() < 0.4:
        args += ["--curvature-angle", "%.3g" % rng.uniform(3, 40)]
    if rng.random() < 0.3:
        args += ["--max-deviation", "%.3g" % rng.uniform(2e-4, 5e-3)]
    if rng.random() < 0.2:
        args += ["--min-size", repr(size / rng.uniform(2, 200))]
    if rng.random() < 0.3:
        args += ["--grading", "%.3g" % rng.uniform(1.05, 2.5)]
    if rng.random() < 0.2:
        args += ["--quads"]
    if rng.random() < 0.15:
        args += ["--order", "2"]
    if rng.random() < 0.15:
        args += ["--proximity", str(rng.choice([2, 3, 4]))]
    if rng.random() < 0.35:
        edges = sorted(rng.sample(range(1, nedges + 1), min(nedges, rng.randint(1, 4))))
        args += ["--bl-edges", ",".join(map(str, edges)), "--bl-first-height", repr(size / rng.uniform(5, 200)),
                 "--bl-layers", str(rng.randint(1, 12))]
    return args


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("paramesh")
    ap.add_argument("models", nargs="+")
    ap.add_argument("--cases", type=int, default=50)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--out", default=tempfile.mkdtemp(prefix="param_sweep_"))
    a = ap.parse_args()
    rng = random.Random(a.seed)
    info = {m: diag_and_edges(m) for m in a.models}
    os.makedirs(a.out, exist_ok=True)
    counts, failures, refused, degraded = {}, [], [], []
    for i in range(a.cases):
        model = rng.choice(a.models)
        args = draw(rng, model, *info[model])
        out = os.path.join(a.out, "case.msh")
        if os.path.exists(out):
            os.remove(out)
        rep = os.path.join(a.out, "case.json")
        if os.path.exists(rep):
            os.remove(rep)
        cmd = [a.paramesh, "mesh", model, "-o", out, "--report", rep, "--quiet"] + args
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout,
                               env=dict(os.environ, ASAN_OPTIONS="detect_leaks=0"))
            rc, err = p.returncode, p.stderr
        except subprocess.TimeoutExpired:
            rc, err = "timeout", ""
        why = None
        if rc == "timeout":
            why = "time-out"
        elif rc < 0 or rc > 5:
            why = "signal or unknown exit %s" % rc
        elif re.search(r"AddressSanitizer|UndefinedBehaviorSanitizer|runtime error:", err):
            why = "sanitizer report"
        elif rc in (0, 3):
            why = check_mesh(out) if os.path.exists(out) else "no mesh written"
            audit = None if why else audit_failure(rep)
            if audit and rc != 3:
                why = "the audit failed but the exit code is %s: %s" % (rc, audit)
            elif audit:  # reported: degraded, exit 3, the faces named
                degraded.append({"case": i, "audit": audit, "cmd": " ".join(cmd)})
        elif len(err.strip().splitlines()) != 1:
            why = "reason of %d lines" % len(err.strip().splitlines())
        key = "failed" if why else ("exit %s" % rc)
        counts[key] = counts.get(key, 0) + 1
        if not why and rc not in (0,):
            refused.append({"case": i, "exit": rc, "reason": err.strip()[-300:], "cmd": " ".join(cmd)})
        if why:
            failures.append({"case": i, "why": why, "cmd": " ".join(cmd), "stderr": err[-2000:]})
            with open(os.path.join(a.out, "failures.txt"), "a") as f:
                f.write(" ".join(cmd) + "\n  " + why + "\n")
    print(json.dumps({"cases": a.cases, "counts": counts, "refused": refused, "degraded_by_audit": degraded,
                      "failures": failures}, indent=1))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
