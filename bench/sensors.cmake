# Sensors (issue 5): cost per sample of each sensor type and the share of a core the default AUV's
# sensors take at their rates.
add_executable(hadal_bench_sensors ${CMAKE_CURRENT_LIST_DIR}/sensors.cc)
target_compile_options(hadal_bench_sensors PRIVATE ${HADAL_WARNINGS})
target_compile_definitions(hadal_bench_sensors PRIVATE HADAL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_link_libraries(hadal_bench_sensors PRIVATE hadal_config hadal_sim)
