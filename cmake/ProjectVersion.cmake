# The project's one version, read from pyproject.toml's [project] table into RADIANCE_VERSION, so that
# the CMake project and the Python package cannot disagree (tests/python/test_package_metadata.py
# runs this file with `cmake -P` and compares). Included by CMakeLists.txt before project().
# cmake -DRADIANCE_PRINT_VERSION=ON -P cmake/ProjectVersion.cmake prints it.
get_filename_component(_radiance_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
file(STRINGS "${_radiance_root}/pyproject.toml" _radiance_version_line REGEX "^version = \"[0-9.]+\"$")
list(LENGTH _radiance_version_line _radiance_version_lines)
if(NOT _radiance_version_lines EQUAL 1)
  message(FATAL_ERROR "pyproject.toml: expected exactly one line 'version = \"X.Y.Z\"' (the project's one "
                      "version, in [project]), found ${_radiance_version_lines}")
endif()
string(REGEX REPLACE "^version = \"([0-9.]+)\"$" "\\1" RADIANCE_VERSION "${_radiance_version_line}")
if(RADIANCE_PRINT_VERSION)
  message(STATUS "${RADIANCE_VERSION}")
endif()
