"""Compare pelvis configurations by the load on the pelvic floor, with abdomen.fmu in fmpy.

Each configuration is pressed by the default sinusoidal force on the diaphragm (0.8 N/mm at
0.5 Hz) for --stop-time seconds; the script prints the peak mean and maximum pelvic-floor
stress of each and plots the mean floor stress over time.

    python examples/python/compare_pelvis.py                      # the five shipped pelvises
    python examples/python/compare_pelvis.py --configurations narrow wide \
        --set floor_E=0.1 --set kinematics=linear --set model_order=modal --plot floor.png

Build the FMUs first: bash fmu/bundle.sh
Every parameter (`--set name=value`) is listed in docs/reference/abdomen-variables.md.
The default kinematics are finite strain, valid at the default press (no warning); the
second line runs the fast path (linear, modal order: 80 Ritz vectors), a different model
form at this press that warns beyond 5 % strain (docs/verification.md gives its error).
"""

import argparse
from pathlib import Path

from fmpy import simulate_fmu

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ["normal", "narrow", "wide", "lordotic", "tilted"]


def parse_settings(pairs):
    """`name=value` strings as start values: numbers where they parse, text otherwise."""
    settings = {}
    for pair in pairs:
        name, _, value = pair.partition("=")
        try:
            settings[name] = float(value)
        except ValueError:
            settings[name] = value
    return settings


def run(fmu, configuration, settings, stop_time, step):
    """One configuration: the floor-stress histories (MPa) every `step` seconds."""
    start_values = {"configuration": configuration, **settings}
    return simulate_fmu(
        fmu, start_values=start_values, stop_time=stop_time, output_interval=step,
        output=["floor_stress_mean", "floor_stress_max"],
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu", default=str(ROOT / "target/fmu/abdomen-fmi2.fmu"))
    parser.add_argument("--configurations", nargs="+", default=SHIPPED,
                        help="shipped names or paths of configuration files")
    parser.add_argument("--stop-time", type=float, default=2.0, help="s")
    parser.add_argument("--step", type=float, default=0.01, help="output interval, s")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--plot", default="pelvis_floor_stress.png")
    args = parser.parse_args()
    settings = parse_settings(args.set)

    results = {}
    for name in args.configurations:
        r = run(args.fmu, name, settings, args.stop_time, args.step)
        results[name] = r
        print(f"{name}: peak floor_stress_mean = {float(r['floor_stress_mean'].max())!r} MPa, "
              f"peak floor_stress_max = {float(r['floor_stress_max'].max())!r} MPa")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for name, r in results.items():
        ax.plot(r["time"], 1e3 * r["floor_stress_mean"], label=name)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mean pelvic-floor stress (kPa)")
    ax.set_title("Abdomen: pelvic-floor stress under the default press")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
    print(f"plot: {args.plot}")


if __name__ == "__main__":
    main()
