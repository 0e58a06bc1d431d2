#!/usr/bin/env python3
"""Histograms of the paper's Figure 10 metrics from a unimesh quality report.

    plot_quality.py quality.json quality.png

One panel per metric (area-length ratio Q^T, primal-dual Q^P, triangle
angles, edge length over spacing h_r); the refined mesh ("before") and the
optimised one ("after") overlaid when the report has both. Uses Debian's
python3-matplotlib, without a display.
"""
import json
import sys

from plot_signal import arguments_when_told

# Exit status 3: matplotlib is missing (the caller's hint names the package);
# any other failure (a full disk, say) is reported on stderr as it is.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402  (the backend is chosen first)
except ImportError as e:
    print(f"plot_quality.py: {e}", file=sys.stderr)
    sys.exit(3)

PANELS = (
    ("area_length_ratio", "area-length ratio $Q^T$", None),
    ("primal_dual", "primal-dual $Q^P$", None),
    ("angle_min_deg", "triangle angles (deg): min", "angle_max_deg"),
    ("edge_spacing_ratio", "edge length / spacing $h_r$", None),
)


def bars(ax, summary, label, colour):
    # One step outline filled down to the axis: a single artist, where a bar
    # per bin made drawing the figure take seconds.
    hist = summary["histogram"]
    counts = hist["counts"]
    lo, hi = hist["lo"], hist["hi"]
    width = (hi - lo) / len(counts)
    edges = [lo + i * width for i in range(len(counts) + 1)]
    ax.stairs(counts, edges, fill=True, alpha=0.55, color=colour, label=label)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1]) as f:
        report = json.load(f)
    before = report.get("before_optimisation")
    fig, axes = plt.subplots(1, len(PANELS), figsize=(4.2 * len(PANELS), 3.4))
    for ax, (key, title, second) in zip(axes, PANELS):
        if before:
            bars(ax, before[key], "refined", "tab:grey")
            if second:
                bars(ax, before[second], None, "tab:grey")
        bars(ax, report[key], "optimised" if before else "mesh", "tab:blue")
        if second:
            bars(ax, report[second], None, "tab:blue")
            title += " and max"
        s = report[key]
        ax.set_title(title, fontsize=10)
        ax.set_yscale("log")
        ax.set_xlabel(f"min {s['min']:.3f}, mean {s['mean']:.3f}", fontsize=8)
        ax.legend(fontsize=8)
    fig.suptitle(f"{report['triangles']} triangles; {report['obtuse_triangles']} obtuse, "
                 f"{report['not_well_centred']} not containing their orthocentre", fontsize=10)
    # Fixed margins: tight_layout measured every tick label, about a second.
    fig.subplots_adjust(left=0.04, right=0.99, bottom=0.17, top=0.84, wspace=0.22)
    try:
        fig.savefig(argv[2], dpi=110)
    except OSError as e:  # a full disk, a missing folder: one line, not a traceback
        print(f"plot_quality.py: cannot write {argv[2]}: {e.strerror}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(arguments_when_told(sys.argv)))
