"""The Python examples run and write their images (small sizes where they take one)."""

import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python")
PNG = b"\x89PNG\r\n\x1a\n"

pytest.importorskip("matplotlib")


def run(script, *args, cwd):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args], cwd=cwd, env=env, check=True,
                          capture_output=True, text=True, timeout=600).stdout


@pytest.mark.parametrize("script,args", [("table1_forces.py", ()), ("cones_3d.py", ()), ("closure_map.py", ("31",)),
                                         ("haptic_forces.py", ())])
def test_plot_examples_write_their_images(script, args, tmp_path):
    out = str(tmp_path / "figure.png")
    text = run(script, out, *args, cwd=tmp_path)
    assert f"wrote {out}" in text
    with open(out, "rb") as f:
        head = f.read(8)
    assert head == PNG and os.path.getsize(out) > 10_000


def test_the_dask_example_evaluates_and_checks_its_batch(tmp_path):
    pytest.importorskip("distributed")
    text = run("dask_batch.py", "20000", cwd=tmp_path)
    assert "20000 grasps of 5 contacts" in text and "equal the serial evaluation bit for bit" in text
