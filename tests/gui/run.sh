#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# ParaMesh GUI test: FreeCAD 0.20 under Xvfb with this repository linked as a user Mod folder in a
# throw-away FreeCAD user directory (the real ~/.local/share/FreeCAD is not touched).
# Exit status: 0 when every check passed. Screenshots and logs: $PARAMESH_GUI_OUT (default out/gui).
set -u
REPO=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${PARAMESH_GUI_OUT:-$REPO/out/gui}
mkdir -p "$OUT"
USERDIR=$(mktemp -d /tmp/paramesh_fc_XXXXXX)
trap 'rm -rf "$USERDIR"' EXIT
mkdir -p "$USERDIR/Mod"
ln -s "$REPO" "$USERDIR/Mod/ParaMesh"
export FREECAD_USER_HOME="$USERDIR" PARAMESH_REPO="$REPO" PARAMESH_GUI_OUT="$OUT"
export QTWEBENGINE_CHROMIUM_FLAGS=--no-sandbox
timeout "${PARAMESH_GUI_TIMEOUT:-420}" xvfb-run -a -s "-screen 0 1600x1000x24" \
    freecad "$REPO/tests/gui/run_gui_test.py" > "$OUT/freecad_output.log" 2>&1
rc=$?
if [ -f "$OUT/summary.txt" ]; then
    cat "$OUT/summary.txt"
else
    echo "GUI test: no summary written (FreeCAD exit status $rc); last output:"
    tail -40 "$OUT/freecad_output.log"
fi
if [ $rc -eq 0 ] && ! grep -q "^RESULT: PASS" "$OUT/summary.txt" 2>/dev/null; then
    rc=1
fi
exit $rc
