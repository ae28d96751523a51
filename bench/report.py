#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Markdown table and pass/fail summary of a bench/compare.py run, against issue 2's criteria.

usage: report.py QUALITY.json [QUALITY2.json ...] [--timing TIMING.json]
QUALITY.json: results.json of a run with meshcheck (bench/compare.py without --no-check); several
(runs over disjoint --models lists, e.g. two halves run side by side) are merged, sorted by model
and h;
TIMING.json: results.json of a separate --no-check run (seconds taken from it when given).
The comparison uses the exact meshcheck values, not the rounded ones printed in the table.
"""
import argparse, json, statistics


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('quality', nargs='+')
    ap.add_argument('--timing', default='')
    a = ap.parse_args()
    rows = sorted((r for q in a.quality for r in json.load(open(q))), key=lambda r: (r['model'], r['div']))
    timing = {}
    if a.timing:
        for r in json.load(open(a.timing)):
            timing[(r['model'], r['div'])] = (r['ours'].get('mesh_s'), r['gmsh'].get('mesh_s'))
    print('| model | h | ParaMesh s | Gmsh s | speed-up | ParaMesh tris | Gmsh tris | γ mean P / G '
          '| % <30° P / G | % len OK P / G | failed faces | bnd / nm edges | dup nodes | flipped % | node dev |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    speed, fails = [], {'gamma': [], 'a30': [], 'len': [], 'valid': [], 'flip': [], 'dev': []}
    for r in rows:
        o, oc, g, gc = r['ours'], r['ours_check'], r['gmsh'], r['gmsh_check']
        ps, gs = timing.get((r['model'], r['div']), (o.get('mesh_s'), g.get('mesh_s')))
        sp = gs / ps if ps and gs else None
        if sp:
            speed.append(sp)
        key = f"{r['model']} d/{r['div']}"
        if oc['gamma_mean'] < gc['gamma_mean']:
            fails['gamma'].append(f"{key} {oc['gamma_mean']:.4f} vs {gc['gamma_mean']:.4f}")
        if oc['pct_angle_lt_30'] > gc['pct_angle_lt_30']:
            fails['a30'].append(f"{key} {oc['pct_angle_lt_30']:.3f} vs {gc['pct_angle_lt_30']:.3f}")
        if oc['pct_len_in_sqrt2'] < gc['pct_len_in_sqrt2']:
            fails['len'].append(f"{key} {oc['pct_len_in_sqrt2']:.2f} vs {gc['pct_len_in_sqrt2']:.2f}")
        if o.get('failed_faces') or oc['nonmanifold_edges'] or oc['duplicate_nodes'] or oc['unused_nodes']:
            fails['valid'].append(key)
        if oc['pct_flipped_vs_cad'] > 0:
            fails['flip'].append(f"{key} {oc['pct_flipped_vs_cad']:.2f} % (Gmsh {gc['pct_flipped_vs_cad']:.2f} %)")
        if oc['node_dev_max_rel'] > 1e-4:
            fails['dev'].append(f"{key} {oc['node_dev_max_rel']:.2g} (Gmsh {gc['node_dev_max_rel']:.2g})")
        print(f"| {r['model']} | d/{r['div']} | {ps:.2f} | {gs:.2f} | {sp:.1f}× | {oc['triangles']} | {gc['triangles']} "
              f"| {oc['gamma_mean']:.4f} / {gc['gamma_mean']:.4f} "
              f"| {oc['pct_angle_lt_30']:.3f} / {gc['pct_angle_lt_30']:.3f} "
              f"| {oc['pct_len_in_sqrt2']:.2f} / {gc['pct_len_in_sqrt2']:.2f} "
              f"| {len(o.get('failed_faces') or [])} | {oc['boundary_edges']} / {oc['nonmanifold_edges']} "
              f"| {oc['duplicate_nodes']} | {oc['pct_flipped_vs_cad']:.2f} | {oc['node_dev_max_rel']:.1e} |")
    n = len(rows)
    print()
    print(f"- faster than Gmsh on {sum(s > 1 for s in speed)} of {n}: {min(speed):.1f}× to {max(speed):.1f}× "
          f"(median {statistics.median(speed):.1f}×)")
    print(f"- invalid (failed face, non-manifold edge, duplicate or unused node): {len(fails['valid'])} of {n} {fails['valid']}")
    print(f"- γ mean ≥ Gmsh's on {n - len(fails['gamma'])} of {n}; below: {fails['gamma']}")
    print(f"- % < 30° ≤ Gmsh's on {n - len(fails['a30'])} of {n}; above: {fails['a30']}")
    print(f"- % len OK ≥ Gmsh's on {n - len(fails['len'])} of {n}; below: {fails['len']}")
    print(f"- flipped > 0: {fails['flip']}")
    print(f"- node dev > 1e-4: {fails['dev']}")


if __name__ == '__main__':
    main()
