"""`pip install .` of the isoatlas Python module, offline with Debian's packages: setuptools drives
the CMake build (the release preset, as scripts/run-tests builds it) and installs what it made.

    scripts/setup                                    # Debian's compilers, pybind11, numpy, pip
    python3 -m venv --system-site-packages ENV       # or pip's --break-system-packages
    ENV/bin/pip install --no-build-isolation .       # offline: setuptools and numpy from Debian
"""
import os
import shutil
import subprocess

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


class CMakeBuild(build_ext):
    """Builds the _isoatlas target with CMake and copies the package (the extension beside __init__.py)."""

    def build_extension(self, ext):
        build = os.path.join(ROOT, "build", "release")
        subprocess.run(["cmake", "--preset", "release"], cwd=ROOT, check=True)  # for Debian's python3 (a venv of it shares its ABI)
        subprocess.run(["cmake", "--build", build, "--target", "_isoatlas"], cwd=ROOT, check=True)
        target = os.path.dirname(os.path.abspath(self.get_ext_fullpath(ext.name)))
        os.makedirs(target, exist_ok=True)
        made = os.path.join(build, "python", "isoatlas")
        for name in os.listdir(made):  # the extension and __init__.py; the subpackages come as packages
            if os.path.isfile(os.path.join(made, name)):
                shutil.copy2(os.path.join(made, name), os.path.join(target, name))


setup(
    name="isoatlas",
    version="0.1.0",
    description="Segment a scan, edit it, extract and model its surface at any level of detail",
    packages=["isoatlas", "isoatlas.cohort"],
    package_dir={"isoatlas": "python/isoatlas", "isoatlas.cohort": "python/isoatlas/cohort"},
    entry_points={"console_scripts": ["isoatlas-cohort = isoatlas.cohort.__main__:main"]},
    ext_modules=[Extension("isoatlas._isoatlas", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    python_requires=">=3.11",
    zip_safe=False,
)
