# SPDX-License-Identifier: LGPL-2.1-or-later
"""View provider of a ParaMesh local size (child of a surface mesh in the tree)."""
from .view_base import ViewProviderChild


class ViewProviderLocalSize(ViewProviderChild):
    icon = "ParaMesh_LocalSize"
    task_module = "task_local_size"
    task_class = "TaskLocalSize"
