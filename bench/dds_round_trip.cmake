# The bare Fast DDS round trip (issue 45): a 1 KB sample to an echo process and back, hadald's participant set-up.
add_executable(hadal_bench_dds_round_trip ${CMAKE_CURRENT_LIST_DIR}/dds_round_trip.cc)
target_compile_options(hadal_bench_dds_round_trip PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_dds_round_trip PRIVATE hadal_dds)
