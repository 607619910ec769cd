# Sonars (issue 16): forward-looking and multibeam pings over the 1M-triangle seabed on 1 and 2 workers.
add_executable(hadal_bench_sonar ${CMAKE_CURRENT_LIST_DIR}/sonar.cc)
target_compile_options(hadal_bench_sonar PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_sonar PRIVATE hadal_sensors hadal_render hadal_raycast)
