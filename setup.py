"""`pip install .`: the Python module hemicontact, the same module as the build tree's.

The package is python/hemicontact (pure Python) and its compiled core _hemicontact, which CMake
builds (target _hemicontact, python/CMakeLists.txt): in the build folder $HEMICONTACT_BUILD_DIR,
else build/ (scripts/build.sh's), configured here first if it has never been. An up-to-date build
is only checked, so installing after scripts/build.sh takes seconds. Offline, with Debian's pip,
setuptools and wheel (scripts/install-deps.sh):

    /usr/bin/python3 -m venv --system-site-packages /tmp/v
    /tmp/v/bin/pip install --no-build-isolation --no-index .
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))


def cmake_build_dir():
    return os.path.abspath(os.environ.get("HEMICONTACT_BUILD_DIR") or os.path.join(HERE, "build"))


def version():
    # The one version: CMakeLists.txt's project() (the module's __version__ is the same).
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(hemicontact VERSION ([0-9.]+)", f.read())
    if not m:
        sys.exit("setup.py: no 'project(hemicontact VERSION x.y.z)' in CMakeLists.txt")
    return m.group(1)


def run(cmd):
    print("setup.py: " + " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)


class BuildWithCMake(build_py):
    """The package's Python files, then the compiled core from CMake beside them."""

    def run(self):
        super().run()
        build = cmake_build_dir()
        if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
            # This interpreter's headers and extension suffix: the module must import here.
            run(["cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                 "-DPython3_EXECUTABLE=" + sys.executable])
        jobs = os.environ.get("JOBS") or str(os.cpu_count() or 1)
        run(["cmake", "--build", build, "-j", jobs, "--target", "_hemicontact"])
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        core = os.path.join(build, "python", "hemicontact", "_hemicontact" + suffix)
        if not os.path.isfile(core):
            found = [f for f in os.listdir(os.path.join(build, "python", "hemicontact")) if f.startswith("_hemicontact")]
            sys.exit(f"setup.py: {core} was not built (found: {found or 'nothing'}); the build folder {build} "
                     f"is configured for another Python than {sys.executable} (or without pybind11: "
                     "scripts/install-deps.sh), set HEMICONTACT_BUILD_DIR to a fresh folder")
        target = os.path.join(self.build_lib, "hemicontact")
        os.makedirs(target, exist_ok=True)
        shutil.copy2(core, target)


class BinaryDistribution(Distribution):
    # A compiled module inside: a wheel for this platform and Python, not a pure one.
    def has_ext_modules(self):
        return True


setup(
    name="hemicontact",
    version=version(),
    description="Static frictional contact of an elastic body with a soft-layer foundation",
    packages=["hemicontact"],
    package_dir={"hemicontact": "python/hemicontact"},
    package_data={"hemicontact": ["__init__.pyi", "py.typed"]},
    python_requires=">=3.8",
    install_requires=["numpy"],
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    # setuptools' scratch folders inside the CMake build folder, not beside the sources.
    options={"build": {"build_base": os.path.join(cmake_build_dir(), "setuptools")}},
    zip_safe=False,
)
