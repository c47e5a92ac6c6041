# `cmake --install` puts the module and its stubs where the interpreter finds them: installed into
# a fresh prefix, `import minksum` loads that copy (ctest passes the build tree's path).
import os
import subprocess
import sys

import pytest


def test_install_tree_imports(tmp_path):
    build = os.environ.get("MINKSUM_BUILD_DIR")
    if not build:
        pytest.skip("run by ctest, which names the build tree")
    subprocess.run(["cmake", "--install", build, "--component", "python", "--prefix", str(tmp_path)], check=True,
                   stdout=subprocess.DEVNULL)
    cache = open(os.path.join(build, "CMakeCache.txt")).read()
    subdir = next(line.split("=", 1)[1] for line in cache.splitlines() if line.startswith("MINKSUM_PYTHON_INSTALL_DIR:"))
    site = tmp_path / subdir
    assert (site / "minksum.pyi").is_file()
    out = subprocess.run([sys.executable, "-c", "import minksum; print(minksum.__file__); print(minksum.Shape.sphere(1).radius)"],
                         env={"PYTHONPATH": str(site), "PATH": os.environ.get("PATH", "")}, check=True, capture_output=True,
                         text=True).stdout.split()
    assert out[0].startswith(str(site)) and out[1] == "1.0"
