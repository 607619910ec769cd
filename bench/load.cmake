# Load (issue 15): one subscriber process of bench/load.py, which starts sixteen of them beside a realtime
# hadald and checks it holds real time and no reliable reader loses a sample.
add_executable(hadal_bench_load_subscriber ${CMAKE_CURRENT_LIST_DIR}/load_subscriber.cc)
target_compile_options(hadal_bench_load_subscriber PRIVATE ${HADAL_WARNINGS})
target_link_libraries(hadal_bench_load_subscriber PRIVATE hadal_record)
