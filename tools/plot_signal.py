"""The start signal of the picture scripts (plot_mesh.py, plot_quality.py).

`unimesh build` starts each script while it still writes the script's input,
with --when-told before the script's own arguments, so that Python and
matplotlib load meanwhile; it then says "go" on the script's stdin once the
input is complete. Anything else on stdin (the build gave up) ends the
script without drawing.
"""
import sys

CANCELLED = 4  # exit status: told to stop before drawing


def arguments_when_told(argv):
    """argv without --when-told, after waiting for "go" when it is given."""
    if len(argv) < 2 or argv[1] != "--when-told":
        return argv
    if sys.stdin.readline().strip() != "go":
        sys.exit(CANCELLED)
    return argv[:1] + argv[2:]
