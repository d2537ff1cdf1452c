# find_package(enact): what a plugin library (a stage of enact-rt's co-located tick) builds
# against, the target enact::plugin: enact's headers (include/enact: core/node/loop_component.h
# ...) and C++20. A plugin links no enact library: enact-rt, and enact replaying a recording,
# hold the functions it calls. Build it with the compiler and the enact that load it
# (docs/components.md, "Building it"; the example: share/enact/examples/plugins):
#   find_package(enact REQUIRED)
#   add_library(my_stage MODULE my_stage.cpp)
#   target_link_libraries(my_stage PRIVATE enact::plugin)
include(${CMAKE_CURRENT_LIST_DIR}/enactTargets.cmake)
