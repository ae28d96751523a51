# SPDX-License-Identifier: LGPL-2.1-or-later
"""FeaturePython proxies. Their module paths are stored in .FCStd files: never move or rename a
proxy class without leaving an alias here."""
