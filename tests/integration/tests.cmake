# Integration tests: Debian's real meshlabserver (and meshlab for the GUI test), from the private
# prefix, on our real plugins. Each test is a bash script; see tests/integration/lib.sh.
set(_integration_env
  "MESHLAB_PREFIX=${MESHLAB_PREFIX}"
  "RADIANCE_BUILD_DIR=${PROJECT_BINARY_DIR}"
  "RADIANCE_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
file(GLOB _integration_scripts CONFIGURE_DEPENDS "${CMAKE_CURRENT_LIST_DIR}/test_*.sh")
foreach(script ${_integration_scripts})
  get_filename_component(name ${script} NAME_WE)
  add_test(NAME integration.${name} COMMAND bash ${script})
  set_tests_properties(integration.${name} PROPERTIES ENVIRONMENT "${_integration_env}"
    LABELS integration TIMEOUT 900)
endforeach()

add_test(NAME gui.smoke COMMAND bash "${PROJECT_SOURCE_DIR}/tests/gui/gui_smoke.sh"
  "${PROJECT_BINARY_DIR}/tests/gui-input/sphere.rply" 230 60 40)
set_tests_properties(gui.smoke PROPERTIES ENVIRONMENT "${_integration_env}" LABELS gui TIMEOUT 300
  FIXTURES_REQUIRED gui_input RUN_SERIAL TRUE)
add_test(NAME gui.make_input COMMAND bash "${PROJECT_SOURCE_DIR}/tests/gui/make_gui_input.sh"
  "${PROJECT_BINARY_DIR}/tests/gui-input")
set_tests_properties(gui.make_input PROPERTIES ENVIRONMENT "${_integration_env}" LABELS gui
  FIXTURES_SETUP gui_input TIMEOUT 300)
