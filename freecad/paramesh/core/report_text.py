# SPDX-License-Identifier: LGPL-2.1-or-later
"""Run reports as short lines for people (the task panel, FreeCAD's report view)."""


def volume_lines(report):
    """(level, text) lines of the report's volume section: the tetrahedra in all, then one line per
    solid (tetrahedra, interior nodes, worst dihedral angle, radius ratio) or its error. [] when
    the run did not fill solids."""
    vol = report.get("volume")
    if not vol:
        return []
    solids = vol.get("solids", [])
    head = f"{vol.get('tetrahedra', 0)} tetrahedra in {vol.get('solids_filled', 0)} of {len(solids)} solid(s)"
    if "straightened_tet10" in vol:
        head += (f"; tet10: {vol['straightened_tet10']} straightened, "
                 f"min scaled Jacobian {vol.get('min_tet10_scaled_jacobian', 0):.3f}")
    out = [("info", head)]
    for s in solids:
        name = f"Solid{s.get('solid', '?')}"
        if not s.get("ok", False):
            out.append(("error", f"{name}: not filled — {s.get('error', 'unknown reason')}"))
            continue
        out.append(("info", f"{name}: {s.get('tetrahedra', 0)} tetrahedra, {s.get('interior_nodes', 0)} interior "
                            f"nodes, min dihedral {s.get('min_dihedral', 0):.1f}°, radius ratio min "
                            f"{s.get('min_radius_ratio', 0):.3f} / mean {s.get('mean_radius_ratio', 0):.3f}"))
    return out
