# SPDX-License-Identifier: LGPL-2.1-or-later
"""Meshing parameters: validated dataclasses whose fields are the CLI's option names in snake_case.

Every field is described once in FIELDS (name, unit, default, help); the same text feeds the
docstrings, the Python error messages and the FreeCAD property tooltips.
"""
from dataclasses import dataclass, field, fields
import math
import numbers

# name -> (unit, help)
FIELDS = {
    "size": ("length", "Target element edge length (straight 3D length), > 0. Left out (None): bounding-box diagonal / 50."),
    "min_size": ("length", "Smallest size a size source (curvature, local size) may ask for. When set, the curvature refinement makes no edge below it either (where the curvature angle needs smaller triangles, they stay at the min-size and the report lists them), > 0. Left out (None): size / 100 (size / 1000 with a curvature angle or a max deviation)."),
    "max_size": ("length", "Largest element size, > 0. Left out (None): size."),
    "curvature_angle": ("degree", "Largest angle an element may subtend on curved faces and edges. 0: off."),
    "max_deviation": ("fraction of size", "Largest distance of a triangle centroid from the CAD, as a fraction "
                      "of size; refines only where needed. 0: off."),
    "grading": ("ratio", "Largest size ratio between neighbouring elements (> 1): sizes grow by at most this "
                "factor per element away from small ones, in 3D and across faces."),
    "threads": ("count", "Worker threads for the faces; 0: all cores. The result does not depend on it."),
    "order": ("1 or 2", "Element order; 2 puts mid-edge nodes on the CAD."),
    "quads": ("bool", "Quad-dominant surface mesh."),
    "optimize_passes": ("count", "Passes of the 3D optimiser (swaps and smoothing)."),
    "max_elements": ("count", "The run stops with an error when the faces would hold more elements than "
                     "this (about 330 bytes each): a size far too small for the model fails at once "
                     "instead of filling the memory."),
    "proximity": ("count", "At least this many elements across thin walls and narrow faces (a first mesh "
                  "measures them). 0: off."),
    "nearest_face_check": ("bool", "Refine triangles cut so deep into a thin part (more than 4.5 % of size) "
                           "that their centroid lies nearer another CAD face than their own, and mesh "
                           "again (at most 6 times), whatever it costs. Off: the same check runs within "
                           "nearest_face_budget."),
    "nearest_face_budget": ("fraction", "By default the nearest-face refinement is kept when it adds at most "
                            "this fraction of triangles (0.1 = 10 %); otherwise the unrefined mesh is kept "
                            "and the report warns. 0: no automatic check."),
    "volume": ("bool", "Also fill every closed solid with tetrahedra (tet4, tet10 at order 2) bounded by the "
               "surface triangles; needs a triangle surface mesh (no quads, triangle boundary layers)."),
    "volume_max_size": ("length", "Largest tetrahedron edge inside the solids, > 0. Left out (None): max_size (the interior grows "
                        "from the surface sizes at the grading up to it)."),
    "volume_optimize": ("count", "nglib's optimisation passes on the tetrahedra (swaps, smoothing); each costs "
                        "about as much as the fill itself."),
    "local_sizes": ("list", "Local sizes: LocalSize objects or dicts {'faces'|'edges'|'vertices': [i,...], "
                    "'size': h}, or strings 'Face3=0.5'."),
    "groups": ("dict", "Named groups tagged in every output beside the default Face<i> / Solid<i> ones: "
               "{'inlet': ['Face3', 'Face7'], 'rim': ['Edge2']} or a list of 'inlet=Face3,Face7' strings."),
    "boundary_layers": ("list", "Surface boundary layers: BoundaryLayer objects or dicts {'edges': [21], "
                        "'first_height': 0.5, 'growth': 1.2, 'layers': 20 (or 'thickness'), 'quads': True}; "
                        "{'auto': True, ...} grows from the detected leading edges."),
}


