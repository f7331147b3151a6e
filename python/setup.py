"""Build of the extension module grip._grip for pip (pyproject.toml): pybind11's setuptools
helpers from Debian's python3-pybind11, grip's headers from this repository, Eigen from
GRIP_EIGEN_INCLUDE (default /usr/include/eigen3, Debian's libeigen3-dev). The version is
read from include/grip/core/version.hpp, the one place it is written."""

import os
import re

from pybind11.setup_helpers import ParallelCompile, Pybind11Extension, build_ext
from setuptools import setup

# The translation units compile in parallel: GRIP_BUILD_JOBS of them (default: every core).
ParallelCompile("GRIP_BUILD_JOBS").install()

HERE = os.path.dirname(os.path.abspath(__file__))
INCLUDE = os.path.join(os.path.dirname(HERE), "include")


def version():
    text = open(os.path.join(INCLUDE, "grip", "core", "version.hpp")).read()
    parts = [re.search(r"#define GRIP_VERSION_%s (\d+)" % k, text).group(1) for k in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


setup(
    version=version(),
    packages=["grip"],
    ext_modules=[
        Pybind11Extension(
            "grip._grip",
            ["src/module.cpp", "src/analysis.cpp", "src/monitor.cpp", "src/hand.cpp", "src/pipeline.cpp", "src/mesh.cpp"],
            include_dirs=[INCLUDE, os.environ.get("GRIP_EIGEN_INCLUDE", "/usr/include/eigen3")],
            define_macros=[("EIGEN_STACK_ALLOCATION_LIMIT", "1048576")],
            cxx_std=17,
        )
    ],
    cmdclass={"build_ext": build_ext},
)
