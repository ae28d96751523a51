#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Every shared model at h = diagonal / div through the CLI, its audit and the independent checker.

usage: bench/audit_sweep.py [--div 100] [--extra "--curvature-angle 10"] [--models a.stp,b.brep]
                            [--paramesh EXE] [--out DIR] [--json FILE] [--timeout S]

Per model: `paramesh mesh MODEL -o OUT.msh --size H --report R.json [extra]`, then
../shared/tools/meshcheck.py MODEL OUT.msh --size H. Prints a Markdown table: exit code, status,
failed faces, the audit's non-zero counts (and repaired nodes), meshcheck's boundary / non-manifold
edges, per-solid open / non-manifold edges, duplicate nodes, % flipped against the CAD, the worst
node's distance to the CAD / H, gamma_min, and the run's seconds. Run with Debian's /usr/bin/python3.
"""
import argparse, json, os, re, subprocess, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.abspath(os.path.join(ROOT, '..', 'shared'))
PY = '/usr/bin/python3'


def run_model(exe, model, div, extra, out, timeout):
    info = subprocess.run([exe, 'info', model], capture_output=True, text=True).stdout
    h = float(re.search(r'diagonal ([0-9.eE+-]+)', info).group(1)) / div
    base = os.path.join(out, f'{os.path.basename(model)}_{div}')
    cmd = [exe, 'mesh', model, '-o', base + '.msh', '--size', repr(h), '--report', base + '.json'] + extra
    t0 = time.time()
    try:
        rc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout).returncode
    except subprocess.TimeoutExpired:
        return dict(model=os.path.basename(model), h=h, rc='timeout')
    row = dict(model=os.path.basename(model), h=h, rc=rc, seconds=time.time() - t0)
    try:
        rep = json.load(open(base + '.json'))
    except (OSError, ValueError):
        return row
    a = rep.get('audit', {})
    row.update(status=rep.get('status'), triangles=rep.get('counts', {}).get('triangles'),
               failed=[f['name'] for f in rep.get('faces', []) if f.get('status') != 'ok'],
               audit_passed=a.get('passed'), audit_found={k: v for k, v in a.get('counts', {}).items() if v},
               repaired=a.get('repaired_nodes', 0))
    chk = subprocess.run([PY, os.path.join(SHARED, 'tools', 'meshcheck.py'), model, base + '.msh',
                          '--size', repr(h)], capture_output=True, text=True)
    try:
        row['check'] = json.loads(chk.stdout)
    except ValueError:
        row['check'] = {'error': chk.stderr[-300:]}
    os.remove(base + '.msh')
    return row


def table(rows):
    out = ['| model | h | triangles | exit | status | failed faces | audit | bnd / nm | solid open / nm | dup nodes '
           '| flipped % | node dev / h | gamma_min | s |', '|' + '---|' * 14]
    for r in rows:
        c = r.get('check', {})
        audit = ('pass' if r.get('audit_passed') else f"FAIL {r.get('audit_found')}") + \
            (f", {r['repaired']} repaired" if r.get('repaired') else '')
        f = lambda k, spec='{}': spec.format(c[k]) if k in c else '–'  # noqa: E731
        out.append(f"| {r['model']} | {r['h']:.4g} | {r.get('triangles', '–')} | {r['rc']} | {r.get('status', '–')} "
                   f"| {', '.join(r.get('failed', [])) or '–'} | {audit} | {f('boundary_edges')} / {f('nonmanifold_edges')} "
                   f"| {f('solid_open_edges')} / {f('solid_nonmanifold_edges')} | {f('duplicate_nodes')} "
                   f"| {f('pct_flipped_vs_cad', '{:.2f}')} | {f('node_dev_max_rel', '{:.1e}')} "
                   f"| {f('gamma_min', '{:.3g}')} | {r.get('seconds', 0):.1f} |")
    return '\n'.join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--div', type=float, default=100)
    ap.add_argument('--extra', default='')
    ap.add_argument('--models', default='')
    ap.add_argument('--paramesh', default=os.path.join(ROOT, 'build', 'bin', 'paramesh'))
    ap.add_argument('--out', default='/tmp/paramesh_audit_sweep')
    ap.add_argument('--json', default='')
    ap.add_argument('--timeout', type=float, default=1800)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    models = a.models.split(',') if a.models else sorted(
        os.path.join(SHARED, 'models', m) for m in os.listdir(os.path.join(SHARED, 'models')) if not m.endswith('.md'))
    div = int(a.div) if a.div == int(a.div) else a.div
    rows = [run_model(a.paramesh, m, div, a.extra.split(), a.out, a.timeout) for m in models]
    if a.json:
        json.dump(rows, open(a.json, 'w'), indent=1)
    print(f"h = diagonal / {div}{' ' + a.extra if a.extra else ''}\n")
    print(table(rows))


if __name__ == '__main__':
    main()