def _groups(v):
    """groups as {name: ['Face3', ...]}: from a dict of lists (or of 'Face3,Face7' strings) or a list
    of 'NAME=Face3,Face7' strings; names and entities are checked by the core's parser."""
    if isinstance(v, str):
        v = [v]
    if isinstance(v, (list, tuple)):
        out = {}
        for t in v:
            if not isinstance(t, str) or "=" not in t:
                raise ValueError(f"groups: expected 'NAME=Face3,Face7', got {t!r}")
            name, items = t.split("=", 1)
            out[name] = items.split(",")
        v = out
    if not isinstance(v, dict):
        raise TypeError(f"groups must be a dict {{'inlet': ['Face3', 'Face7']}}, got {type(v).__name__}")
    out = {}
    for name, items in v.items():
        if isinstance(items, str):
            items = items.split(",")
        if not isinstance(name, str) or not all(isinstance(i, str) for i in items):
            raise TypeError(f"groups: {name!r} must map to names like ['Face3', 'Face7']")
        out[name] = [i.strip() for i in items]
    from .. import _native
    for name, items in out.items():
        _native.parse_group(f"{name}={','.join(items)}")  # the core's check: a bad name is refused now
    return out


def _number(name, v, lo=None, hi=None, lo_open=False, integer=False):
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(v).__name__} {v!r}")
    if integer and int(v) != v:
        raise ValueError(f"{name} must be an integer, got {v!r}")
    v = int(v) if integer else float(v)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    if lo is not None and (v <= lo if lo_open else v < lo):
        raise ValueError(f"{name} must be {'>' if lo_open else '>='} {lo}, got {v!r}")
    if hi is not None and v > hi:
        raise ValueError(f"{name} must be <= {hi}, got {v!r}")
    return v


def _length(name, v):
    """A size that may be left out (None); when given it must be > 0 (0 is not 'the default')."""
    return None if v is None else _number(name, v, lo=0, lo_open=True)


def _boolean(name, v):
    if not isinstance(v, bool):
        raise TypeError(f"{name} must be True or False, got {v!r}")
    return v


def _indices(name, v):
    if isinstance(v, (int, numbers.Integral)) and not isinstance(v, bool):
        v = [v]
    if isinstance(v, str) or not hasattr(v, "__iter__"):
        raise TypeError(f"{name} must be a list of 1-based numbers, got {v!r}")
    out = []
    for x in v:
        if isinstance(x, bool) or not isinstance(x, numbers.Integral):
            if isinstance(x, str) and x.lstrip("FaceEdgVrtx").isdigit():
                x = int(x.lstrip("FaceEdgVrtx"))
            else:
                raise TypeError(f"{name} must hold 1-based integers (FreeCAD numbering), got {x!r}")
        if x < 1:
            raise ValueError(f"{name}: entity numbers start at 1 (FreeCAD's Face1/Edge1), got {x}")
        out.append(int(x))
    if not out:
        raise ValueError(f"{name} is empty")
    return out


@dataclass
class LocalSize:
    """A target size near CAD faces, edges or vertices (1-based FreeCAD numbers)."""
    kind: str = "face"        #: "face", "edge" or "vertex"
    entities: list = field(default_factory=list)
    size: float = 0.0         #: target size near the entities (length, > 0)

    @staticmethod
    def parse(spec):
        """From a LocalSize, a dict {'faces': [3], 'size': 0.5} or a string 'Face3=0.5'."""
        if isinstance(spec, LocalSize):
            return spec
        if isinstance(spec, str):
            try:
                name, value = spec.split("=")
                for kind, prefix in (("face", "Face"), ("edge", "Edge"), ("vertex", "Vertex")):
                    if name.strip().startswith(prefix):
                        return LocalSize(kind, [int(name.strip()[len(prefix):])], float(value))
            except ValueError:
                pass
            raise ValueError(f"local size {spec!r}: expected 'FaceN=size', 'EdgeN=size' or 'VertexN=size'")
        if isinstance(spec, dict):
            for kind in ("face", "edge", "vertex"):
                for key in (kind + "s", kind, kind + "es" if kind == "vertex" else kind):
                    if key in spec:
                        return LocalSize(kind, spec[key], spec.get("size", 0.0))
            if "vertices" in spec:
                return LocalSize("vertex", spec["vertices"], spec.get("size", 0.0))
            raise ValueError(f"local size {spec!r}: needs 'faces', 'edges' or 'vertices' and 'size'")
        raise TypeError(f"local size must be a dict, a string or LocalSize, got {type(spec).__name__}")

    def validate(self, i=0):
        tag = f"local_sizes[{i}]"
        if self.kind not in ("face", "edge", "vertex"):
            raise ValueError(f"{tag}.kind must be 'face', 'edge' or 'vertex', got {self.kind!r}")
        self.entities = _indices(f"{tag}.{self.kind}s", self.entities)
        self.size = _number(f"{tag}.size", self.size, lo=0, lo_open=True)


