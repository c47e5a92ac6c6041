# The Python examples run as a user runs them, and write their plots.
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


@pytest.mark.parametrize("script, expect", [("distance_sweep.py", "the distance at 2000 poses"), ("draw_sum.py", "A (+) B with")])
def test_example_writes_its_plot(tmp_path, script, expect):
    out = tmp_path / "plot.png"
    run = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), "--out", str(out)], capture_output=True, text=True,
                         env=dict(os.environ), timeout=300)
    assert run.returncode == 0, run.stderr
    assert expect in run.stdout
    assert out.stat().st_size > 10000  # a drawing, not an empty canvas


def test_sweep_refuses_one_mesh(tmp_path):
    run = subprocess.run([sys.executable, os.path.join(EXAMPLES, "distance_sweep.py"), "only_one.ply"], capture_output=True, text=True)
    assert run.returncode == 2 and "give two meshes" in run.stderr
