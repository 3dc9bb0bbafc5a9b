# Sourced by scripts/setup.sh, test.sh, build_wheel.sh and run_main_job.sh: one compiler cache for the
# builds of one run.
# The cmake build and the Python package's build (build/python-package) compile the cores with the same
# flags; ccache hands the second build the first one's objects instead of compiling the cores again.
# The cache lives in the build folder, so a fresh clone starts empty and no run depends on what an
# earlier run on the machine left behind. Without ccache everything compiles as before.
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_DIR="${CCACHE_DIR:-$BUILD_DIR/ccache}"
  # No CCACHE_BASEDIR: it would rewrite the include paths relative to each build folder, and the two
  # folders (build/, build/python-package/) sit at different depths, so no entry would match.
  export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-5G}"
  # Read by CMake when it configures a build folder for the first time (cmake and scikit-build-core).
  export CMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}"
  export CMAKE_C_COMPILER_LAUNCHER="${CMAKE_C_COMPILER_LAUNCHER:-ccache}"
fi
