# add_meshlab_plugin(<name> SOURCES ... [LIBRARIES ...] [HOSTS 2020 2025]): one plugin source built
# for each MeshLab host that is enabled and listed (default: both):
#   - MeshLab 2020.09 (Debian: meshlab, meshlabserver): target <name>, file lib<name>.so in
#     <build>/<folder>/, linked to Debian's libmeshlab-common.so, float CMeshO;
#   - MeshLab 2025.07 (pymeshlab): target <name>_2025, file lib<name>.so in <build>/pymeshlab_plugins/,
#     linked to pymeshlab's libmeshlab-common.so, double CMeshO.
# Each host's target sees its own compatibility folder (plugins_shared/host_2020 or host_2025) and
# links the shared toolkit built for it (radiance_meshlab_glue / radiance_meshlab_glue_2025).
# Linked with --no-undefined so that a missing symbol fails the build rather than MeshLab's loader.

set_property(GLOBAL PROPERTY RADIANCE_MESHLAB_PLUGINS "")
set_property(GLOBAL PROPERTY RADIANCE_PYMESHLAB_PLUGINS "")
set(RADIANCE_PYMESHLAB_PLUGIN_DIR "${PROJECT_BINARY_DIR}/pymeshlab_plugins")

function(add_meshlab_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;HOSTS" ${ARGN})
  if(NOT ARG_HOSTS)
    set(ARG_HOSTS 2020 2025)
  endif()
  if(RADIANCE_PLUGINS_2020 AND "2020" IN_LIST ARG_HOSTS)
    add_library(${name} MODULE ${ARG_SOURCES})
    set_target_properties(${name} PROPERTIES AUTOMOC ON PREFIX "lib")
    target_link_libraries(${name} PRIVATE radiance_meshlab_glue ${ARG_LIBRARIES})
    target_link_options(${name} PRIVATE -Wl,--no-undefined)
    target_compile_options(${name} PRIVATE -Wall -Wextra -Wno-unused-parameter)
    install(TARGETS ${name} LIBRARY DESTINATION "${MESHLAB_PLUGIN_DIR}" COMPONENT meshlab2020)
    set_property(GLOBAL APPEND PROPERTY RADIANCE_MESHLAB_PLUGINS ${name})
  endif()
  if(RADIANCE_PLUGINS_2025 AND "2025" IN_LIST ARG_HOSTS)
    add_library(${name}_2025 MODULE ${ARG_SOURCES})
    set_target_properties(${name}_2025 PROPERTIES AUTOMOC ON PREFIX "lib" OUTPUT_NAME ${name}
      LIBRARY_OUTPUT_DIRECTORY "${RADIANCE_PYMESHLAB_PLUGIN_DIR}"
      # Loaded inside pymeshlab, whose Qt and libmeshlab-common are already in the process (found by
      # soname). Installed, the plugins sit in site-packages/pymeshlab_radiance/plugins: the RUNPATH
      # names pymeshlab's lib folder beside it, so libgomp and the rest of pymeshlab's own libraries
      # resolve to its copies even before pymeshlab loaded them (and for ldd). scripts/build_wheel.sh
      # puts it back after auditwheel, which keeps only paths inside the wheel.
      SKIP_BUILD_RPATH TRUE INSTALL_RPATH "$ORIGIN/../../pymeshlab/lib")
    target_link_libraries(${name}_2025 PRIVATE radiance_meshlab_glue_2025 ${ARG_LIBRARIES})
    # --as-needed: only the libraries whose symbols the plugin uses are recorded (the wheel then
    # carries no library a plugin does not need).
    target_link_options(${name}_2025 PRIVATE -Wl,--no-undefined -Wl,--as-needed)
    target_compile_options(${name}_2025 PRIVATE -Wall -Wextra -Wno-unused-parameter)
    if(RADIANCE_PYTHON_PACKAGE)
      install(TARGETS ${name}_2025 LIBRARY DESTINATION pymeshlab_radiance/plugins COMPONENT python)
    endif()
    set_property(GLOBAL APPEND PROPERTY RADIANCE_PYMESHLAB_PLUGINS ${name}_2025)
  endif()
endfunction()
