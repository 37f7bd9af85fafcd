"""bench/run_all.py's table as text, JSON and a PNG bar chart (matplotlib), the machine
stated at the top of each."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

from machine import machine_line
from table_rows import Row


def number(value: float | None) -> str:
    if value is None:
        return "-"
    if abs(value) >= 100:
        return f"{value:,.0f}"
    return f"{value:.3g}"


def met_cell(row: Row) -> str:
    return "" if row.met is None else ("yes" if row.met else "NO")


COLUMNS = (("measure", 58, "<"), ("unit", 9, "<"), ("ours", 9, ">"), ("peer", 9, ">"), ("ratio", 7, ">"),
           ("target", 24, ">"), ("met", 4, ">"))


def format_table(rows: list[Row], machine: dict) -> str:
    """The table: the machine first, a line per row with its peer and note under it."""
    header = "".join(f"{name:{align}{width}} " for name, width, align in COLUMNS)
    lines = ["machine: " + machine_line(machine), "ratio: how many times better ours is than the peer "
             "(> 1: ours faster / smaller), from figures measured in this run", "", header, "-" * len(header)]
    for row in rows:
        cells = (row.measure, row.unit, number(row.ours), number(row.peer),
                 "-" if row.ratio is None else f"{row.ratio:.3g}x", row.target, met_cell(row))
        lines.append("".join(f"{c[:w]:{a}{w}} " for c, (_, w, a) in zip(cells, COLUMNS)))
        detail = "; ".join(x for x in (f"peer: {row.peer_name}" if row.peer_name else "", row.note) if x)
        if detail:
            lines += textwrap.wrap(detail, width=len(header) - 4, initial_indent="    ", subsequent_indent="    ")
    return "\n".join(lines)


def write_json(path: Path, rows: list[Row], machine: dict, runs: dict) -> None:
    path.write_text(json.dumps({"machine": machine, "rows": [row.as_dict() for row in rows], "runs": runs},
                               indent=2, default=str))


def write_chart(path: Path, rows: list[Row], machine: dict) -> None:
    """Ratio per measure (log scale), green where the row's target is met, red where it is
    not, grey where the issue names none; rows without a peer figure are listed beneath."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plotted = [row for row in rows if row.ratio is not None]
    left_out = [row.measure for row in rows if row.ratio is None]
    height = 1.6 + 0.38 * max(len(plotted), 1)
    fig, ax = plt.subplots(figsize=(12, height + 0.18 * len(left_out) / 2))
    colours = ["#4a4" if row.met else "#d44" if row.met is False else "#888" for row in plotted]
    labels = [f"{row.measure} ({row.unit})" for row in plotted]
    ratios = [row.ratio for row in plotted]
    ax.barh(range(len(plotted)), ratios, color=colours)
    ax.set_yticks(range(len(plotted)), labels, fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.axvline(1.0, color="black", linewidth=0.8)
    low, high = min(ratios + [1.0]), max(ratios + [1.0])
    ax.set_xlim(low / 3, high * 300)  # room on the right for each bar's figures
    for i, row in enumerate(plotted):
        ax.text(row.ratio, i, f" {row.ratio:.3g}x  (ours {number(row.ours)}, {row.peer_name}: {number(row.peer)})",
                va="center", fontsize=7)
        if row.target.startswith("ratio >= "):  # the target for the ratio itself
            ax.plot([float(row.target.split()[-1])], [i], marker="|", markersize=14, color="black")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in ("#4a4", "#d44", "#888")]
    ax.legend(handles + [plt.Line2D([], [], marker="|", linestyle="", color="black", markersize=10)],
              ["target met", "target missed", "no target", "target ratio"], fontsize=7, loc="lower right")
    ax.set_xlabel("ratio: times better than the peer measured in the same run (log scale; > 1: ours better)")
    fig.suptitle("\n".join(textwrap.wrap("animanifold benchmark table. " + machine_line(machine), 170)), fontsize=8)
    if left_out:
        fig.text(0.01, 0.005, "\n".join(textwrap.wrap("No peer figure (see the table): " + "; ".join(left_out), 190)),
                 fontsize=6, va="bottom")
    fig.tight_layout(rect=(0, 0.02 + 0.012 * len(left_out) / 3, 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)
