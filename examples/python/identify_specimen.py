"""Identify E (and ν) of a silicone specimen from your own measurements, with the harness,
and read the result as JSON.

    python examples/python/identify_specimen.py --data my_data --set B
    python examples/python/identify_specimen.py --set A            # a shipped set
    python examples/python/identify_specimen.py --set A --nu 0.43 --material linear \
        --element tet4                                  # E alone at a given ν, the fast path

`my_data/` holds `specimen_B.toml`, `force_displacement_B.csv` and, if scanned,
`profile_B_x<X>.csv` per scan line (formats: docs/reference/data-formats.md). The fit runs
`harness identify` (neo-Hookean tet10 by default, the model the shipped sets match; about a
minute); its `identify.json` carries the values, 95 % intervals, residuals against the
stated noise and the verdict. Build the harness first: cargo build --release -p harness
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def identify(harness, data, set_name, material, element, nu, out):
    """Runs `harness identify` and returns its JSON results."""
    args = [harness, "identify", "--set", set_name, "--material", material,
            "--element", element, "--out", str(out)]
    if data:
        args += ["--data", str(data)]
    if nu is not None:
        args += ["--nu", repr(nu)]
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"harness identify failed: {done.stderr.strip()}")
    return json.loads((Path(out) / "identify.json").read_text())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--harness", default=str(ROOT / "target/release/harness"))
    parser.add_argument("--data", help="folder with the set's files [default: shipped sets]")
    parser.add_argument("--set", default="A", dest="set_name")
    parser.add_argument("--material", default="neo-hookean")
    parser.add_argument("--element", default="tet10")
    parser.add_argument("--nu", type=float, help="fix ν (needed without profiles)")
    parser.add_argument("--out", default="identify_result")
    args = parser.parse_args()

    r = identify(args.harness, args.data, args.set_name, args.material, args.element,
                 args.nu, args.out)
    e, nu = r["E_MPa"], r["nu"]
    if e["interval95"]:
        lo, hi = e["interval95"]
        print(f"E = {e['value']!r} MPa (95 %: {lo:.5f} … {hi:.5f})")
    else:
        print(f"E = {e['value']!r} MPa (no interval: ν is at its bound)")
    if nu["given"]:
        print(f"nu = {nu['value']!r} (given)")
    elif nu["at_bound"]:
        print(f"nu = {nu['value']!r} (at the end of the search interval "
              f"{nu['search_interval']}: not a material value)")
    else:
        lo, hi = nu["interval95"]
        print(f"nu = {nu['value']!r} (95 %: {lo:.4f} … {hi:.4f}), "
              f"correlation with E {r['correlation']}")
    f = r["forces"]
    print(f"force RMS residual = {f['rms_N']!r} N ({f['rms_over_noise']:.2f} x noise)")
    if r["profiles"]["lines"]:
        p = r["profiles"]
        print(f"profile RMS residual = {p['rms_mm']:.4f} mm ({p['rms_over_noise']:.2f} x noise)")
    print(f"verdict: {r['verdict']}")
    for w in r["warnings"]:
        print(f"warning: {w}")


if __name__ == "__main__":
    main()
