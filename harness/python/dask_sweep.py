"""Runs a harness sweep on a Dask cluster, with fmpy workers importing the packaged FMU.

The case plan comes from the Rust harness, so both runners execute the same cases with the
same settings: `harness sweep EXPERIMENT --plan-only --out DIR` writes DIR/plan.json (the
scene, stop time, communication step, recorded outputs, input tables and every case's
resolved settings). Then

    python harness/python/dask_sweep.py DIR/plan.json --fmu target/fmu/abdomen-fmi2.fmu \
        --scheduler tcp://scheduler:8786 --out DIR/dask

runs every case as one Dask task (or on a local cluster: `--local-workers 2`). Like the Rust
sweep it writes each finished case atomically to OUT/cases/case_NNNN.csv, a failed one to
case_NNNN.error with the FMU's message, skips finished cases when re-run, and ends with
OUT/summary.csv. The workers need fmpy and numpy; the FMU file must be readable by them at
the same path (a shared file system), or pass a path valid on the workers.

Inputs follow the harness's rule (harness/src/sweep/simulate.rs): each input table is
sampled at the start of every communication step and held over the step. The runner hands
fmpy one input row per communication point, holding those sampled values, so fmpy sets
exactly the values the Rust loop sets, wherever the table's own breakpoints lie
(tests/python/test_dask_sweep.py puts one inside a step).
"""

import argparse
import csv
import io
import json
import os
import sys
from pathlib import Path

import numpy as np

_UNZIPPED = {}


def _unzipped(fmu):
    """Extracts the FMU once per worker process."""
    from fmpy import extract

    if fmu not in _UNZIPPED:
        _UNZIPPED[fmu] = extract(fmu)
    return _UNZIPPED[fmu]


def input_at(table, t):
    """The piecewise-linear input at time t, held beyond its ends (the harness's formula,
    `InputTable::at`); the runner evaluates it at communication points only."""
    times, values = table["time"], table["value"]
    k = sum(1 for s in times if s <= t)
    if k == 0:
        return values[0]
    if k == len(times):
        return values[-1]
    t0, t1 = times[k - 1], times[k]
    w = (t - t0) / (t1 - t0)
    return values[k - 1] + w * (values[k] - values[k - 1])


def run_case(fmu, plan, case):
    """Simulates one case with fmpy; returns (id, rows or None, error or None)."""
    from fmpy import read_model_description, simulate_fmu

    messages = []

    def logger(_env, _name, status, _category, message):
        if status >= 3:  # fmi2Error, fmi2Fatal
            messages.append(message.decode() if isinstance(message, bytes) else str(message))

    start, step = plan["start_time"], plan["step"]
    steps = round((plan["stop_time"] - start) / step)
    inputs = plan["inputs"]
    table = None
    if inputs:
        # One row per communication point t_k = start + k step (the harness's and fmpy's
        # formula), so fmpy applies exactly the harness's values.
        names = list(inputs)
        times = [start + k * step for k in range(steps + 1)]
        rows = [tuple([t] + [input_at(inputs[n], t) for n in names]) for t in times]
        table = np.array(rows, dtype=[("time", float)] + [(n, float) for n in names])
    unzipped = _unzipped(fmu)
    try:
        result = simulate_fmu(
            unzipped,
            model_description=read_model_description(unzipped),
            fmi_type="CoSimulation",
            start_values=case["settings"],
            input=table,
            output=plan["record"],
            start_time=start,
            stop_time=plan["stop_time"],
            output_interval=plan["step"],
            logger=logger,
        )
    except Exception as e:  # the FMU refused the case: report its own words
        return case["id"], None, "; ".join(messages) or str(e)
    rows = [[float(r["time"])] + [float(r[n]) for n in plan["record"]] for r in result]
    return case["id"], rows, None


def write_atomic(path, text):
    tmp = path.with_name("." + path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def case_csv(record, rows):
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["time"] + record)
    for r in rows:
        w.writerow([repr(x) for x in r])
    return out.getvalue()


def summary(plan, cases_dir):
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    record = plan["record"]
    w.writerow(["case", "status"] + [f"{r}_peak" for r in record] + [f"{r}_final" for r in record] + ["error"])
    for case in plan["cases"]:
        path = cases_dir / f"case_{case['id']:04d}.csv"
        if path.is_file():
            data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
            peak = [repr(float(x)) for x in data[:, 1:].max(axis=0)]
            final = [repr(float(x)) for x in data[-1, 1:]]
            w.writerow([case["id"], "finished"] + peak + final + [""])
        else:
            error = path.with_suffix(".error")
            message = error.read_text() if error.is_file() else "did not run"
            w.writerow([case["id"], "failed"] + [""] * (2 * len(record)) + [message])
    return out.getvalue()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("plan", type=Path, help="plan.json written by `harness sweep --plan-only`")
    p.add_argument("--fmu", required=True, help="the FMU (FMI 2 co-simulation) of the plan's scene")
    p.add_argument("--out", type=Path, help="output folder [default: next to the plan, dask/]")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a running Dask scheduler")
    where.add_argument("--local-workers", type=int, default=2, help="local cluster size [2]")
    args = p.parse_args(argv)

    from dask.distributed import Client, LocalCluster, as_completed

    plan = json.loads(args.plan.read_text())
    fmu = str(Path(args.fmu).resolve())
    out = args.out or args.plan.parent / "dask"
    cases_dir = out / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    pending = [c for c in plan["cases"] if not (cases_dir / f"case_{c['id']:04d}.csv").is_file()]
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.local_workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        futures = [client.submit(run_case, fmu, plan, c, pure=False) for c in pending]
        for done, future in enumerate(as_completed(futures), start=1):
            case_id, rows, error = future.result()
            base = cases_dir / f"case_{case_id:04d}"
            if rows is None:
                write_atomic(base.with_suffix(".error"), error)
                print(f"case {case_id} failed: {error}", file=sys.stderr)
            else:
                write_atomic(base.with_suffix(".csv"), case_csv(plan["record"], rows))
                base.with_suffix(".error").unlink(missing_ok=True)
            print(f"{done}/{len(pending)} cases", file=sys.stderr)
    finally:
        client.close()
    write_atomic(out / "summary.csv", summary(plan, cases_dir))
    print(f"summary written to {out / 'summary.csv'}")


if __name__ == "__main__":
    main()
