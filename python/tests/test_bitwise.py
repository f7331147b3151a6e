"""Python against the C++ library on the same inputs, bit for bit: the reference instances of
the constrained solver solved by solve_range_space, solve_constrained and force_closure in a
C++ program (reference_results.cpp, built by CMake; its path in GRIP_PYTHON_REFERENCE) and
from Python."""

import os
import subprocess

import numpy as np
import pytest

import grip
from references import ROOT, constrained_reference

MODELS = {"H": grip.Model.HardFinger, "S": grip.Model.SoftFinger, "F": grip.Model.FrictionlessPoint}


def parse(line):
    words = line.split()
    out, k = {}, 0
    while k < len(words):
        tag, status = words[k], int(words[k + 1])
        k += 2
        values = []
        while k < len(words) and words[k] not in ("rs", "cs", "cert", "fc"):
            values.append(float.fromhex(words[k]))
            k += 1
        out[tag] = (status, np.array(values))
    return out


def test_python_equals_cpp_bit_for_bit():
    exe = os.environ.get("GRIP_PYTHON_REFERENCE")
    if not exe:
        pytest.skip("GRIP_PYTHON_REFERENCE (the C++ reference_results program) not given")
    path = os.path.join(ROOT, "tests", "solve", "constrained_reference.txt")
    lines = subprocess.run([exe, path], check=True, capture_output=True, text=True, timeout=300).stdout.splitlines()
    refs = constrained_reference()
    assert len(lines) == len(refs) > 300
    for ref, line in zip(refs, lines):
        cpp = parse(line)
        c = ref["contacts"]
        g = grip.Grasp(c[:, 0:3], c[:, 3:6], c[:, 6], torsional_friction=c[:, 7], squeeze=c[:, 8], weights=c[:, 9],
                       max_normal_force=c[:, 10], model=MODELS[ref["model"]])
        rs = grip.solve_range_space(g, ref["w"])
        cs = grip.solve_constrained(g, ref["w"])
        fc = grip.force_closure(g)
        assert (int(rs.status), int(cs.status), int(fc.status)) == (cpp["rs"][0], cpp["cs"][0], cpp["fc"][0])
        assert np.array_equal(rs.forces.ravel(), cpp["rs"][1])
        assert np.array_equal(cs.forces.ravel(), cpp["cs"][1])
        assert np.array_equal(cs.certificate, cpp["cert"][1])
        assert fc.margin == cpp["fc"][1][0]
