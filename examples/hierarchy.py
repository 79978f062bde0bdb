"""A hierarchical swarm (Alunni et al., WPI 2011) maps the report's empty 20 m x 20 m room: the
queen, 2 workers and 2 scouts each (N = 7, the report's "four physical robots and three virtual
robots").

Covers: a run until the queen's coverage call ends, the per-level results the report plots
(mean scan area and drive distance per scout and per worker, queen iterations), the completion
time, the messages by kind counted on the tree's links, the diagnostics of claim C12, and a PNG
of the final swarm over the queen's known map. Prints where every output went.
"""

from pathlib import Path

from abm.draw import save_swarm_png
from models.hierarchy import HierarchyModel

WORKERS = 2  # W, level-1 robots
SCOUTS_PER_WORKER = 2  # S, level-2 robots under each worker
SEED = 1
OUT = Path("out/hierarchy")


def main() -> None:
    model = HierarchyModel(workers=WORKERS, scouts_per_worker=SCOUTS_PER_WORKER, seed=SEED)
    model.run()
    s = model.summary()
    print(f"HST, W = {WORKERS}, S = {SCOUTS_PER_WORKER} (N = {s['N']}), 20 m room, seed {SEED}:")
    print(f"  ended by          {s['end_reason']} at t = {s['time']:.1f} s")
    print(f"  free cells known  {100 * s['known_free_fraction']:.2f} %")
    print(f"  scout  scan area  {s['scout_scan_area']:.1f} m^2, drive {s['scout_drive']:.1f} m")
    print(f"  worker scan area  {s['worker_scan_area']:.1f} m^2, drive {s['worker_drive']:.1f} m")
    print(f"  queen iterations  {s['queen_iterations']}, worker iterations "
          f"{s['worker_iterations']:.1f} (mean)")  # fmt: skip
    log = model.comms.log.frame()
    print(f"  messages          {len(log)} ({s['bytes']} bytes); busiest node "
          f"{s['max_node_load']} sent + received")  # fmt: skip
    for kind, count in log["kind"].value_counts().items():
        print(f"    {kind:14s}  {count}")
    print(f"  C12 diagnostics   {s['wave_order_violations']} wave-order violations, "
          f"{s['robot_proximity_events']} proximity events, "
          f"{s['robot_collisions']} contacts")  # fmt: skip
    png = save_swarm_png(model, OUT / "final_swarm.png")
    print(f"\nwrote {png}")


if __name__ == "__main__":
    main()
