# A private MeshLab installation inside the build tree, so tests and the demo never write to system
# directories: copies of /usr/bin/meshlab and meshlabserver (their RUNPATH is
# $ORIGIN/../lib/<arch>/meshlab, and MeshLab only looks for plugins in <bin>/../lib/<arch>/meshlab/plugins),
# a link to libmeshlab-common.so, links to every system plugin and to ours.
set(MESHLAB_PREFIX "${PROJECT_BINARY_DIR}/meshlab-prefix" CACHE PATH "Private MeshLab prefix for tests and demos")
get_property(_plugins GLOBAL PROPERTY RADIANCE_MESHLAB_PLUGINS)
set(_plugin_files "")
foreach(p ${_plugins})
  list(APPEND _plugin_files "$<TARGET_FILE:${p}>")
endforeach()
add_custom_target(meshlab_prefix ALL
  COMMAND "${PROJECT_SOURCE_DIR}/scripts/make_meshlab_prefix.sh" "${MESHLAB_PREFIX}"
          "${MESHLAB_BINARY}" "${MESHLABSERVER_BINARY}" "${MESHLAB_LIB_DIR}" ${_plugin_files}
  DEPENDS ${_plugins}
  COMMENT "Private MeshLab prefix in ${MESHLAB_PREFIX}"
  VERBATIM)
