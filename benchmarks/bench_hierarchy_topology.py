"""The topology comparison (models/hierarchy/README.md, "The message comparison"), run and drawn:
HST, STAR, FC and RING on the same empty 20 m room with n_s = 4, 8, 16, 32 scouts (W = 2, 4 x S = 2,
4, 8; the grid of ``experiments/hierarchy_topology.toml``) and **the same seeds in every arm**
(common random numbers: the sweep runner would spawn a different seed per condition). Then figures
of task transmissions, bytes, the busiest node's load and the completion time against n_s (one line
per topology, mean +- SD over the seeds) and a Markdown table of the means (plus a CSV of every
run).

Usage:
    python benchmarks/bench_hierarchy_topology.py                 # 4 arms x 6 sizes x 5 seeds
    python benchmarks/bench_hierarchy_topology.py --seeds 1       # a quick look

Writes ``<out>/topology.png``, ``<out>/topology.md`` and ``<out>/runs.csv``; prints progress.
"""

import argparse
import itertools
import os
import time
from concurrent.futures import as_completed
from pathlib import Path

import matplotlib
import pandas as pd
from tqdm import tqdm

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from abm.pools import process_pool  # noqa: E402
from analysis.runner import run_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SIZES = [(2, 2), (2, 4), (4, 2), (4, 4), (2, 8), (4, 8)]  # (W, S): n_s = 4, 8, 8, 16, 16, 32
FIRST_SEED = 2011053
METRICS = {
    "messages_task": "task transmissions (unicast, per run)",
    "bytes": "bytes transmitted (per run)",
    "max_node_load": "busiest node: sent + received",
    "completion_time": "completion time (s)",
}
ORDER = ("hst", "star", "fc", "ring")
#: Line styles that keep coinciding arms visible (FC and RING send the same totals; STAR, FC and
#: RING make the same plans, so their completion times coincide).
STYLE = {
    "hst": {"marker": "o", "linestyle": "-", "linewidth": 2.0},
    "star": {"marker": "s", "linestyle": "-", "linewidth": 2.0},
    "fc": {"marker": "^", "linestyle": "--", "linewidth": 3.0, "markersize": 9},
    "ring": {"marker": "v", "linestyle": ":", "linewidth": 2.0},
}


def _markdown(mean) -> str:
    """The means as a Markdown table (one row per topology and n_s)."""
    head = ["topology", "n_s", *mean.columns]
    rows = [f"| {' | '.join(head)} |", f"|{'---|' * len(head)}"]
    for (topo, n_s), row in mean.iterrows():
        cells = [topo, str(n_s), *(f"{v:,.4g}" for v in row.to_numpy())]
        rows.append(f"| {' | '.join(cells)} |")
    return "\n".join(rows) + "\n"


def _one(topology: str, workers: int, scouts: int, seed: int) -> dict:
    result = run_model("hierarchy", {"topology": topology, "workers": workers,
                                     "scouts_per_worker": scouts}, seed)  # fmt: skip
    return {**result.summary, "topology": topology, "seed": seed, "wall_time": result.wall_time,
            "n_s": workers * scouts}  # fmt: skip


def _run_all(args) -> pd.DataFrame:
    """Every arm x size x seed on a process pool; the rows also go to ``<out>/runs.csv``."""
    jobs = list(itertools.product(ORDER, SIZES, range(FIRST_SEED, FIRST_SEED + args.seeds)))
    t0 = time.perf_counter()
    rows = []
    with process_pool(args.workers or os.cpu_count()) as pool:
        futures = [pool.submit(_one, topo, w, s, seed) for topo, (w, s), seed in jobs]
        for future in tqdm(as_completed(futures), total=len(futures), unit="run"):
            rows.append(future.result())
    print(f"{len(rows)} runs in {time.perf_counter() - t0:.1f} s")
    ok = pd.DataFrame(rows)
    ok.to_csv(args.out / "runs.csv", index=False)
    return ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/hierarchy_topology"))
    parser.add_argument("--seeds", type=int, default=5, help="seeds per arm and size")
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    parser.add_argument("--plot-only", action="store_true", help="redraw from <out>/runs.csv")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    if args.plot_only:
        ok = pd.read_csv(args.out / "runs.csv")
    else:
        ok = _run_all(args)
    means = ok.groupby(["topology", "n_s"])[[*METRICS, "known_free_fraction", "links"]]
    mean, sd = means.mean(), means.std()
    fig, axes = plt.subplots(1, len(METRICS), figsize=(4.6 * len(METRICS), 4.0))
    for ax, (metric, label) in zip(axes, METRICS.items(), strict=True):
        for topo in ORDER:
            m, s = mean.loc[topo, metric], sd.loc[topo, metric]
            ax.errorbar(m.index, m.values, yerr=s.values, capsize=3, label=topo, **STYLE[topo])
        ax.set_xscale("log", base=2)
        ax.set_yscale("log" if metric != "completion_time" else "linear")
        ax.set_xlabel("scanning robots n_s = W S")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(title="topology", frameon=False)
    n = ok.groupby(["topology", "n_s"]).size()
    fig.suptitle(f"Same room, scouts, planning code and seeds; mean ± SD over {n.min()}-"
                 f"{n.max()} runs")  # fmt: skip
    fig.tight_layout()
    png = args.out / "topology.png"
    fig.savefig(png, dpi=110)
    md = args.out / "topology.md"
    md.write_text(_markdown(mean))
    print(mean.round(3).to_string())
    print(f"wrote {png}\nwrote {md}\nwrote {args.out / 'runs.csv'}")


if __name__ == "__main__":
    main()
