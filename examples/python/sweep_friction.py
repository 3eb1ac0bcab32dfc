"""Example 3.2 over a grid of friction coefficients and step sizes, on Dask.

Each task solves one (mu, step) pair of the paper's Example 3.2 (three cantilevers pressed by a
pin) and returns whether the run completed, its peak pin force and its Newton iterations. By
default the tasks run on a local cluster; `--scheduler tcp://host:8786` runs the same script on
an existing Dask cluster. The results go to a CSV file and a plot of peak pin force against mu.

    python examples/python/sweep_friction.py --workers 2 --mu 0 0.1 0.2 0.3 --step 0.01 0.02
"""

import argparse
import csv
import os

import tsm_contact as tc


def example_3_2(mu, step):
    """Example 3.2 with Coulomb friction `mu` at every contact, the pin driven `step` m a step
    over the same 0.8 m."""
    d = tc.Scene.builtin("example_3_2").to_dict()
    for c in d["contacts"]:
        c["mu"] = mu
    d["prescribed"][0]["per_step"] = -step
    d["control"]["steps"] = int(round(0.8 / step))
    d["name"] = f"Example 3.2, mu {mu}, step {step} m"
    return tc.Scene.from_dict(d)


def run(mu, step):
    """One point of the grid: completion, the peak pin force (N) and the Newton iterations."""
    scene = example_3_2(mu, step)
    h = tc.solve(scene)
    pin = scene.node_ids.index(34)
    r = h.reactions
    on_pin = (r["node"] == 34) & (r["dof"] == "v")
    peak = float(abs(r["value"][on_pin]).max()) if on_pin.any() else 0.0
    return {
        "mu": mu,
        "step": step,
        "completed": h.completed,
        "increments": len(h),
        "peak_pin_force": peak,
        "iterations": int(h.iterations.sum()),
        "final_pin_y": float(h.positions[-1, pin, 1]) if len(h) else float("nan"),
        "error": h.error or "",
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    ap.add_argument("--step", type=float, nargs="+", default=[0.01, 0.02])
    ap.add_argument("--scheduler", help="address of an existing Dask scheduler")
    ap.add_argument("--workers", type=int, default=2, help="workers of the local cluster")
    ap.add_argument("--out", default="sweep_friction", help="output folder")
    args = ap.parse_args()

    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
    grid = [(mu, step) for mu in args.mu for step in args.step]
    futures = client.map(run, [g[0] for g in grid], [g[1] for g in grid], pure=False)
    rows = client.gather(futures)
    client.close()

    os.makedirs(args.out, exist_ok=True)
    table = os.path.join(args.out, "sweep_friction.csv")
    with open(table, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {table}")
    for r in rows:
        state = "completed" if r["completed"] else "stopped"
        print(f"mu {r['mu']:.2f}  step {r['step']:.3f}  {state:9}  peak pin force {r['peak_pin_force']:.4g} N")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for step in args.step:
        pts = sorted((r["mu"], r["peak_pin_force"], r["completed"]) for r in rows if r["step"] == step)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=f"step {step} m")
        ax.plot([p[0] for p in pts if not p[2]], [p[1] for p in pts if not p[2]], "rx")
    ax.set_xlabel("friction coefficient mu")
    ax.set_ylabel("peak pin force (N)")
    ax.set_title("Example 3.2: peak pin force (x: run stopped)")
    ax.legend()
    fig.tight_layout()
    plot = os.path.join(args.out, "sweep_friction.png")
    fig.savefig(plot, dpi=120)
    print(f"wrote {plot}")


if __name__ == "__main__":
    main()
