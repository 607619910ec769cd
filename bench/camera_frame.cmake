# Cameras (issue 11): a scenario's camera frame as the simulation captures it (default: the default scenario).
add_executable(hadal_bench_camera_frame ${CMAKE_CURRENT_LIST_DIR}/camera_frame.cc)
target_compile_options(hadal_bench_camera_frame PRIVATE ${HADAL_WARNINGS})
target_compile_definitions(hadal_bench_camera_frame PRIVATE HADAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_link_libraries(hadal_bench_camera_frame PRIVATE hadal_config hadal_sim hadal_raycast)
