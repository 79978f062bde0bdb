"""The topology comparison of spec §5.3, run and drawn: ``experiments/hierarchy_topology.toml``
(HST, STAR, FC and RING on the same room with n_s = 4-32 scouts), then figures of total
transmissions, bytes, the busiest node's load and the completion time against n_s (one line
per topology, mean +- SD over the runs) and a Markdown table of the means.

Usage:
    python benchmarks/bench_hierarchy_topology.py                     # 120 runs, all cores
    python benchmarks/bench_hierarchy_topology.py --replications 1    # a quick look

Resumable (the common sweep runner); writes ``<out>/topology.png`` and ``<out>/topology.md``,
and the sweep's report ``<out>/report.html`` (claims and condition means).
"""

import argparse
import os
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from abm.pools import process_pool  # noqa: E402
from analysis.report import write_report  # noqa: E402
from analysis.sweep.execute import execute  # noqa: E402
from analysis.sweep.spec import load_sweep  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
METRICS = {
    "messages_task": "task transmissions (unicast, per run)",
    "bytes": "bytes transmitted (per run)",
    "max_node_load": "busiest node: sent + received",
    "completion_time": "completion time (s)",
}
ORDER = ("hst", "star", "fc", "ring")


def _markdown(mean) -> str:
    """The means as a Markdown table (one row per topology and n_s)."""
    head = ["topology", "n_s", *mean.columns]
    rows = [f"| {' | '.join(head)} |", f"|{'---|' * len(head)}"]
    for (topo, n_s), row in mean.iterrows():
        cells = [topo, str(n_s), *(f"{v:,.4g}" for v in row.to_numpy())]
        rows.append(f"| {' | '.join(cells)} |")
    return "\n".join(rows) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/hierarchy_topology"))
    parser.add_argument("--replications", type=int, default=None)
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    args = parser.parse_args()
    sweep = load_sweep(ROOT / "experiments" / "hierarchy_topology.toml", args.replications)
    folder = args.out / sweep.name
    t0 = time.perf_counter()
    with process_pool(args.workers or os.cpu_count()) as pool:
        runs = execute(sweep, folder, executor=pool, progress=True)
    print(f"{len(runs)} runs in {time.perf_counter() - t0:.1f} s")
    ok = runs[runs["status"] == "ok"].copy()
    ok["n_s"] = ok["workers"] * ok["scouts_per_worker"]
    means = ok.groupby(["topology", "n_s"])[[*METRICS, "known_free_fraction", "links"]]
    mean, sd = means.mean(), means.std()
    fig, axes = plt.subplots(1, len(METRICS), figsize=(4.6 * len(METRICS), 4.0))
    for ax, (metric, label) in zip(axes, METRICS.items(), strict=True):
        for topo in ORDER:
            if topo in mean.index.get_level_values(0):
                m, s = mean.loc[topo, metric], sd.loc[topo, metric]
                ax.errorbar(m.index, m.values, yerr=s.values, marker="o", capsize=3, label=topo)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log" if metric != "completion_time" else "linear")
        ax.set_xlabel("scanning robots n_s = W S")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(title="topology", frameon=False)
    n = ok.groupby(["topology", "n_s"]).size()
    fig.suptitle(f"Same room, scouts and planning code; mean ± SD over {n.min()}-{n.max()} runs")
    fig.tight_layout()
    png = args.out / "topology.png"
    fig.savefig(png, dpi=110)
    md = args.out / "topology.md"
    md.write_text(_markdown(mean))
    print(mean.round(3).to_string())
    report = write_report([folder], args.out / "report.html")
    print(f"wrote {png}\nwrote {md}\nwrote {report}")


if __name__ == "__main__":
    main()
