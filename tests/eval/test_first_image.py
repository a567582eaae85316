"""`restircl bench first-image` (eval/bench/first_image.py): each run in a process of its own reports every phase,
the warm kernel cache skips the build, and the shipped GGX tables cost nothing where computing them costs seconds."""

from __future__ import annotations

from restircl.eval.bench.first_image import bench_first_image


def test_phases_of_a_glossy_still(device):
    lines: list[str] = []
    out = bench_first_image(32, 18, scenes=("material_balls",), print_fn=lines.append)["material_balls"]
    for run in ("cold", "warm"):
        phases = out[run]
        parts = phases["import"] + phases["scene"] + phases["renderer"] + phases["first frame"]
        assert abs(phases["total"] - parts) < 1e-6 and phases["total"] > 0
        assert phases["  of which the GGX tables"] < 0.1  # read from the package, not computed
    assert out["warm"]["  of which the kernel build"] < out["cold"]["  of which the kernel build"]
    assert len(lines) == 1 + len(out["cold"])
