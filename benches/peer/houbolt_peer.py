"""The peer benchmark: the default abdomen's Houbolt run, stepped in Python with scipy's
``splu`` and with CHOLMOD (scikit-sparse), set beside this project's own times on the same
matrices.

``harness peer-export`` writes the problem (M, C, K on the free dofs in Matrix Market, the
pressing load, the end of its own Houbolt run and its own times); this script runs the same
scheme -- two Newmark average-acceleration steps to start, then Houbolt (models/src/solve/
houbolt.rs) -- with each peer solver, checks that it ends where the project's run ended, and
prints one table. Not a test: it measures. Run through ``benches/peer/run.sh``.
"""

import json
import pathlib
import statistics
import sys
import time

import numpy as np
import scipy.io
import scipy.sparse.linalg as spla
from sksparse.cholmod import cholesky

FACTORIZATIONS = 5


def load(folder):
    """The matrices (CSR for the products, CSC for the factorizations) and problem.json."""
    m, c, k = (scipy.io.mmread(folder / f"{name}.mtx").tocsc() for name in "MCK")
    return m, c, k, json.loads((folder / "problem.json").read_text())


def solvers():
    """Name -> function that factorizes a CSC matrix and returns its solve."""

    def splu(a):
        return spla.splu(a).solve

    def cholmod(mode):
        return lambda a: cholesky(a, mode=mode).solve_A

    return {
        "scipy splu (SuperLU, COLAMD)": splu,
        "CHOLMOD simplicial": cholmod("simplicial"),
        "CHOLMOD supernodal": cholmod("supernodal"),
    }


def run(m, c, k, p, factorize):
    """The Houbolt run of problem.json with one solver: final displacement, per-step times
    of the Houbolt steps, and the factorization time of the Houbolt effective matrix."""
    dt, steps = p["dt"], p["steps"]
    unit = np.asarray(p["unit_load"])

    def force(t):
        return p["force"] + p["amplitude"] * np.sin(2 * np.pi * p["frequency"] * t)

    mr, cr = m.tocsr(), c.tocsr()
    houbolt = (2 / dt**2) * m + (11 / (6 * dt)) * c + k
    factor_times = []
    for _ in range(FACTORIZATIONS):
        t0 = time.perf_counter()
        solve_h = factorize(houbolt.tocsc())
        factor_times.append(time.perf_counter() - t0)
    solve_n = factorize(((4 / dt**2) * m + (2 / dt) * c + k).tocsc())

    n = k.shape[0]
    u, v = np.zeros(n), np.zeros(n)
    a = np.zeros(n)
    if force(0.0) != 0.0:
        a = factorize(m)(force(0.0) * unit)
    history = []
    t = 0.0
    for _ in range(2):  # Newmark average acceleration (the starter)
        t += dt
        rhs = force(t) * unit + mr @ (4 / dt**2 * u + 4 / dt * v + a) + cr @ (2 / dt * u + v)
        u1 = solve_n(rhs)
        a1 = 4 / dt**2 * (u1 - u) - 4 / dt * v - a
        v = v + 0.5 * dt * (a + a1)
        history.insert(0, u)
        u, a = u1, a1
    u1, u2 = history[0], history[1]
    times = []
    for _ in range(steps - 2):
        t0 = time.perf_counter()
        t += dt
        rhs = (
            force(t) * unit
            + mr @ ((5 * u - 4 * u1 + u2) / dt**2)
            + cr @ ((3 * u - 1.5 * u1 + u2 / 3) / dt)
        )
        u, u1, u2 = solve_h(rhs), u, u1
        times.append(time.perf_counter() - t0)
    solve_times = []
    for _ in range(steps):
        t0 = time.perf_counter()
        solve_h(unit)
        solve_times.append(time.perf_counter() - t0)
    return u, times, solve_times, factor_times


def main(folder):
    m, c, k, p = load(folder)
    rust = p["rust"]
    u_ref = np.asarray(p["u_final"])
    rows = [
        (
            "tissuefmu (faer factorization, own sweeps)",
            rust["step"],
            rust["solve"],
            rust["factor"],
            0.0,
        )
    ]
    for name, factorize in solvers().items():
        u, steps, solves, factors = run(m, c, k, p, factorize)
        diff = np.max(np.abs(u - u_ref)) / np.max(np.abs(u_ref))
        rows.append(
            (
                name,
                statistics.median(steps),
                statistics.median(solves),
                statistics.median(factors),
                diff,
            )
        )
    header = (
        f"Default abdomen: {p['n']} equations, {p['nnz']} entries in K, "
        f"{p['nnz_factor']} in the project's Cholesky factor; {p['steps']} steps of "
        f"{p['dt'] * 1e3:g} ms. Medians.\n\n"
        "| solver | Houbolt step (µs) | solve (µs) | factorization (ms) | step time / "
        "tissuefmu's | end state vs tissuefmu (max rel.) |\n"
        "|---|---:|---:|---:|---:|---:|\n"
    )
    body = "".join(
        f"| {name} | {step * 1e6:.0f} | {solve * 1e6:.0f} | {factor * 1e3:.2f} | "
        f"{step / rust['step']:.2f} | {diff:.1e} |\n"
        for name, step, solve, factor, diff in rows
    )
    table = header + body
    print(table)
    (folder / "peer.md").write_text(table)
    worst = max(row[4] for row in rows)
    if worst > 1e-8:
        sys.exit(f"a peer solver ended {worst:.1e} away from tissuefmu's run: not the same problem")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/peer"))
