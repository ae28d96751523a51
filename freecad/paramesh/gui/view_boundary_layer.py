# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of a ParaMesh boundary layer (child of a surface mesh in the tree)."""
from .view_base import ViewProviderChild


class ViewProviderBoundaryLayer(ViewProviderChild):
    icon = "ParaMesh_BoundaryLayer"
    task_module = "task_boundary_layer"
    task_class = "TaskBoundaryLayer"
