"""Builds the `symphong` Python module with the project's CMake build for `pip install .` (pyproject.toml).

The extension is CMake's target symphong_python, configured like the release preset without tests,
benchmarks or fuzzers, in build/pip (or in $SYMPHONG_CMAKE_BUILD_DIR, an existing build tree, which
is then built incrementally), and copied into the wheel.
"""
import os
import pathlib
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("SYMPHONG_CMAKE_BUILD_DIR", ROOT / "build" / "pip"))
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                            "-DSYMPHONG_WERROR=ON", "-DSYMPHONG_BUILD_TESTS=OFF", "-DSYMPHONG_BUILD_BENCH=OFF",
                            f"-DPython_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "symphong_python"], check=True)
        built = sorted((build / "python").glob("symphong*.so"))
        if not built:
            raise RuntimeError(f"the CMake build in {build} made no module (python/symphong*.so)")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built[-1]), str(target))


setup(ext_modules=[CMakeExtension("symphong")], cmdclass={"build_ext": CMakeBuild}, packages=[], py_modules=[], zip_safe=False)
