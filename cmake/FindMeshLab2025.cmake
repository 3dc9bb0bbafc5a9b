# Finds the MeshLab 2025.07 plugin SDK that pymeshlab runs:
#   - the headers: MeshLab's 2025.07 source tree (src/common + src/vcglib), which scripts/setup.sh
#     takes from the orig tarball of Debian's source package 'meshlab 2025.07~dfsg' into
#     third_party/meshlab-2025.07/ (source only; no binary package of that suite is installed);
#   - the library: libmeshlab-common.so inside the installed pymeshlab wheel (the plugin interfaces'
#     vtables live there, and pymeshlab only loads plugins linked against its own copy).
#
# Inputs (cache):  MESHLAB2025_SOURCE_DIR   the tree holding src/common/plugins/interfaces/filter_plugin.h
#                  PYMESHLAB_DIR            the installed pymeshlab package (found with RADIANCE_PYTHON)
#                  RADIANCE_PYTHON          the Python whose pymeshlab the plugins are for
# Outputs:         MeshLab2025_FOUND, imported target MeshLab2025::common, PYMESHLAB_DIR.

set(_ml2025_howto
  "Run scripts/setup.sh from the repository root (it fetches the headers and installs pymeshlab into "
  "build/python-venv), or: 'pip install pymeshlab==2025.7.post1' and unpack MeshLab 2025.07's sources "
  "(Debian's source package meshlab 2025.07~dfsg, orig tarball) into third_party/meshlab-2025.07.")

if(NOT MESHLAB2025_SOURCE_DIR)
  file(GLOB _ml2025_candidates LIST_DIRECTORIES true "${PROJECT_SOURCE_DIR}/third_party/meshlab-2025.07*")
  foreach(_c ${_ml2025_candidates})
    if(EXISTS "${_c}/src/common/plugins/interfaces/filter_plugin.h")
      set(MESHLAB2025_SOURCE_DIR "${_c}")
    endif()
  endforeach()
endif()
set(MESHLAB2025_SOURCE_DIR "${MESHLAB2025_SOURCE_DIR}" CACHE PATH "MeshLab 2025.07 source tree (headers)")
if(NOT EXISTS "${MESHLAB2025_SOURCE_DIR}/src/common/plugins/interfaces/filter_plugin.h")
  message(FATAL_ERROR "MeshLab 2025.07 headers not found (MESHLAB2025_SOURCE_DIR='${MESHLAB2025_SOURCE_DIR}'). ${_ml2025_howto}")
endif()
file(READ "${MESHLAB2025_SOURCE_DIR}/ML_VERSION" MESHLAB2025_VERSION)
string(STRIP "${MESHLAB2025_VERSION}" MESHLAB2025_VERSION)

if(NOT PYMESHLAB_DIR)
  if(NOT RADIANCE_PYTHON)
    find_package(Python3 COMPONENTS Interpreter REQUIRED)
    set(RADIANCE_PYTHON "${Python3_EXECUTABLE}")
  endif()
  execute_process(COMMAND "${RADIANCE_PYTHON}" -c
      "import importlib.util, os; s = importlib.util.find_spec('pymeshlab'); print(os.path.dirname(s.origin))"
    OUTPUT_VARIABLE _pml_dir OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _pml_rc ERROR_QUIET)
  if(_pml_rc EQUAL 0 AND EXISTS "${_pml_dir}/lib/libmeshlab-common.so")
    set(PYMESHLAB_DIR "${_pml_dir}")
  endif()
endif()
set(PYMESHLAB_DIR "${PYMESHLAB_DIR}" CACHE PATH "The installed pymeshlab package (holds lib/libmeshlab-common.so)")
if(NOT EXISTS "${PYMESHLAB_DIR}/lib/libmeshlab-common.so")
  message(FATAL_ERROR "pymeshlab's libmeshlab-common.so not found (PYMESHLAB_DIR='${PYMESHLAB_DIR}', "
    "Python '${RADIANCE_PYTHON}'). ${_ml2025_howto}")
endif()

find_package(Qt5 5.11 REQUIRED COMPONENTS Core Gui Widgets OpenGL Xml)

add_library(MeshLab2025::common SHARED IMPORTED)
set_target_properties(MeshLab2025::common PROPERTIES IMPORTED_LOCATION "${PYMESHLAB_DIR}/lib/libmeshlab-common.so"
  IMPORTED_NO_SONAME TRUE)
target_include_directories(MeshLab2025::common SYSTEM INTERFACE
  "${MESHLAB2025_SOURCE_DIR}/src" "${MESHLAB2025_SOURCE_DIR}/src/vcglib")
# pymeshlab's build is double precision ("2025.07d"); its plugin loader checks both.
target_compile_definitions(MeshLab2025::common INTERFACE MESHLAB_VERSION=${MESHLAB2025_VERSION}
  MESHLAB_SCALAR=double QT_NO_DEBUG_OUTPUT)
# Debian's Qt 5.15 headers and libraries at link time; at run time the process already holds the
# wheel's Qt 5.15 (same sonames, binary compatible within 5.15). No OpenGL library: no 2025 plugin
# calls GL (pymeshlab has no view), and linking GLVND's libOpenGL.so.0 would record it as needed
# (it provides symbols libmeshlab-common uses), a library neither pymeshlab nor the manylinux policy
# has (docs/wheel.md).
target_link_libraries(MeshLab2025::common INTERFACE Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml
  Eigen3::Eigen)
find_path(GLEW_INCLUDE_DIR GL/glew.h)
target_include_directories(MeshLab2025::common SYSTEM INTERFACE "${GLEW_INCLUDE_DIR}")

set(MeshLab2025_FOUND TRUE)
message(STATUS "MeshLab 2025 SDK: sources ${MESHLAB2025_SOURCE_DIR} (${MESHLAB2025_VERSION}), pymeshlab ${PYMESHLAB_DIR}")
