# SPDX-License-Identifier: LGPL-2.1-or-later
"""Per-element quality of a surface mesh (numpy only, no Qt): corner angles, radius ratio and
edge-length ratio of triangles and quadrilaterals (corner nodes; 2nd-order mid-nodes ignored)."""
import numpy as np

#: metric name -> (label, unit, True when larger is better, histogram range)
METRICS = {
    "radius_ratio": ("Radius ratio", "", True, (0.0, 1.0)),
    "min_angle": ("Minimum angle", "°", True, (0.0, 90.0)),
    "edge_ratio": ("Edge-length ratio", "", False, (1.0, 10.0)),
}

_QUAD_GAMMA = 2.0 * (np.sqrt(2.0) - 1.0)  # radius ratio of a corner triangle of a square


def _gamma(a, b, c):
    """Radius ratio 2 r_in / r_circ of triangles with corners a, b, c ((n, 3) arrays); 1 = equilateral."""
    la = np.linalg.norm(b - c, axis=1)
    lb = np.linalg.norm(c - a, axis=1)
    lc = np.linalg.norm(a - b, axis=1)
    area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)  # twice the area
    den = la * lb * lc * (la + lb + lc)
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.where(den > 0, 4.0 * area2 ** 2 / den, 0.0)
    return np.clip(g, 0.0, 1.0)


def _corner_angles(P, loops):
    """Corner angles in degrees, (n, k) for elements given as (n, k) corner index loops."""
    k = loops.shape[1]
    out = np.empty(loops.shape, dtype=np.float64)
    for i in range(k):
        p = P[loops[:, i]]
        u = P[loops[:, (i + 1) % k]] - p
        v = P[loops[:, (i - 1) % k]] - p
        nu = np.linalg.norm(u, axis=1)
        nv = np.linalg.norm(v, axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.einsum("ij,ij->i", u, v) / (nu * nv)
        out[:, i] = np.degrees(np.arccos(np.clip(np.nan_to_num(c, nan=1.0), -1.0, 1.0)))
    return out


def _edge_ratio(P, loops):
    k = loops.shape[1]
    lens = np.stack([np.linalg.norm(P[loops[:, (i + 1) % k]] - P[loops[:, i]], axis=1) for i in range(k)], axis=1)
    mn = lens.min(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(mn > 0, lens.max(axis=1) / mn, np.inf)


class Quality:
    """Metrics of all face elements, triangles first then quads (the order of element_ids).

    angles: all corner angles (flat); min_angle, max_angle, radius_ratio, edge_ratio: per element;
    element_ids: FemMesh element ids; face: 1-based CAD face per element; nodes: corner node
    indices per element (list of arrays)."""

    def __init__(self, arrays):
        P = np.asarray(arrays.nodes, dtype=np.float64)
        T = np.asarray(arrays.triangles, dtype=np.int64).reshape(-1, 3)
        Q = np.asarray(arrays.quads, dtype=np.int64).reshape(-1, 4)
        self.n_tri, self.n_quad = len(T), len(Q)
        ta = _corner_angles(P, T) if len(T) else np.zeros((0, 3))
        qa = _corner_angles(P, Q) if len(Q) else np.zeros((0, 4))
        self.angles = np.concatenate([ta.ravel(), qa.ravel()])
        self.min_angle = np.concatenate([ta.min(axis=1) if len(T) else [], qa.min(axis=1) if len(Q) else []])
        self.max_angle = np.concatenate([ta.max(axis=1) if len(T) else [], qa.max(axis=1) if len(Q) else []])
        tg = _gamma(P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]) if len(T) else np.zeros(0)
        if len(Q):
            corner = [_gamma(P[Q[:, i]], P[Q[:, (i + 1) % 4]], P[Q[:, (i + 3) % 4]]) for i in range(4)]
            qg = np.clip(np.min(corner, axis=0) / _QUAD_GAMMA, 0.0, 1.0)
        else:
            qg = np.zeros(0)
        self.radius_ratio = np.concatenate([tg, qg])
        self.edge_ratio = np.concatenate([_edge_ratio(P, T) if len(T) else [], _edge_ratio(P, Q) if len(Q) else []])
        self.element_ids = np.asarray(arrays.element_ids, dtype=np.int64)
        self.face = np.concatenate([np.asarray(arrays.triangle_face), np.asarray(arrays.quad_face)]).astype(np.int64)
        self._T, self._Q = T, Q
        self.points = P

    def __len__(self):
        return self.n_tri + self.n_quad

    def values(self, metric):
        return getattr(self, metric)

    def corners(self, i):
        """Corner node indices (0-based) of element i (in this object's order)."""
        return self._T[i] if i < self.n_tri else self._Q[i - self.n_tri]

    def kind(self, i):
        return "tria" if i < self.n_tri else "quad"

    def worst(self, metric, count=50):
        """Indices of the count worst elements for metric, worst first."""
        v = self.values(metric)
        better_high = METRICS[metric][2]
        key = v if better_high else -np.nan_to_num(v, posinf=1e300)
        count = min(count, len(v))
        if count == 0:
            return np.zeros(0, dtype=np.int64)
        idx = np.argpartition(key, count - 1)[:count]
        return idx[np.argsort(key[idx], kind="stable")]

    def normalized(self, metric):
        """Quality in [0, 1] (1 good) for the colour map."""
        v = self.values(metric)
        if metric == "radius_ratio":
            return np.clip(v, 0, 1)
        if metric == "min_angle":
            ideal = np.where(np.arange(len(v)) < self.n_tri, 60.0, 90.0)
            return np.clip(v / ideal, 0, 1)
        return np.clip(1.0 / np.nan_to_num(v, posinf=1e300), 0, 1)  # edge ratio: 1 best

    def histogram(self, metric, bins=20):
        """(counts, edges) of the metric (all corner angles for 'angle'); the last bin of the edge
        ratio also counts everything above its range."""
        if metric == "angle":
            return np.histogram(self.angles, bins=36, range=(0.0, 180.0))
        lo, hi = METRICS[metric][3]
        v = np.nan_to_num(self.values(metric), posinf=hi)
        return np.histogram(np.clip(v, lo, hi), bins=bins, range=(lo, hi))

    def summary(self):
        return {
            "elements": len(self), "triangles": self.n_tri, "quads": self.n_quad,
            "angle_min": float(self.min_angle.min()) if len(self) else 0.0,
            "angle_max": float(self.max_angle.max()) if len(self) else 0.0,
            "radius_ratio_min": float(self.radius_ratio.min()) if len(self) else 0.0,
            "radius_ratio_mean": float(self.radius_ratio.mean()) if len(self) else 0.0,
            "edge_ratio_max": float(np.nan_to_num(self.edge_ratio, posinf=1e300).max()) if len(self) else 0.0,
        }


def colormap(q):
    """RGB in [0, 1] for qualities q in [0, 1]: red (bad), orange, yellow, green, blue (good)."""
    q = np.clip(np.asarray(q, dtype=np.float64), 0.0, 1.0)
    stops = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    cols = np.array([[0.85, 0.0, 0.0], [1.0, 0.55, 0.0], [1.0, 0.95, 0.1], [0.2, 0.8, 0.2], [0.15, 0.35, 0.95]])
    return np.stack([np.interp(q, stops, cols[:, c]) for c in range(3)], axis=-1)
