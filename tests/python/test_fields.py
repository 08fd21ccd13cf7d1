"""The VTU files of `harness fields`, read by an independent reader (meshio): the meshes and
fields ParaView will see match what the harness reports."""

import re
import subprocess

import meshio
import numpy as np

from paths import HARNESS


def test_fields_read_back_with_meshio(tmp_path):
    out = tmp_path / "fields"
    subprocess.run([str(HARNESS), "fields", "--out", str(out)], check=True, capture_output=True)
    report = (out / "report.md").read_text()

    a = meshio.read(out / "abdomen.vtu")
    cells = {c.type: len(c.data) for c in a.cells}
    # The default mesh (verification report): 6-node triangles, 3-node membrane lines; the
    # counts of the mesher on the graded default (issue 26: 750 triangles targeted, graded
    # towards the ends of the boundary parts).
    assert cells == {"triangle6": 1013, "line3": 116}
    tri6 = next(c.data for c in a.cells if c.type == "triangle6")
    corners = tri6[:, :3].astype(np.int64)  # meshio hands the connectivity back as floats
    assert len(np.unique(corners)) == 601
    # Euler's formula for a triangulated disk: V = 1 + (T + B) / 2, B the boundary edges.
    edges = np.sort(np.concatenate([corners[:, [0, 1]], corners[:, [1, 2]], corners[:, [2, 0]]]), axis=1)
    _, uses = np.unique(edges, axis=0, return_counts=True)
    assert set(uses) == {1, 2}
    assert len(np.unique(corners)) == 1 + (len(tri6) + (uses == 1).sum()) // 2
    assert len(np.unique(tri6)) == len(a.points)  # every point is a triangle's node
    assert np.all(a.points[:, 2] == 0.0)
    tissue = np.concatenate(a.cell_data["tissue"])
    assert set(np.unique(tissue)) == {0.0, 1.0, 2.0, 3.0}
    largest = float(re.search(r"largest ([0-9.]+) mm", report).group(1))
    u = a.point_data["displacement"]
    # The report draws its arrows at the corner nodes and prints the largest to 0.1 mm.
    assert abs(np.linalg.norm(u[np.unique(corners)], axis=1).max() - largest) <= 0.05

    c = meshio.read(out / "cutblock.vtu")
    # 6 × 16 × 14 cubes of 6 tetrahedra (split along x).
    assert [(x.type, len(x.data)) for x in c.cells] == [("tetra", 8064)]
    d = c.point_data["displacement"]
    assert d.shape == (len(c.points), 3)
    # The pulled face y = 80 mm moved 10 mm in y; the clamped face y = 0 did not move.
    far, near = c.points[:, 1] > 79.99, c.points[:, 1] < 1e-9
    assert np.allclose(d[far, 1], 10.0) and np.allclose(d[near], 0.0)
    assert np.all(np.concatenate(c.cell_data["von_mises"]) >= 0.0)
