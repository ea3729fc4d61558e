# Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#
# Small helpers so that every module's CMakeLists.txt reads the same way.

# efs_core_library(NAME SOURCES ... [DEPENDS targets...])
# A ROS-free core library with its public include/ folder.
function(efs_core_library name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_library(${name} ${A_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(${name} PUBLIC Eigen3::Eigen ${A_DEPENDS})
endfunction()

# efs_gtest(NAME SOURCES ... [DEPENDS targets...])
# A gtest binary; each TEST becomes one ctest test so scripts/test counts them individually.
# Tests find the shared data and their output folder through efs_common/testing/paths.h: the
# environment variables EFS_SHARED_DATA_DIR / EFS_TEST_OUTPUT_DIR override the defaults compiled in.
function(efs_gtest name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_link_libraries(${name} PRIVATE GTest::gtest GTest::gtest_main Threads::Threads ${A_DEPENDS})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/efs_tests)
  target_compile_definitions(${name} PRIVATE
    EFS_DEFAULT_SHARED_DATA_DIR="${EFS_SHARED_DATA_DIR}"
    EFS_DEFAULT_TEST_OUTPUT_DIR="${CMAKE_BINARY_DIR}/efs_test_output")
  gtest_discover_tests(${name} TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 60)
endfunction()

# efs_executable(NAME SOURCES ... [DEPENDS targets...])
# A command-line tool or benchmark. Under catkin it lands in devel/lib/explore_from_sketch so
# rosrun finds it; standalone it lands in bin/.
function(efs_executable name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_link_libraries(${name} PRIVATE Threads::Threads ${A_DEPENDS})
  if(NOT EFS_WITH_ROS)
    set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bin)
  endif()
endfunction()

# efs_ros_library(NAME SOURCES ... [DEPENDS targets...]) -- a module's ROS layer (ros/ folder).
function(efs_ros_library name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_library(${name} ${A_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/ros/include
                                            ${catkin_INCLUDE_DIRS})
  target_link_libraries(${name} PUBLIC ${catkin_LIBRARIES} ${A_DEPENDS})
  add_dependencies(${name} ${PROJECT_NAME}_generate_messages_cpp)
endfunction()

# efs_node(NAME SOURCES ... [DEPENDS targets...]) -- a ROS node executable.
function(efs_node name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_include_directories(${name} PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(${name} PRIVATE ${catkin_LIBRARIES} ${A_DEPENDS})
  add_dependencies(${name} ${PROJECT_NAME}_generate_messages_cpp)
endfunction()

# efs_rostest(FILE) -- a rostest .test file run as one ctest test with a private ROS master.
function(efs_rostest file)
  get_filename_component(stem ${file} NAME_WE)
  add_test(NAME rostest.${stem}
           COMMAND ${PROJECT_SOURCE_DIR}/scripts/lib/run_rostest ${CMAKE_CURRENT_SOURCE_DIR}/${file})
  set_tests_properties(rostest.${stem} PROPERTIES
    ENVIRONMENT "EFS_SHARED_DATA_DIR=${EFS_SHARED_DATA_DIR}" TIMEOUT 300 RUN_SERIAL TRUE)
endfunction()

# efs_bench(NAME SOURCES ... [DEPENDS targets...])
# A benchmark that prints a table (never asserts times). Sources live in the root bench/ folder;
# the module that owns the measured code registers it. scripts/bench runs them all.
function(efs_bench name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_link_libraries(${name} PRIVATE Threads::Threads ${A_DEPENDS})
  target_compile_definitions(${name} PRIVATE
    EFS_DEFAULT_SHARED_DATA_DIR="${EFS_SHARED_DATA_DIR}")
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
endfunction()

# efs_module_targets(MODULE DEPENDS ...)
# The usual shape of a module: the core library efs_<module> from src/*.cpp, one gtest binary
# <module>_test from test/*_test.cpp, and one executable per tools/*.cpp named after the file.
# The sets are globbed so that several people can add files to a module without editing this.
function(efs_module_targets module)
  cmake_parse_arguments(A "" "" "DEPENDS;TEST_DEPENDS" ${ARGN})
  file(GLOB core_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  efs_core_library(efs_${module} SOURCES ${core_sources} DEPENDS efs_common ${A_DEPENDS})
  file(GLOB test_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test/*_test.cpp)
  if(test_sources)
    efs_gtest(${module}_test SOURCES ${test_sources} DEPENDS efs_${module} ${A_TEST_DEPENDS})
  endif()
  file(GLOB tool_sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/tools/*.cpp)
  foreach(tool_source ${tool_sources})
    get_filename_component(tool ${tool_source} NAME_WE)
    efs_executable(${tool} SOURCES ${tool_source} DEPENDS efs_${module})
  endforeach()
endfunction()

# efs_expect_failure(NAME REGEX COMMAND ...)
# A ctest test that a tool refuses bad input cleanly: non-zero exit, no crash, a short message on
# stderr matching REGEX.
function(efs_expect_failure name regex)
  add_test(NAME ${name} COMMAND ${PROJECT_SOURCE_DIR}/scripts/lib/expect_failure "${regex}" ${ARGN})
endfunction()

# efs_rostest_gtest(NAME TEST_FILE SOURCES ... [DEPENDS ...])
# A gtest that talks to live nodes: built as a ROS executable (found by rostest as
# <test pkg="explore_from_sketch" type="NAME">) and run through rostest with TEST_FILE.
function(efs_rostest_gtest name test_file)
  cmake_parse_arguments(A "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_include_directories(${name} PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(${name} PRIVATE GTest::gtest ${catkin_LIBRARIES} Threads::Threads ${A_DEPENDS})
  add_dependencies(${name} ${PROJECT_NAME}_generate_messages_cpp)
  target_compile_definitions(${name} PRIVATE EFS_DEFAULT_SHARED_DATA_DIR="${EFS_SHARED_DATA_DIR}")
  efs_rostest(${test_file})
endfunction()
