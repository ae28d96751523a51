# SPDX-License-Identifier: LGPL-2.1-or-later
"""Shared helpers of the ParaMesh document objects (schema handling, state)."""

SCHEMA_VERSION = 1


def add_property(obj, ptype, name, group, doc, default=None, mode=None, enum=None):
    """Adds a property if it is missing (idempotent, so it runs both on creation and restore)."""
    if name not in obj.PropertiesList:
        obj.addProperty(ptype, name, group, doc)
        if enum is not None:
            setattr(obj, name, enum)
        if default is not None:
            setattr(obj, name, default)
    if mode is not None:
        obj.setEditorMode(name, mode)


class BaseProxy:
    """Proxy base: stores nothing in the file (properties hold the state); works with FreeCAD
    0.20 (__getstate__) and 1.x (dumps/loads)."""

    Type = "ParaMesh::Base"

    def __init__(self, obj):
        obj.Proxy = self
        self.init_properties(obj)

    def init_properties(self, obj):
        add_property(obj, "App::PropertyInteger", "SchemaVersion", "Base",
                     "Version of the ParaMesh object schema (for migrations)", SCHEMA_VERSION, mode=1)

    def onDocumentRestored(self, obj):
        self.init_properties(obj)
        if obj.SchemaVersion < SCHEMA_VERSION:
            obj.SchemaVersion = SCHEMA_VERSION

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None
