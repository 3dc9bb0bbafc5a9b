# Finds the MeshLab 2020.09 plugin SDK as Debian ships it:
#   - the Debian *source* tree of the installed meshlab package (src/common headers + bundled vcglib),
#     obtained by scripts/setup.sh with `apt-get source meshlab` into third_party/meshlab-<version>;
#   - the binary package's libmeshlab-common.so and plugin directory.
#
# Inputs (cache):  MESHLAB_SOURCE_DIR  the extracted source tree (contains src/common/interfaces.h)
#                  MESHLAB_LIB_DIR     directory holding libmeshlab-common.so
# Outputs:         MeshLab_FOUND, imported target MeshLab::common, MESHLAB_PLUGIN_DIR,
#                  MESHLAB_VCGLIB_DIR, MESHLAB_BINARY (meshlab), MESHLABSERVER_BINARY.
# The plugins are declared with add_meshlab_plugin (MeshLabPlugins.cmake).

set(_meshlab_howto
  "Run scripts/setup.sh from the repository root: it installs the 'meshlab' package and the build "
  "dependencies with apt, enables a deb-src entry derived from this machine's apt sources and runs "
  "'apt-get source meshlab' into third_party/. By hand: 'apt-get install meshlab dpkg-dev', add a "
  "deb-src line for your Debian suite, 'apt-get source meshlab', then configure with "
  "-DMESHLAB_SOURCE_DIR=<extracted meshlab-2020.09+dfsg1 directory>.")

if(NOT MESHLAB_SOURCE_DIR)
  file(GLOB _meshlab_candidates LIST_DIRECTORIES true "${PROJECT_SOURCE_DIR}/third_party/meshlab-*")
  foreach(_c ${_meshlab_candidates})
    if(EXISTS "${_c}/src/common/interfaces.h")
      set(MESHLAB_SOURCE_DIR "${_c}")
    endif()
  endforeach()
endif()
set(MESHLAB_SOURCE_DIR "${MESHLAB_SOURCE_DIR}" CACHE PATH "Debian source tree of MeshLab 2020.09 (apt-get source meshlab)")

if(NOT MESHLAB_SOURCE_DIR OR NOT EXISTS "${MESHLAB_SOURCE_DIR}/src/common/interfaces.h")
  message(FATAL_ERROR "MeshLab 2020.09 source headers not found (no src/common/interfaces.h under "
    "MESHLAB_SOURCE_DIR='${MESHLAB_SOURCE_DIR}'). ${_meshlab_howto}")
endif()
set(MESHLAB_VCGLIB_DIR "${MESHLAB_SOURCE_DIR}/vcglib")
if(NOT EXISTS "${MESHLAB_VCGLIB_DIR}/vcg/complex/complex.h")
  message(FATAL_ERROR "The MeshLab source tree '${MESHLAB_SOURCE_DIR}' has no bundled vcglib "
    "(vcglib/vcg/complex/complex.h). ${_meshlab_howto}")
endif()
if(EXISTS "${MESHLAB_SOURCE_DIR}/ML_VERSION")
  file(READ "${MESHLAB_SOURCE_DIR}/ML_VERSION" MESHLAB_SOURCE_VERSION)
  string(STRIP "${MESHLAB_SOURCE_VERSION}" MESHLAB_SOURCE_VERSION)
  if(NOT MESHLAB_SOURCE_VERSION STREQUAL "2020.09")
    message(WARNING "MeshLab sources are version ${MESHLAB_SOURCE_VERSION}; these plugins target the 2020.09 API.")
  endif()
endif()

find_library(MESHLAB_COMMON_LIBRARY NAMES meshlab-common
  HINTS ${MESHLAB_LIB_DIR} /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/meshlab /usr/lib/meshlab
  NO_DEFAULT_PATH)
if(NOT MESHLAB_COMMON_LIBRARY)
  message(FATAL_ERROR "libmeshlab-common.so not found (looked in MESHLAB_LIB_DIR='${MESHLAB_LIB_DIR}' and "
    "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/meshlab). Install Debian's binary package: 'apt-get install meshlab'. "
    "${_meshlab_howto}")
endif()
get_filename_component(MESHLAB_LIB_DIR "${MESHLAB_COMMON_LIBRARY}" DIRECTORY CACHE)
set(MESHLAB_PLUGIN_DIR "${MESHLAB_LIB_DIR}/plugins" CACHE PATH "Where 'cmake --install' puts the plugins (MeshLab's plugin directory)")
find_program(MESHLAB_BINARY meshlab PATHS /usr/bin NO_DEFAULT_PATH)
find_program(MESHLABSERVER_BINARY meshlabserver PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT MESHLAB_BINARY OR NOT MESHLABSERVER_BINARY)
  message(FATAL_ERROR "/usr/bin/meshlab or /usr/bin/meshlabserver missing: 'apt-get install meshlab'.")
endif()

find_package(Qt5 5.11 REQUIRED COMPONENTS Core Gui Widgets OpenGL Xml)
find_package(OpenGL REQUIRED)
find_package(GLEW REQUIRED)

add_library(MeshLab::common SHARED IMPORTED)
set_target_properties(MeshLab::common PROPERTIES IMPORTED_LOCATION "${MESHLAB_COMMON_LIBRARY}"
  IMPORTED_NO_SONAME TRUE)
# System includes: vcglib and MeshLab's headers warn a lot; our own warnings stay visible.
target_include_directories(MeshLab::common SYSTEM INTERFACE
  "${MESHLAB_SOURCE_DIR}/src" "${MESHLAB_VCGLIB_DIR}")
# MESHLAB_SCALAR=float is mandatory: it fixes CMeshO's layout, which must match Debian's build.
target_compile_definitions(MeshLab::common INTERFACE MESHLAB_SCALAR=float QT_NO_DEBUG_OUTPUT)
target_link_libraries(MeshLab::common INTERFACE Qt5::Core Qt5::Gui Qt5::Widgets Qt5::OpenGL Qt5::Xml
  GLEW::GLEW OpenGL::GL Eigen3::Eigen)

set(MeshLab_FOUND TRUE)
message(STATUS "MeshLab SDK: sources ${MESHLAB_SOURCE_DIR}, library ${MESHLAB_COMMON_LIBRARY}")