@dataclass
class BoundaryLayer:
    """Rows of stretched elements grown in the surface from CAD edges (1-based FreeCAD numbers).
    Give the number of layers or the total thickness."""
    edges: list = field(default_factory=list)
    first_height: float = 0.0   #: height of the first row (length, > 0)
    growth: float = 1.2         #: ratio between consecutive row heights (>= 1)
    layers: int = 0             #: number of rows (0: from thickness)
    thickness: float = 0.0      #: total thickness (length; 0: from layers)
    max_aspect: float = 0.0     #: a column stops when its row is this much thinner than the spacing... 0: off
    quads: bool = True          #: stretched quads (True) or each quad split into two triangles
    auto: bool = False          #: grow from the automatically detected leading edges (edges may be empty)

    @staticmethod
    def parse(spec):
        if isinstance(spec, BoundaryLayer):
            return spec
        if isinstance(spec, dict):
            unknown = set(spec) - {f.name for f in fields(BoundaryLayer)}
            if unknown:
                raise ValueError(f"boundary layer: unknown key(s) {sorted(unknown)}")
            return BoundaryLayer(**spec)
        raise TypeError(f"boundary layer must be a dict or BoundaryLayer, got {type(spec).__name__}")

    def validate(self, i=0):
        tag = f"boundary_layers[{i}]"
        _boolean(f"{tag}.auto", self.auto)
        self.edges = _indices(f"{tag}.edges", self.edges) if (self.edges or not self.auto) else []
        self.first_height = _number(f"{tag}.first_height", self.first_height, lo=0, lo_open=not self.auto)
        self.growth = _number(f"{tag}.growth", self.growth, lo=1.0, hi=5.0)
        self.layers = _number(f"{tag}.layers", self.layers, lo=0, hi=1000, integer=True)
        self.thickness = _number(f"{tag}.thickness", self.thickness, lo=0)
        self.max_aspect = _number(f"{tag}.max_aspect", self.max_aspect, lo=0)
        _boolean(f"{tag}.quads", self.quads)
        if self.layers == 0 and self.thickness == 0:
            if not self.auto:
                raise ValueError(f"{tag}: give layers or thickness")
            self.layers = 20


