# The whole system, really started: a closed-loop flight through sim_explore.launch and a recorded
# bag replayed through replay.launch. Their inputs (a prior bundle, a recorded flight) are made by
# a fixture with the product's own tools.
set(EFS_MISSION_INPUTS ${CMAKE_CURRENT_BINARY_DIR}/mission_inputs)
add_test(NAME rostest.prepare_mission_inputs
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/prepare_mission_inputs.sh
                 ${CATKIN_DEVEL_PREFIX}/lib/${PROJECT_NAME} ${EFS_MISSION_INPUTS})
set_tests_properties(rostest.prepare_mission_inputs PROPERTIES
  FIXTURES_SETUP mission_inputs TIMEOUT 600)

foreach(stem sim_explore replay)
  add_executable(${stem}_rostest ros/${stem}_rostest.cpp)
  target_include_directories(${stem}_rostest PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(${stem}_rostest PRIVATE GTest::gtest ${catkin_LIBRARIES} Threads::Threads)
  add_dependencies(${stem}_rostest ${PROJECT_NAME}_generate_messages_cpp)
  add_test(NAME rostest.${stem}
           COMMAND ${PROJECT_SOURCE_DIR}/scripts/lib/run_rostest ${CMAKE_CURRENT_SOURCE_DIR}/${stem}.test)
  set_tests_properties(rostest.${stem} PROPERTIES
    ENVIRONMENT "EFS_MISSION_INPUTS=${EFS_MISSION_INPUTS}"
    FIXTURES_REQUIRED mission_inputs TIMEOUT 400 RUN_SERIAL TRUE)
endforeach()

# Whole explorations to the coverage goal: with the precise sketch, without one, through a LIO
# dropout, and with a sketch of another place. One test program; each .test says what to expect.
add_executable(mission_rostest ros/mission_rostest.cpp)
target_include_directories(mission_rostest PRIVATE ${catkin_INCLUDE_DIRS})
target_link_libraries(mission_rostest PRIVATE GTest::gtest ${catkin_LIBRARIES} Threads::Threads)
add_dependencies(mission_rostest ${PROJECT_NAME}_generate_messages_cpp)
foreach(case precise no_sketch lio_dropout wrong_sketch)
  add_test(NAME rostest.mission_${case}
           COMMAND ${PROJECT_SOURCE_DIR}/scripts/lib/run_rostest
                   ${CMAKE_CURRENT_SOURCE_DIR}/mission_${case}.test)
  set_tests_properties(rostest.mission_${case} PROPERTIES
    ENVIRONMENT "EFS_MISSION_INPUTS=${EFS_MISSION_INPUTS}"
    FIXTURES_REQUIRED mission_inputs TIMEOUT 480 RUN_SERIAL TRUE)
endforeach()
