# tc_layer(NAME DEPS ...): a static library of every .cpp in the current folder.
function(tc_layer name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(tc_${name} STATIC ${sources})
  target_include_directories(tc_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_link_libraries(tc_${name} PUBLIC ${ARG_DEPS} PRIVATE tc_warnings)
  set_target_properties(tc_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