@dataclass
class MeshParams:
    """All meshing parameters. See FIELDS for units and meaning; validate() raises ValueError or
    TypeError naming the field."""
    size: float = None       # None: left out (the core's default); a given size must be > 0
    min_size: float = None
    max_size: float = None
    curvature_angle: float = 0.0
    max_deviation: float = 0.0
    grading: float = 1.3
    threads: int = 1
    order: int = 1
    quads: bool = False
    optimize_passes: int = 4
    max_elements: int = 50_000_000
    proximity: int = 0
    nearest_face_check: bool = False
    nearest_face_budget: float = 0.10
    volume: bool = False
    volume_max_size: float = None
    volume_optimize: int = 1
    local_sizes: list = field(default_factory=list)
    boundary_layers: list = field(default_factory=list)
    groups: dict = field(default_factory=dict)

    @classmethod
    def from_kwargs(cls, **kw):
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(kw) - names)
        if unknown:
            raise TypeError(f"unknown parameter(s) {unknown}; known: {sorted(names)}")
        p = cls(**kw)
        p.validate()
        return p

    def validate(self):
        self.size = _length("size", self.size)
        self.min_size = _length("min_size", self.min_size)
        self.max_size = _length("max_size", self.max_size)
        if self.min_size and self.max_size and self.min_size > self.max_size:
            raise ValueError(f"min_size ({self.min_size}) is larger than max_size ({self.max_size})")
        self.curvature_angle = _number("curvature_angle", self.curvature_angle, lo=0, hi=179.9)
        self.max_deviation = _number("max_deviation", self.max_deviation, lo=0, hi=1)
        self.grading = _number("grading", self.grading, lo=1.0, lo_open=True, hi=10)
        self.threads = _number("threads", self.threads, lo=0, hi=1024, integer=True)
        self.order = _number("order", self.order, lo=1, hi=2, integer=True)
        _boolean("quads", self.quads)
        self.optimize_passes = _number("optimize_passes", self.optimize_passes, lo=0, hi=100, integer=True)
        self.max_elements = _number("max_elements", self.max_elements, lo=1000, hi=1e10, integer=True)
        self.proximity = _number("proximity", self.proximity, lo=0, hi=100, integer=True)
        _boolean("nearest_face_check", self.nearest_face_check)
        self.nearest_face_budget = _number("nearest_face_budget", self.nearest_face_budget, lo=0, hi=10)
        _boolean("volume", self.volume)
        self.volume_max_size = _length("volume_max_size", self.volume_max_size)
        self.volume_optimize = _number("volume_optimize", self.volume_optimize, lo=0, hi=10, integer=True)
        if isinstance(self.local_sizes, (dict, str, LocalSize)):
            self.local_sizes = [self.local_sizes]
        if isinstance(self.boundary_layers, (dict, BoundaryLayer)):
            self.boundary_layers = [self.boundary_layers]
        self.local_sizes = [LocalSize.parse(s) for s in self.local_sizes]
        for i, s in enumerate(self.local_sizes):
            s.validate(i)
        self.boundary_layers = [BoundaryLayer.parse(b) for b in self.boundary_layers]
        for i, b in enumerate(self.boundary_layers):
            b.validate(i)
        self.groups = _groups(self.groups)
        return self

    def to_native(self):
        from .. import _native
        n = _native.MeshParams()
        for name in ("size", "min_size", "max_size", "curvature_angle", "max_deviation", "grading",
                     "threads", "order", "quads", "optimize_passes", "proximity", "nearest_face_check",
                     "nearest_face_budget", "max_elements", "volume", "volume_max_size",
                     "volume_optimize"):
            if getattr(self, name) is not None:  # None: left out, the core's default
                setattr(n, name, getattr(self, name))
        ls = []
        for s in self.local_sizes:
            x = _native.LocalSize()
            x.kind = {"face": _native.LocalSize.Kind.Face, "edge": _native.LocalSize.Kind.Edge,
                      "vertex": _native.LocalSize.Kind.Vertex}[s.kind]
            x.entities = list(s.entities)
            x.size = s.size
            ls.append(x)
        n.local_sizes = ls
        bl = []
        for b in self.boundary_layers:
            x = _native.BoundaryLayerSpec()
            x.edges = list(b.edges)
            x.first_height, x.growth, x.layers = b.first_height, b.growth, b.layers
            x.thickness, x.max_aspect, x.quads = b.thickness, b.max_aspect, b.quads
            x.auto_edges = b.auto
            bl.append(x)
        n.boundary_layers = bl
        n.groups = [_native.parse_group(f"{name}={','.join(items)}") for name, items in self.groups.items()]
        return n


MeshParams.__doc__ += "\n\nFields:\n" + "\n".join(
    f"    {k} ({u}): {h}" for k, (u, h) in FIELDS.items())
